"""Figures of the blur model (notebook 01): kernels, spectra, blind-estimation accuracy and the
detector's scores."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Patch
from scipy.stats import spearmanr

from ..blur import BLURRED_FROM_PX, SHARP_BELOW_PX, detection_rates
from .style import image_axis, styled


@styled
def plot_kernels(kernels: dict[str, np.ndarray]) -> plt.Figure:
    """Blur kernels (PSFs) side by side, each titled by its label.

    Parameters
    ----------
    kernels : dict
        ``{label: kernel}``, each (k, k), non-negative, summing to 1.

    Returns
    -------
    matplotlib.figure.Figure
    """
    figure, axes = plt.subplots(1, len(kernels), figsize=(2.0 * len(kernels), 2.2))
    for axis, (label, kernel) in zip(np.atleast_1d(axes), kernels.items(), strict=True):
        axis.imshow(kernel, cmap="magma", interpolation="nearest")
        axis.set_title(label)
        axis.axis("off")
    return figure


@styled
def plot_spectra(
    sharp: np.ndarray,
    blurred: np.ndarray,
    spectrum_sharp: np.ndarray,
    spectrum_blurred: np.ndarray,
    length_px: float,
    angle_deg: float,
) -> plt.Figure:
    """Sharp and blurred image and their log power spectra.

    The blurred spectrum's dark stripes (sinc zeros) run perpendicular to the motion, N / L
    bins apart; dashed lines mark the predicted zeros.

    Parameters
    ----------
    sharp, blurred : numpy.ndarray
        Gray images (N, N), float in [0, 1].
    spectrum_sharp, spectrum_blurred : numpy.ndarray
        Their centred log power spectra (N, N).
    length_px : float
        Blur length L, pixels.
    angle_deg : float
        Motion direction, degrees.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Eq. 1 of the paper (the blur model whose spectrum this is).
    """
    figure, axes = plt.subplots(1, 4, figsize=(11, 2.9))
    image_axis(axes[0], sharp, "sharp")
    image_axis(axes[1], blurred, f"blurred: L = {length_px:g} px, θ = {angle_deg:g}°")
    size = spectrum_blurred.shape[0]
    panels = ((axes[2], spectrum_sharp, "log power spectrum, sharp"),
              (axes[3], spectrum_blurred, "log power spectrum, blurred"))  # fmt: skip
    for axis, spectrum, title in panels:
        axis.imshow(spectrum, cmap="viridis", extent=(-size / 2, size / 2, -size / 2, size / 2))
        axis.set_title(title)
        axis.axis("off")
    theta = np.radians(angle_deg)
    direction, normal = (
        np.array([np.cos(theta), np.sin(theta)]),
        np.array([-np.sin(theta), np.cos(theta)]),
    )
    for k in range(1, int(length_px / 2) + 1):  # zeros at r = k N / L along the motion
        for sign in (-1, 1):
            centre = sign * k * size / length_px * direction
            ends = np.array([centre - normal * size, centre + normal * size])
            axes[3].plot(ends[:, 0], ends[:, 1], "w--", lw=0.6)
    axes[3].set_xlim(-size / 2, size / 2)
    axes[3].set_ylim(-size / 2, size / 2)
    return figure


@styled
def plot_estimation_accuracy(rows: list[dict], noise_for_length: float) -> plt.Figure:
    """Median (line) and interquartile range (band) of the blind angle and length errors,
    against the true length and against the noise, with the accuracy aims (1.5°, 1 px) dotted.

    Parameters
    ----------
    rows : list of dict
        Trials (:func:`blurloc.experiments.estimation.estimation_trials`): length_px,
        noise_sigma, angle_error_deg (degrees), length_error_px (pixels).
    noise_for_length : float
        The noise sigma of the trials shown against the length.

    Returns
    -------
    matplotlib.figure.Figure
    """
    figure, axes = plt.subplots(1, 2, figsize=(10, 3.6), layout="constrained")
    sweeps = (("length_px", "true blur length L (px)"),
              ("noise_sigma", "noise σ (images in [0, 1])"))  # fmt: skip
    errors = (("angle_error_deg", "#1f77b4", "angle error (°)"),
              ("length_error_px", "#d62728", "length error (px)"))  # fmt: skip
    for column, (key, label) in enumerate(sweeps):
        axis = axes[column]
        subset = [r for r in rows if key == "noise_sigma" or r["noise_sigma"] == noise_for_length]
        values = sorted({r[key] for r in subset})
        for error, colour, name in errors:
            stats = np.array([np.percentile([r[error] for r in subset if r[key] == v],
                                            [25, 50, 75]) for v in values])  # fmt: skip
            axis.plot(values, stats[:, 1], "o-", color=colour, label=f"median {name}")
            axis.fill_between(values, stats[:, 0], stats[:, 2], color=colour, alpha=0.15)
        axis.axhline(1.5, color="#1f77b4", ls=":", lw=1, label="target: 1.5°")
        axis.axhline(1.0, color="#d62728", ls=":", lw=1, label="target: 1 px")
        axis.set_xlabel(label)
        axis.set_yscale("symlog", linthresh=1.0)
        axis.set_ylim(0, None)
        axis.set_ylabel("error (symmetric log scale)")
        axis.set_title(f"against L (σ = {noise_for_length:g})" if column == 0
                       else "against noise (all L)")  # fmt: skip
    handles, labels = axes[0].get_legend_handles_labels()
    handles.append(Patch(color="#777777", alpha=0.15))
    labels.append("band: 25-75th percentile")
    figure.legend(handles, labels, loc="outside lower center", ncol=5, fontsize=7)
    return figure


@styled
def plot_detection(
    scores: dict[str, tuple[np.ndarray, np.ndarray]], threshold: float
) -> plt.Figure:
    """Histograms of the detector's score for sharp and blurred frames, with the threshold.

    Parameters
    ----------
    scores : dict
        ``{panel title: (scores (N,), labels (N,) bool, True = blurred)}``, one panel each.
    threshold : float
        The detector's threshold on the score (the coarse estimated blur length, px).

    Returns
    -------
    matplotlib.figure.Figure
    """
    figure, axes = plt.subplots(1, len(scores), figsize=(5 * len(scores), 3), sharex=True)
    for axis, (name, (values, labels)) in zip(np.atleast_1d(axes), scores.items(), strict=True):
        bins = np.linspace(min(values.min(), threshold) - 0.5, values.max() + 0.5, 40)
        sharp_label = f"sharp (render, or < {SHARP_BELOW_PX:g} px)"
        axis.hist(values[~labels], bins, alpha=0.6, color="#1f77b4", label=sharp_label)
        axis.hist(values[labels], bins, alpha=0.6, color="#d62728",
                  label=f"blurred (≥ {BLURRED_FROM_PX:g} px)")  # fmt: skip
        axis.axvline(threshold, color="k", lw=1.2, label=f"threshold {threshold:.2f}")
        hit, correct_sharp, _ = detection_rates(values, labels, threshold)
        axis.set_title(f"{name}: {hit:.0%} of blurred, {correct_sharp:.0%} of sharp right")
        axis.set_xlabel("blur score: estimated blur length (px)")
        axis.legend(fontsize=7)
    return figure


@styled
def plot_standin_estimation(rows: list[dict], angle_from_px: float = 4.0) -> plt.Figure:
    """Blind estimates of stand-in frames against their recorded blur: the estimated length
    (with the line estimate = recorded) and the angle error, each against the recorded extent.

    Parameters
    ----------
    rows : list of dict
        :func:`blurloc.experiments.blur_estimation.estimation_rows`; only the camera frames
        (kind ``color``) are drawn, the sharp renders are left out. Uses extent_px and
        estimated_length_px (pixels) and angle_error_deg (degrees).
    angle_from_px : float
        Extent (pixels) from which the angle is scored, marked by a dotted line.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Eq. 1-2 of the paper (the linear blur model whose length and angle are estimated).
    """
    frames = [r for r in rows if r["kind"] == "color"]
    extent = np.array([r["extent_px"] for r in frames])
    figure, axes = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    axes[0].scatter(extent, [r["estimated_length_px"] for r in frames], s=8, alpha=0.6)
    axes[0].plot([0, extent.max()], [0, extent.max()], "k--", lw=1, label="estimate = recorded")
    axes[0].set(xlabel="recorded extent (px, blur.csv)", ylabel="estimated length L (px)",
                title="Blur length")  # fmt: skip
    axes[1].scatter(extent, [r["angle_error_deg"] for r in frames], s=8, alpha=0.6)
    axes[1].axvline(angle_from_px, color="#888888", ls=":",
                    label=f"scored from {angle_from_px:g} px")  # fmt: skip
    axes[1].set(xlabel="recorded extent (px, blur.csv)", ylabel="angle error (°)",
                title="Blur direction")  # fmt: skip
    for axis in axes:
        axis.legend(fontsize=7)
    figure.suptitle(f"Blind estimation on {len(frames)} stand-in frames against the recorded blur")
    return figure


@styled
def plot_motion_agreement(
    measures: dict[str, np.ndarray], motion_px: np.ndarray, title: str
) -> plt.Figure:
    r"""Blur measures of frames against the camera's image motion during each, one panel per
    measure, with its Spearman rank correlation :math:`\rho` in the panel's title.

    Parameters
    ----------
    measures : dict of str to numpy.ndarray
        (N,) values per measure, larger for more blur
        (:func:`blurloc.experiments.real_frames.blur_measures`).
    motion_px : numpy.ndarray
        (N,) image motion of the same frames, px per frame interval.
    title : str
        Figure title: which frames, at what size.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Eq. 1 of the paper: the blur's length is the image's motion during the exposure.
    """
    figure, axes = plt.subplots(1, len(measures), figsize=(3.6 * len(measures), 3.4),
                                squeeze=False, layout="constrained")  # fmt: skip
    for axis, (name, values) in zip(axes[0], measures.items(), strict=True):
        rho = spearmanr(values, motion_px).statistic
        axis.scatter(motion_px, values, s=10, alpha=0.7)
        axis.set(xlabel="camera image motion (px per frame interval)", ylabel=name,
                 title=f"{name}: ρ = {rho:.2f}")  # fmt: skip
    figure.suptitle(title)
    return figure
