"""The interactive figures of notebooks 01-02: the static drawing, the sliders and their ranges,
a redraw on a slider change, and the refusal of a bad image."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
import skimage.data

from blurloc import plots
from blurloc.blur import to_gray


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def photo() -> np.ndarray:
    return to_gray(skimage.data.camera())[::4, ::4].astype(np.float64)  # 128x128


def _titles(figure: plt.Figure) -> list[str]:
    return [axis.get_title() for axis in figure.axes]


def test_static_blur_figure_shows_images_and_spectra(photo: np.ndarray) -> None:
    figure = plots.plot_blur_spectrum(photo, 12.0, 45.0, 0.01)
    titles = _titles(figure)
    assert len(titles) == 4
    assert titles[1] == "blurred: L = 12 px, θ = 45°"
    assert [t for t in titles if "log power spectrum" in t] == titles[2:]
    assert figure.axes[3].lines  # the predicted sinc zeros


def _scores_db(figure: plt.Figure) -> tuple[float, float]:
    """PSNR of the blurred and the restored panel, read from their titles."""
    blurred, restored = (float(t.split("\n")[1].removesuffix(" dB")) for t in _titles(figure)[:2])
    return blurred, restored


def test_static_wiener_figure_scores_the_restoration(photo: np.ndarray) -> None:
    figure = plots.plot_wiener_restoration(photo, 9.0, 30.0, 0.01, 1e-2)
    assert len(figure.axes) == 3 and _titles(figure)[2] == "sharp"
    blurred_db, restored_db = _scores_db(figure)
    assert restored_db > blurred_db + 1  # the true kernel and a fitting NSR: sharper
    too_small = _scores_db(plots.plot_wiener_restoration(photo, 9.0, 30.0, 0.01, 1e-5))
    assert too_small[0] == blurred_db and too_small[1] < restored_db - 5  # noise amplified


def test_blur_explorer_has_the_three_sliders_and_redraws(photo: np.ndarray) -> None:
    explorer = plots.blur_spectrum_explorer(photo, length_px=10.0)
    sliders = {name: (w.min, w.max, w.value) for name, w in explorer.sliders.items()}
    assert sliders == {"length_px": (1.0, 40.0, 10.0), "angle_deg": (0.0, 179.0, 30.0),
                       "noise_sigma": (0.0, 0.05, 0.005)}  # fmt: skip
    assert explorer.figure is None  # nothing drawn inside the widget until a slider moves
    explorer.sliders["angle_deg"].value = 100.0
    first = explorer.figure
    assert _titles(first)[1] == "blurred: L = 10 px, θ = 100°"
    explorer.sliders["length_px"].value = 20.0
    assert explorer.figure is not first
    assert _titles(explorer.figure)[1] == "blurred: L = 20 px, θ = 100°"


def test_wiener_explorer_has_a_logarithmic_nsr_slider_and_redraws(photo: np.ndarray) -> None:
    explorer = plots.wiener_explorer(photo)
    assert list(explorer.sliders) == ["length_px", "angle_deg", "noise_sigma", "nsr"]
    nsr = explorer.sliders["nsr"]
    assert type(nsr).__name__ == "FloatLogSlider" and (nsr.base, nsr.min, nsr.max) == (10, -5, 0)
    nsr.value = 1e-4
    first = _titles(explorer.figure)[1]
    nsr.value = 0.1
    assert _titles(explorer.figure)[1] != first
    assert "NSR = 0.1\n" in _titles(explorer.figure)[1]


@pytest.mark.parametrize(
    "image", [np.zeros((100, 100, 4)), np.zeros((32, 200)), np.zeros(100)], ids=str
)
def test_bad_images_are_refused_naming_the_shape(image: np.ndarray) -> None:
    for call in (plots.blur_spectrum_explorer, plots.wiener_explorer,
                 lambda x: plots.plot_blur_spectrum(x, 5, 0, 0)):  # fmt: skip
        with pytest.raises(ValueError, match=rf"shape \({image.shape[0]},"):
            call(image)
