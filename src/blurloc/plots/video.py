"""Figures of video deblurring (notebook 03): the recurrent network of eq. 8-11 (Fig. 4), training
curves, the blending weights and the ablations' intervals."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from .style import image_axis, styled


def _box(
    axis: plt.Axes,
    x: float,
    y: float,
    text: str,
    colour: str,
    width: float = 1.5,
    linestyle: str = "-",
) -> None:
    axis.add_patch(plt.Rectangle((x - width / 2, y - 0.32), width, 0.64, facecolor=colour,
                                 edgecolor="#333333", lw=0.8, ls=linestyle))  # fmt: skip
    axis.text(x, y, text, ha="center", va="center", fontsize=8)


def _arrow(
    axis: plt.Axes, start: tuple, end: tuple, text: str = "", at: tuple | None = None
) -> None:
    """An arrow from ``start`` to ``end``, its label at ``at`` (default: above the middle)."""
    axis.annotate("", end, start, arrowprops={"arrowstyle": "->", "lw": 0.9, "color": "#333333"})
    if text:
        x, y = at or ((start[0] + end[0]) / 2, (start[1] + end[1]) / 2 + 0.12)
        axis.text(x, y, text, fontsize=8, ha="center", va="bottom", color="#555555")


def largest_difference_window(
    reference: np.ndarray, image: np.ndarray, size: tuple[int, int]
) -> tuple[int, int, int, int]:
    r"""The window of an image where it differs most from a reference: the (height, width)
    window with the largest mean absolute difference (over channels too).

    .. math::

        (r, c) = \arg\max_{r, c} \sum_{i < h, j < w} \lVert I_{r+i, c+j} - R_{r+i, c+j} \rVert_1

    Parameters
    ----------
    reference, image : numpy.ndarray
        (H, W) or (H, W, C) images of the same shape (e.g. the sharp and the blurred frame).
    size : tuple of int
        (height, width) of the window, px; at most the image's.

    Returns
    -------
    tuple of int
        (top, left, height, width), px.

    Raises
    ------
    ValueError
        If the shapes differ or the window does not fit.
    """
    reference, image = np.asarray(reference, float), np.asarray(image, float)
    height, width = size
    if reference.shape != image.shape or not (0 < height <= image.shape[0]
                                              and 0 < width <= image.shape[1]):  # fmt: skip
        raise ValueError(f"images {reference.shape} and {image.shape} with window {size}: the "
                         "shapes must match and the window fit")  # fmt: skip
    difference = np.abs(image - reference)
    difference = difference.sum(axis=2) if difference.ndim == 3 else difference
    sums = np.pad(difference.cumsum(0).cumsum(1), ((1, 0), (1, 0)))  # summed-area table
    windows = (sums[height:, width:] - sums[:-height, width:] - sums[height:, :-width]
               + sums[:-height, :-width])  # fmt: skip
    top, left = np.unravel_index(int(np.argmax(windows)), windows.shape)
    return int(top), int(left), height, width


@styled
def plot_video_network(
    strip: dict[str, list[np.ndarray]] | None = None,
    windows: list[tuple[int, int, int, int]] | None = None,
) -> plt.Figure:
    r"""Fig. 4: one time step t of the recurrent deblurring network of eq. 8-11 as built in
    :mod:`blurloc.models.video_deblur`, with the recurrent inputs of step t - 1 (the hidden
    state :math:`h_{t-1}`, the auxiliary state :math:`\tilde h_{t-1}` and the blended features
    :math:`\tilde f_{t-1}`, dashed boxes), optionally above a test sequence, one row per method.

    With ``windows`` each frame of the strip is shown zoomed to its column's window, so that
    the rows' differences are visible, under a row of the first method's whole frames with the
    window outlined.

    Parameters
    ----------
    strip : dict, optional
        ``{row label: [frames]}``, RGB frames, the same count in every row.
    windows : list of tuple of int, optional
        One (top, left, height, width) window per column, px (e.g.
        :func:`largest_difference_window` of the blurred and the sharp frame).

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Fig. 4 and eq. 8-11 of the paper.
    """
    if strip and windows is not None:
        first_label, first_frames = next(iter(strip.items()))
        crops = {label: [frame[top : top + height, left : left + width]
                         for frame, (top, left, height, width) in zip(frames, windows,
                                                                     strict=True)]
                 for label, frames in strip.items()}  # fmt: skip
        strip = {f"{first_label}\n(whole frame)": first_frames,
                 **{f"{label}\n(zoom)": frames for label, frames in crops.items()}}  # fmt: skip
    rows = len(strip) if strip else 0
    columns = len(next(iter(strip.values()))) if strip else 1
    figure = plt.figure(figsize=(11, 3.9 + 1.9 * rows))
    grid = figure.add_gridspec(1 + rows, columns, height_ratios=[3.9] + [1.9] * rows)
    axis = figure.add_subplot(grid[0, :])
    axis.set_xlim(0, 14)
    axis.set_ylim(0, 4.9)
    axis.axis("off")
    previous = "#f7f7f7"
    _box(axis, 1.0, 2.2, "$B_t$\nblurred", "#eeeeee", 1.2)
    _box(axis, 3.0, 2.2, "encoder\n(stride 4)", "#dde8f5")
    _box(axis, 5.4, 3.3, "Recurrence (eq. 8)\n→ $f_t$, $h_t$", "#c6dbef", 2.1)
    _box(axis, 8.4, 3.3, "auxiliary recurrence\n(eq. 9) → " r"$\tilde h_t$", "#fdd0a2", 2.1)
    _box(axis, 8.4, 1.5, "blending (eq. 10)\n"
         r"$\tilde f_t = \tilde w_{t-1} \tilde f_{t-1} + w_t f_t$", "#c7e9c0", 2.7)  # fmt: skip
    _box(axis, 11.3, 2.2, "Rec (eq. 11)\npixel shuffle ×4", "#dadaeb", 1.9)
    _box(axis, 13.2, 2.2, "$L_t = B_t$ +\nresidual", "#eeeeee", 1.3)
    _box(axis, 5.4, 4.45, "$h_{t-1}$", previous, 1.1, "--")
    _box(axis, 8.4, 4.45, r"$\tilde h_{t-1}$", previous, 1.1, "--")
    _box(axis, 5.4, 1.5, r"$\tilde f_{t-1}$", previous, 1.1, "--")
    axis.text(3.0, 4.45, "from step $t-1$\n(dashed)", fontsize=7, ha="center", va="center",
              color="#555555")  # fmt: skip
    axis.text(12.2, 4.45, r"kept for step $t+1$: $h_t$, $\tilde h_t$, $\tilde f_t$", fontsize=7,
              ha="center", va="center", color="#555555")  # fmt: skip
    _arrow(axis, (1.6, 2.2), (2.25, 2.2))
    _arrow(axis, (3.75, 2.45), (4.35, 3.0), "features", at=(3.55, 2.8))
    _arrow(axis, (5.4, 4.13), (5.4, 3.62))
    _arrow(axis, (8.4, 4.13), (8.4, 3.62))
    _arrow(axis, (6.45, 3.3), (7.35, 3.3), "$h_t$")
    _arrow(axis, (5.95, 1.5), (7.05, 1.5))
    _arrow(axis, (6.1, 2.98), (7.4, 1.82), "$f_t$", at=(6.55, 2.15))
    _arrow(axis, (9.45, 3.3), (10.9, 2.52), r"$\tilde h_t$", at=(10.45, 2.95))
    _arrow(axis, (9.75, 1.5), (10.9, 1.88), r"$\tilde f_t$", at=(10.45, 1.35))
    _arrow(axis, (6.45, 3.05), (10.35, 2.3), "$f_t$, $h_t$", at=(9.75, 2.5))
    _arrow(axis, (12.25, 2.2), (12.55, 2.2))
    axis.plot([1.0, 1.0, 13.2], [1.88, 0.35, 0.35], color="#333333", lw=0.9)
    _arrow(axis, (13.2, 0.35), (13.2, 1.88))
    axis.text(7.1, 0.45, "full-resolution features of $B_t$ and the skip to the output",
              fontsize=7, ha="center", va="bottom", color="#555555")  # fmt: skip
    axis.set_title("Fig. 4 · Recurrent video deblurring, one time step "
                   "(this package's network, eq. 8-11)")  # fmt: skip
    for row, (label, frames) in enumerate((strip or {}).items()):
        for column, frame in enumerate(frames):
            panel = figure.add_subplot(grid[1 + row, column])
            panel.imshow(frame, interpolation="nearest")
            panel.set_xticks([])
            panel.set_yticks([])
            panel.grid(False)
            if column == 0:
                panel.set_ylabel(label, fontsize=8)
            if windows is not None and row == 0:
                top, left, height, width = windows[column]
                panel.add_patch(plt.Rectangle((left - 0.5, top - 0.5), width, height,
                                              fill=False, edgecolor="#ffd700", lw=1.2))  # fmt: skip
    return figure


@styled
def plot_training_curves(
    histories: dict[str, dict], reference_db: float | None = None
) -> plt.Figure:
    """Training loss and validation PSNR against the step, one line per model.

    Parameters
    ----------
    histories : dict
        ``{model: {"step": [...], "train_loss": [...], "val_psnr": [...] (dB)}}``.
    reference_db : float, optional
        PSNR of the blurred input, drawn as a dotted line.

    Returns
    -------
    matplotlib.figure.Figure
    """
    figure, axes = plt.subplots(1, 2, figsize=(10, 3.2))
    for name, history in histories.items():
        axes[0].plot(history["step"], history["train_loss"], "o-", label=name, ms=3)
        axes[1].plot(history["step"], history["val_psnr"], "o-", label=name, ms=3)
    if reference_db is not None:
        axes[1].axhline(reference_db, color="#555555", ls=":", label="blurred input")
    axes[0].set_xlabel("step")
    axes[0].set_ylabel("Charbonnier loss (training)")
    axes[1].set_xlabel("step")
    axes[1].set_ylabel("PSNR on validation frames (dB)")
    axes[1].legend(fontsize=7)
    return figure


@styled
def plot_attention(frame: np.ndarray, weights: np.ndarray, restored: np.ndarray) -> plt.Figure:
    """A blurred frame, the blending weight w_t of eq. 10 (the share of the current frame's
    features; the rest comes from the blended past) and the restored frame.

    Parameters
    ----------
    frame, restored : numpy.ndarray
        RGB frames (H, W, 3), uint8 or float [0, 1].
    weights : numpy.ndarray
        (h, w) in [0, 1].

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Eq. 10 of the paper.
    """
    figure, axes = plt.subplots(1, 3, figsize=(10, 3.0), layout="constrained")
    image_axis(axes[0], frame, "blurred $B_t$")
    shown = axes[1].imshow(weights, cmap="viridis", vmin=0, vmax=1)
    axes[1].set_title("$w_t$ (eq. 10): weight of\nthe current frame's features")
    axes[1].axis("off")
    figure.colorbar(shown, ax=axes[1], fraction=0.04)
    image_axis(axes[2], restored, "restored $L_t$")
    return figure


@styled
def plot_ablation_intervals(gains: dict[str, dict[int, float]], rows: list[dict]) -> plt.Figure:
    """The video network's ablations: each variant's gain over the blurred input per seed, and
    its paired difference to the full network with the confidence interval.

    Parameters
    ----------
    gains : dict
        Variant -> {seed: gain over the blurred input (dB)}.
    rows : list of dict
        Rows of :func:`blurloc.experiments.video_ablation.ablation_intervals` (``variant``,
        ``parameters``, ``gain_mean`` and, but for the reference, ``minus_reference``,
        ``ci_low``, ``ci_high``).

    Returns
    -------
    matplotlib.figure.Figure
        Left: one dot per seed and the mean (bar); right: the difference to the reference with
        its interval (green when wholly below zero: the removed part helps; red when above).

    References
    ----------
    Eq. 8-11 of the paper (the parts removed: recurrence, eq. 9, eq. 10).
    """
    names = [row["variant"] for row in rows]
    labels = [f"{row['variant']}\n({row['parameters'] / 1000:.0f} k)" for row in rows]
    figure, axes = plt.subplots(1, 2, figsize=(9, 1.2 + 0.5 * len(rows)), sharey=True,
                                layout="constrained")  # fmt: skip
    for y, row in enumerate(rows):
        values = list(gains[row["variant"]].values())
        axes[0].barh(y, row["gain_mean"], color="#9bc", height=0.6)
        axes[0].plot(values, [y] * len(values), "o", color="#235", ms=4)
        if "minus_reference" in row:
            low, high, mean = row["ci_low"], row["ci_high"], row["minus_reference"]
            colour = "#2a7" if high < 0 else "#c33" if low > 0 else "#555"
            axes[1].errorbar(mean, y, xerr=[[mean - low], [high - mean]], fmt="o",
                             color=colour, capsize=3)  # fmt: skip
    axes[0].axvline(0, color="black", linewidth=0.8)
    axes[0].set_xlabel("PSNR gain over the blurred input (dB)")
    axes[0].set_yticks(range(len(names)), labels)
    axes[0].invert_yaxis()
    axes[1].axvline(0, color="black", linewidth=0.8)
    axes[1].set_xlabel(f"minus {rows[0]['variant']} (dB, 95 % t-interval)")
    return figure
