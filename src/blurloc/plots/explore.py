"""Interactive figures of notebooks 01 and 02: sliders for the blur (eq. 1-2) and the Wiener
filter (eq. 4) that redraw the figure, and the same figure drawn once for given values.

The sliders are ipywidgets, imported only when an explorer is built, so the rest of the
package runs without them. In JupyterLab a slider change redraws the figure; run headless
(papermill), the widget is stored in the notebook and the static figure is what a reader sees.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt
import numpy as np

from ..blur import blur_image, log_power_spectrum, motion_kernel
from ..deconv import wiener_deconvolve
from ..images import as_float_image
from ..metrics import psnr
from .blur import plot_spectra
from .style import image_axis, styled

if TYPE_CHECKING:
    import ipywidgets

#: Smallest image side (px) the explorers accept: the longest kernel of the length slider
#: (MAX_LENGTH_PX, 43 px wide) must fit in the image.
MIN_SIDE_PX = 64
#: Range of the length slider, pixels.
MIN_LENGTH_PX, MAX_LENGTH_PX = 1.0, 40.0
#: Range of the noise slider (σ of eq. 1's η, [0, 1] intensity scale).
MAX_NOISE_SIGMA = 0.05
#: Range of the NSR slider, powers of ten.
NSR_EXPONENTS = (-5.0, 0.0)


def _checked(image: np.ndarray) -> np.ndarray:
    """The image as float64 in [0, 1], or a ValueError naming its shape."""
    image = as_float_image(image)
    if min(image.shape[:2]) < MIN_SIDE_PX:
        raise ValueError(
            f"image must be at least {MIN_SIDE_PX}x{MIN_SIDE_PX} px, got shape {image.shape}"
        )
    return image


def _blurred(
    image: np.ndarray, length_px: float, angle_deg: float, noise_sigma: float, seed: int
) -> tuple[np.ndarray, np.ndarray]:
    """The linear kernel and eq. 1 with it, noise drawn from ``seed`` (the same values give the
    same image)."""
    kernel = motion_kernel(length_px, angle_deg)
    return kernel, blur_image(image, kernel, noise_sigma, rng=np.random.default_rng(seed))


def plot_blur_spectrum(
    image: np.ndarray, length_px: float, angle_deg: float, noise_sigma: float, seed: int = 0
) -> plt.Figure:
    """Blur an image by a linear kernel plus noise and draw it beside the log power spectra.

    Parameters
    ----------
    image : numpy.ndarray
        Sharp image x, (H, W) or (H, W, 3), uint8 or float in [0, 1], both sides at least
        ``MIN_SIDE_PX``.
    length_px : float
        Blur length L, pixels (> 0).
    angle_deg : float
        Motion direction θ, degrees counter-clockwise from the horizontal.
    noise_sigma : float
        Standard deviation of the Gaussian noise η, [0, 1] intensity scale.
    seed : int
        Seed of the noise.

    Returns
    -------
    matplotlib.figure.Figure
        Four panels (:func:`~blurloc.plots.plot_spectra`): sharp, blurred, and the log power
        spectra of both, with the predicted sinc zeros dashed on the blurred one.

    Raises
    ------
    ValueError
        If the image is not an image or is smaller than ``MIN_SIDE_PX``; the message names the
        shape.

    References
    ----------
    Eq. 1 (b = c * x + η) and eq. 2 (its Fourier form, whose zeros are the stripes) of the
    paper.
    """
    sharp = _checked(image)
    _, blurred = _blurred(sharp, length_px, angle_deg, noise_sigma, seed)
    return plot_spectra(sharp, np.clip(blurred, 0, 1), log_power_spectrum(sharp),
                        log_power_spectrum(blurred), length_px, angle_deg)  # fmt: skip


@styled
def plot_wiener_restoration(
    image: np.ndarray,
    length_px: float,
    angle_deg: float,
    noise_sigma: float,
    nsr: float,
    seed: int = 0,
) -> plt.Figure:
    """Blur an image by a linear kernel plus noise, restore it with the Wiener filter given the
    true kernel, and draw blurred, restored and sharp with their PSNR against the sharp image.

    Parameters
    ----------
    image : numpy.ndarray
        Sharp image, (H, W) or (H, W, 3), uint8 or float in [0, 1], both sides at least
        ``MIN_SIDE_PX``.
    length_px : float
        Blur length L, pixels (> 0).
    angle_deg : float
        Motion direction θ, degrees counter-clockwise from the horizontal.
    noise_sigma : float
        Standard deviation of the Gaussian noise, [0, 1] intensity scale.
    nsr : float
        Constant noise-to-signal ratio 1/SNR of the Wiener filter (> 0).
    seed : int
        Seed of the noise.

    Returns
    -------
    matplotlib.figure.Figure
        Three panels: blurred, Wiener-restored (each titled with its PSNR in dB over the whole
        image, data range 1) and sharp.

    Raises
    ------
    ValueError
        If the image is not an image or is smaller than ``MIN_SIDE_PX`` (the message names the
        shape), or if ``nsr`` is not > 0.

    References
    ----------
    Eq. 1 (the blur), eq. 4 (the Wiener filter) and eq. 5-6 (PSNR) of the paper.
    """
    sharp = _checked(image)
    kernel, blurred = _blurred(sharp, length_px, angle_deg, noise_sigma, seed)
    restored = np.clip(wiener_deconvolve(blurred, kernel, nsr), 0, 1)
    blurred = np.clip(blurred, 0, 1)
    figure, axes = plt.subplots(1, 3, figsize=(10, 3.4))
    setting = f"L = {length_px:g} px, θ = {angle_deg:g}°, σ = {noise_sigma:g}"
    image_axis(axes[0], blurred, f"blurred ({setting})\n{psnr(sharp, blurred, 1.0):.2f} dB")
    image_axis(axes[1], restored,
               f"Wiener (eq. 4), NSR = {nsr:.2g}\n{psnr(sharp, restored, 1.0):.2f} dB")  # fmt: skip
    image_axis(axes[2], sharp, "sharp")
    return figure


@dataclass
class SliderExplorer:
    """Sliders above an output area that redraws a figure when a slider is released.

    Nothing is drawn until a slider moves: the notebook draws the figure at the starting values
    once, statically, so that a copy without a running kernel shows it (and a headless run
    stores no figure inside a widget, where papermill would wait on it).

    Attributes
    ----------
    sliders : dict
        ``{keyword of the drawing function: slider}``.
    output : ipywidgets.Output
        Where the figure is drawn.
    figure : matplotlib.figure.Figure or None
        The figure last drawn (None before any slider moved).
    """

    sliders: dict
    output: ipywidgets.Output
    figure: plt.Figure | None = None

    def _ipython_display_(self) -> None:
        """Show the sliders and the output area in a notebook."""
        import ipywidgets
        from IPython.display import display

        display(ipywidgets.VBox([*self.sliders.values(), self.output]))


def _explorer(
    draw: Callable[..., plt.Figure], image: np.ndarray, seed: int, sliders: dict
) -> SliderExplorer:
    """A :class:`SliderExplorer` that calls ``draw(image, **slider values, seed=seed)`` when a
    slider changes and shows the figure in its output area (any matplotlib backend)."""
    import ipywidgets
    from IPython.display import display

    image = _checked(image)
    explorer = SliderExplorer(sliders, ipywidgets.Output())

    def redraw(_change: dict) -> None:
        figure = draw(image, **{k: w.value for k, w in sliders.items()}, seed=seed)
        plt.close(figure)  # shown once, in the output area, not again by the inline backend
        explorer.figure = figure
        explorer.output.clear_output(wait=True)
        with explorer.output:
            display(figure)

    for slider in sliders.values():
        slider.observe(redraw, names="value")
    return explorer


def _blur_sliders(length_px: float, angle_deg: float, noise_sigma: float) -> dict:
    """The length, angle and noise sliders, set to the given values."""
    import ipywidgets

    style = {"description_width": "initial"}
    return {
        "length_px": ipywidgets.FloatSlider(
            value=length_px, min=MIN_LENGTH_PX, max=MAX_LENGTH_PX, step=0.5,
            description="blur length L (px)", continuous_update=False, style=style),
        "angle_deg": ipywidgets.FloatSlider(
            value=angle_deg, min=0.0, max=179.0, step=1.0,
            description="angle θ (°)", continuous_update=False, style=style),
        "noise_sigma": ipywidgets.FloatSlider(
            value=noise_sigma, min=0.0, max=MAX_NOISE_SIGMA, step=0.001, readout_format=".3f",
            description="noise σ", continuous_update=False, style=style),
    }  # fmt: skip


def blur_spectrum_explorer(
    image: np.ndarray,
    length_px: float = 16.0,
    angle_deg: float = 30.0,
    noise_sigma: float = 0.005,
    seed: int = 0,
) -> SliderExplorer:
    """Sliders for blur length, angle and noise that redraw :func:`plot_blur_spectrum`.

    Parameters
    ----------
    image : numpy.ndarray
        Sharp image, (H, W) or (H, W, 3), uint8 or float in [0, 1], both sides at least
        ``MIN_SIDE_PX``.
    length_px : float
        Starting blur length L, pixels (slider 1-40 px).
    angle_deg : float
        Starting motion direction θ, degrees (slider 0-179°).
    noise_sigma : float
        Starting noise σ, [0, 1] intensity scale (slider 0-0.05).
    seed : int
        Seed of the noise (fixed: the same slider values draw the same figure).

    Returns
    -------
    SliderExplorer
        The sliders and an output area; ``display`` it in a notebook. Its ``figure`` is the
        figure last drawn.

    Raises
    ------
    ValueError
        If the image is not an image or is too small; the message names the shape.

    References
    ----------
    Eq. 1-2 of the paper: the blur model and its Fourier form, whose sinc zeros the spectrum
    shows.
    """
    sliders = _blur_sliders(length_px, angle_deg, noise_sigma)
    return _explorer(plot_blur_spectrum, image, seed, sliders)


def wiener_explorer(
    image: np.ndarray,
    length_px: float = 15.0,
    angle_deg: float = 30.0,
    noise_sigma: float = 0.01,
    nsr: float = 1e-2,
    seed: int = 0,
) -> SliderExplorer:
    """Sliders for blur length, angle, noise and NSR that redraw
    :func:`plot_wiener_restoration`.

    Parameters
    ----------
    image : numpy.ndarray
        Sharp image, (H, W) or (H, W, 3), uint8 or float in [0, 1], both sides at least
        ``MIN_SIDE_PX``.
    length_px : float
        Starting blur length L, pixels (slider 1-40 px).
    angle_deg : float
        Starting motion direction θ, degrees (slider 0-179°).
    noise_sigma : float
        Starting noise σ, [0, 1] intensity scale (slider 0-0.05).
    nsr : float
        Starting NSR = 1/SNR of eq. 4 (logarithmic slider, 1e-5 to 1).
    seed : int
        Seed of the noise (fixed: the same slider values draw the same figure).

    Returns
    -------
    SliderExplorer
        The sliders and an output area; ``display`` it in a notebook. Its ``figure`` is the
        figure last drawn.

    Raises
    ------
    ValueError
        If the image is not an image or is too small; the message names the shape.

    References
    ----------
    Eq. 1 (the blur), eq. 4 (the Wiener filter) and eq. 5-6 (PSNR) of the paper.
    """
    import ipywidgets

    sliders = _blur_sliders(length_px, angle_deg, noise_sigma)
    sliders["nsr"] = ipywidgets.FloatLogSlider(
        value=nsr, base=10, min=NSR_EXPONENTS[0], max=NSR_EXPONENTS[1], step=0.1,
        description="NSR = 1/SNR", readout_format=".1e", continuous_update=False,
        style={"description_width": "initial"})  # fmt: skip
    return _explorer(plot_wiener_restoration, image, seed, sliders)
