"""Figures of single-image deblurring (notebook 02): inverse filter against Wiener, the NSR
curve, the boundaries, the deblurring process of Fig. 3 and the oracle runs."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from .style import image_axis, styled


@styled
def plot_deblurring_process(rows: list[dict]) -> plt.Figure:
    """Fig. 3, the image deblurring process, one row per example: the blurred image, its log
    spectrum with the estimated motion direction, the estimated PSF, the restored image and the
    sharp truth.

    Parameters
    ----------
    rows : list of dict
        Each with ``blurred``, ``restored``, ``sharp`` (images, float [0, 1] or uint8),
        ``spectrum`` (N, N), ``angle_deg`` (degrees), ``kernel`` (k, k), ``length_px`` (pixels)
        and ``title``.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Fig. 3 and eq. 4 of the paper.
    """
    figure, axes = plt.subplots(len(rows), 5, figsize=(13, 2.7 * len(rows)), squeeze=False)
    for row, item in zip(axes, rows, strict=True):
        image_axis(row[0], item["blurred"], f"{item['title']}: blurred")
        size = item["spectrum"].shape[0]
        row[1].imshow(item["spectrum"], cmap="viridis",
                      extent=(-size / 2, size / 2, -size / 2, size / 2))  # fmt: skip
        theta = np.radians(item["angle_deg"])
        ends = np.array([-1, 1]) * size / 2
        row[1].plot(ends * np.cos(theta), ends * np.sin(theta), "w-", lw=0.8)
        row[1].set_title(f"spectrum, motion at {item['angle_deg']:.1f}°")
        row[1].axis("off")
        row[2].imshow(item["kernel"], cmap="magma", interpolation="nearest")
        row[2].set_title(f"estimated PSF, L = {item['length_px']:.1f} px")
        row[2].axis("off")
        image_axis(row[3], item["restored"], "restored (Wiener)")
        image_axis(row[4], item["sharp"], "sharp (truth)")
    figure.suptitle("Fig. 3 · The image deblurring process (this package)")
    return figure


@styled
def plot_restorations(rows: list[dict], title: str) -> plt.Figure:
    """Restorations side by side, one row per noise level, each panel titled by its method and
    PSNR.

    Parameters
    ----------
    rows : list of dict
        Each with ``method``, ``image`` (H, W) float (shown clipped to [0, 1]), ``psnr_db`` (dB)
        and optionally ``noise_sigma`` (images in [0, 1]); rows of one noise level in order
        (:func:`blurloc.experiments.deblurring.filter_comparison` or
        :func:`~blurloc.experiments.deblurring.boundary_comparison`).
    title : str
        Figure title: what is shown and where the PSNR is measured.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Eq. 3 (inverse filter), eq. 4 (Wiener) and eq. 5-6 (PSNR) of the paper.
    """
    levels = list(dict.fromkeys(r.get("noise_sigma") for r in rows))
    columns = max(sum(r.get("noise_sigma") == level for r in rows) for level in levels)
    figure, axes = plt.subplots(len(levels), columns, figsize=(3.2 * columns, 3.3 * len(levels)),
                                squeeze=False, layout="constrained")  # fmt: skip
    for axis_row, level in zip(axes, levels, strict=True):
        subset = [r for r in rows if r.get("noise_sigma") == level]
        for axis, row in zip(axis_row, subset, strict=False):
            noise = "" if level is None else f"σ = {level:g}: "
            image_axis(axis, row["image"], f"{row['method']}\n{noise}{row['psnr_db']:.1f} dB")
    figure.suptitle(title)
    return figure


@styled
def plot_nsr_curve(curve: dict, title: str) -> plt.Figure:
    """PSNR of the Wiener restoration against the NSR (log scale), with the estimated NSR and
    the blurred input's PSNR as reference lines.

    Parameters
    ----------
    curve : dict
        :func:`blurloc.experiments.deblurring.nsr_curve`: ``nsr`` (M,), ``psnr_db`` (M,) dB,
        ``estimated_nsr`` and ``blurred_psnr_db`` (dB).
    title : str
        What was restored (image, kernel, noise).

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Eq. 4 (Wiener) and eq. 5-6 (PSNR) of the paper.
    """
    figure, axis = plt.subplots(figsize=(5.5, 3.2), layout="constrained")
    axis.semilogx(curve["nsr"], curve["psnr_db"], "o-", label="Wiener (eq. 4)")
    axis.axvline(curve["estimated_nsr"], color="k", ls="--",
                 label=f"estimated NSR {curve['estimated_nsr']:.3g}")  # fmt: skip
    axis.axhline(curve["blurred_psnr_db"], color="#555555", ls=":", label="blurred input")
    axis.set_xlabel("NSR = 1/SNR (constant, log scale)")
    axis.set_ylabel("PSNR (dB)")
    axis.set_title(title)
    axis.legend(fontsize=7)
    return figure


@styled
def plot_oracle_gains(
    summary: list[dict], points: dict[str, tuple[np.ndarray, np.ndarray]]
) -> plt.Figure:
    """Mean PSNR change of each oracle variant against the blurred input (bars, 95 % interval),
    and the per-frame change against the recorded blur extent.

    Parameters
    ----------
    summary : list of dict
        :func:`blurloc.experiments.wiener_oracles.oracle_summary`: variant, gain_db and
        gain_ci95_db (dB), frames.
    points : dict
        ``{variant: (extent_px (N,) pixels, gain_db (N,) dB)}``
        (:func:`blurloc.experiments.wiener_oracles.frame_gains`), one scatter each.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Eq. 4 (Wiener) and eq. 5-6 (PSNR) of the paper.
    """
    figure, axes = plt.subplots(1, 2, figsize=(11, 3.9), layout="constrained")
    axes[0].barh([r["variant"] for r in summary], [r["gain_db"] for r in summary],
                 xerr=[r["gain_ci95_db"] for r in summary], color="#4c72b0")  # fmt: skip
    axes[0].axvline(0, color="k", lw=1)
    axes[0].set(xlabel="mean PSNR change vs blurred input (dB)", ylabel="Wiener variant",
                title="Mean change per variant (95 % interval)")  # fmt: skip
    for variant, (extent, gain) in points.items():
        axes[1].scatter(extent, gain, s=10, alpha=0.7, label=variant)
    axes[1].axhline(0, color="k", lw=1)
    axes[1].set(xlabel="recorded blur extent (px, blur.csv)", ylabel="PSNR change (dB)",
                title="Change per frame against blur extent")  # fmt: skip
    axes[1].legend(fontsize=7)
    figure.suptitle(f"Wiener with ingredients replaced by the truth, "
                    f"{summary[0]['frames']} stand-in frames")  # fmt: skip
    return figure


@styled
def plot_skimage_comparison(rows: list[dict]) -> plt.Figure:
    """This package's Wiener minus scikit-image's best-balance ``wiener`` per trial, against how
    close the blurred image already is to the truth: with the NSR rule and with the best
    constant NSR of each trial, against scikit-image as it is (periodic DFT) and against
    scikit-image given the same mirror padding (then only the regulariser differs).

    Parameters
    ----------
    rows : list of dict
        :func:`blurloc.experiments.wiener_oracles.skimage_comparison` with ``oracle_nsr``:
        kernel, noise_sigma, blurred_db, ours_db, best_nsr_db, skimage_best_balance_db,
        skimage_padded_db (dB).

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Eq. 4 (Wiener) and eq. 6 (PSNR) of the paper.
    """
    kinds = list(dict.fromkeys(r["kernel"] for r in rows))
    figure, axes = plt.subplots(1, len(kinds), figsize=(5.2 * len(kinds), 4.2), sharex=True,
                                sharey=True, squeeze=False, layout="constrained")  # fmt: skip
    series = (
        ("ours_db", "skimage_best_balance_db", "NSR rule vs scikit-image",
         {"color": "#4c72b0"}),
        ("best_nsr_db", "skimage_best_balance_db", "best constant NSR (oracle) vs scikit-image",
         {"facecolors": "none", "edgecolors": "#dd8452"}),
        ("ours_db", "skimage_padded_db", "NSR rule vs scikit-image, mirror-padded",
         {"color": "#55a868", "marker": "x"}),
    )  # fmt: skip
    for axis, kind in zip(axes[0], kinds, strict=True):
        trials = [r for r in rows if r["kernel"] == kind]
        blurred = np.array([r["blurred_db"] for r in trials])
        for ours, theirs, label, style in series:
            gain = np.array([r[ours] - r[theirs] for r in trials])
            axis.scatter(blurred, gain, s=22, label=label, **style)
        axis.axhline(0, color="k", lw=1)
        axis.axhline(1, color="gray", lw=1, ls="--", label="+1 dB")
        axis.set(xlabel="PSNR of the blurred image (dB)", title=f"{kind} kernels")
        axis.legend(fontsize=7)
    axes[0, 0].set_ylabel("Wiener (eq. 4) minus scikit-image's wiener (dB)")
    sigmas = sorted({r["noise_sigma"] for r in rows})
    figure.suptitle("This package's Wiener against scikit-image's at its best balance, true "
                    f"kernels, noise σ = {', '.join(f'{s:g}' for s in sigmas)}")  # fmt: skip
    return figure
