"""Figures of video deblurring (notebook 03): the recurrent network of eq. 8-11 (Fig. 4), training
curves and the blending weights."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from .style import image_axis, styled


def _box(axis: plt.Axes, x: float, y: float, text: str, colour: str, width: float = 1.5) -> None:
    axis.add_patch(plt.Rectangle((x - width / 2, y - 0.32), width, 0.64, facecolor=colour,
                                 edgecolor="#333333", lw=0.8))  # fmt: skip
    axis.text(x, y, text, ha="center", va="center", fontsize=8)


def _arrow(axis: plt.Axes, start: tuple, end: tuple, text: str = "") -> None:
    axis.annotate("", end, start, arrowprops={"arrowstyle": "->", "lw": 0.9, "color": "#333333"})
    if text:
        axis.text((start[0] + end[0]) / 2, (start[1] + end[1]) / 2 + 0.12, text, fontsize=7,
                  ha="center", color="#555555")  # fmt: skip


@styled
def plot_video_network(strip: dict[str, list[np.ndarray]] | None = None) -> plt.Figure:
    """Fig. 4: the recurrent deblurring network of eq. 8-11 as built in
    :mod:`blurloc.models.video_deblur`, optionally above a test sequence, one row per method.

    Parameters
    ----------
    strip : dict, optional
        ``{row label: [frames]}``, RGB frames, the same count in every row.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Fig. 4 and eq. 8-11 of the paper.
    """
    rows = len(strip) if strip else 0
    columns = len(next(iter(strip.values()))) if strip else 1
    figure = plt.figure(figsize=(11, 3.4 + 1.9 * rows))
    grid = figure.add_gridspec(1 + rows, columns, height_ratios=[3.4] + [1.9] * rows)
    axis = figure.add_subplot(grid[0, :])
    axis.set_xlim(0, 14)
    axis.set_ylim(0, 4.2)
    axis.axis("off")
    _box(axis, 1.0, 2.1, "B_t\nblurred", "#eeeeee", 1.2)
    _box(axis, 3.0, 2.1, "encoder\n(stride 4)", "#dde8f5")
    _box(axis, 5.3, 3.2, "Recurrence (eq. 8)\n→ f_t, h_t", "#c6dbef", 2.1)
    _box(axis, 5.3, 1.0, "h_{t-1}", "#f0f0f0", 1.1)
    _box(axis, 8.0, 3.2, "Recurrence~ (eq. 9)\n→ h~_t", "#fdd0a2", 2.1)
    _box(axis, 8.0, 1.0, "blending (eq. 10)\nf~_t = w~f~_{t-1} + w f_t", "#c7e9c0", 2.6)
    _box(axis, 10.9, 2.1, "Rec (eq. 11)\npixel shuffle ×4", "#dadaeb", 1.9)
    _box(axis, 13.1, 2.1, "L_t = B_t +\nresidual", "#eeeeee", 1.5)
    _arrow(axis, (1.6, 2.1), (2.25, 2.1))
    _arrow(axis, (3.75, 2.3), (4.25, 3.0), "features")
    _arrow(axis, (5.3, 1.32), (5.3, 2.88), "h_{t-1}")
    _arrow(axis, (6.35, 3.2), (6.95, 3.2), "h_t")
    _arrow(axis, (6.0, 2.88), (7.2, 1.32), "f_t")
    _arrow(axis, (9.05, 3.2), (10.2, 2.4), "h~_t")
    _arrow(axis, (9.3, 1.0), (10.2, 1.8), "f~_t")
    _arrow(axis, (6.35, 3.0), (10.0, 2.1), "f_t, h_t")
    _arrow(axis, (11.85, 2.1), (12.35, 2.1))
    _arrow(axis, (1.0, 1.78), (12.6, 1.78), "")
    axis.text(6.8, 1.6, "full-resolution features of B_t and the skip to the output", fontsize=7,
              ha="center", color="#555555")  # fmt: skip
    axis.set_title("Fig. 4 · Recurrent video deblurring (this package's network, eq. 8-11)")
    for row, (label, frames) in enumerate((strip or {}).items()):
        for column, frame in enumerate(frames):
            panel = figure.add_subplot(grid[1 + row, column])
            panel.imshow(frame)
            panel.set_xticks([])
            panel.set_yticks([])
            panel.grid(False)
            if column == 0:
                panel.set_ylabel(label, fontsize=8)
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
