"""Figures and tables, one function per figure, in one consistent style; saved as PNG + PDF."""

from __future__ import annotations

import csv
import itertools
import os
from collections.abc import Sequence
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import ConnectionPatch

from .data.sevenscenes import SPLIT_FILES, list_scenes, load_split, read_image
from .data.synth import path_lengths

SPLIT_COLOURS = {"train": "#1f77b4", "test": "#d62728"}
STYLE = {
    "figure.dpi": 110,
    "savefig.dpi": 150,
    "savefig.bbox": "tight",
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "legend.frameon": False,
}
plt.rcParams.update(STYLE)


def save_figure(figure: plt.Figure, folder: str | os.PathLike, name: str) -> list[Path]:
    """Save ``figure`` as ``<folder>/<name>.png`` and ``.pdf``; returns both paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = [folder / f"{name}.png", folder / f"{name}.pdf"]
    for path in paths:
        figure.savefig(path, metadata={"CreationDate": None} if path.suffix == ".pdf" else None)
    return paths


def save_table(
    rows: list[dict],
    folder: str | os.PathLike,
    name: str,
    columns: Sequence[str] | None = None,
    caption: str = "",
) -> list[Path]:
    """Save rows as ``<folder>/<name>.md`` (Markdown) and ``.csv``; returns both paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    columns = list(columns or rows[0].keys())
    csv_path, md_path = folder / f"{name}.csv", folder / f"{name}.md"
    with open(csv_path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    lines = [caption, ""] if caption else []
    lines.append("| " + " | ".join(columns) + " |")
    lines.append("|" + "|".join("---" for _ in columns) + "|")
    lines += ["| " + " | ".join(str(row.get(c, "")) for c in columns) + " |" for row in rows]
    md_path.write_text("\n".join(lines) + "\n")
    return [md_path, csv_path]


def plot_scene_gallery(root: str | os.PathLike, kind: str = "sharp") -> plt.Figure:
    """The first test frame of every scene (``kind``: ``sharp`` or ``color``)."""
    scenes = list_scenes(root)
    columns = 4
    rows = -(-len(scenes) // columns)
    figure, axes = plt.subplots(rows, columns, figsize=(2.4 * columns, 1.95 * rows))
    for axis in np.ravel(axes):
        axis.axis("off")
    for axis, scene in zip(np.ravel(axes), scenes, strict=False):
        sequence = load_split(root, scene, "test")[0]
        axis.imshow(read_image(sequence.path(sequence.frame_ids[0], kind)))
        axis.set_title(scene)
    figure.suptitle("The seven stand-in scenes (first test frame, sharp render)")
    return figure


def plot_exposure(
    sub_frames: Sequence[np.ndarray],
    blurred: np.ndarray,
    tracks: np.ndarray,
    times_ms: Sequence[float],
) -> plt.Figure:
    """How a blurred frame is made: sharp renders over the exposure, their average, and the
    image paths of scene points over the exposure (they differ from point to point)."""
    count = len(sub_frames)
    figure, axes = plt.subplots(1, count + 2, figsize=(2.3 * (count + 2), 2.3))
    for axis, frame, time in zip(axes[:count], sub_frames, times_ms, strict=True):
        axis.imshow(frame)
        axis.set_title(f"sharp at {time:+.0f} ms")
        axis.axis("off")
    axes[count].imshow(blurred)
    axes[count].set_title("average in linear light")
    axes[count].axis("off")
    axis = axes[count + 1]
    axis.imshow(np.full_like(blurred, 255))
    length = path_lengths(tracks)
    colours = plt.cm.viridis(length / max(length.max(), 1e-9))
    for point in range(tracks.shape[1]):
        axis.plot(tracks[:, point, 0], tracks[:, point, 1], color=colours[point], lw=1.2)
    axis.set_xlim(0, blurred.shape[1])
    axis.set_ylim(blurred.shape[0], 0)
    axis.set_title(f"point paths: {length.min():.1f}-{length.max():.1f} px")
    axis.axis("off")
    return figure


def plot_trajectories(root: str | os.PathLike) -> plt.Figure:
    """Camera positions of every sequence in 3-D, one panel per scene, coloured by split."""
    scenes = list_scenes(root)
    columns = 4
    rows = -(-len(scenes) // columns)
    figure = plt.figure(figsize=(3.0 * columns, 2.8 * rows))
    for index, scene in enumerate(scenes):
        axis = figure.add_subplot(rows, columns, index + 1, projection="3d")
        for split in SPLIT_FILES:
            for number, sequence in enumerate(load_split(root, scene, split)):
                xyz = sequence.poses()[:, :3, 3]
                label = split if number == 0 else None
                axis.plot(*xyz.T, color=SPLIT_COLOURS[split], lw=1.0, label=label)
                axis.scatter(*xyz[0], color=SPLIT_COLOURS[split], s=6)
        axis.set_title(scene)
        axis.set_xlabel("x (m)", labelpad=-6)
        axis.set_ylabel("y (m)", labelpad=-6)
        axis.set_zlabel("z (m)", labelpad=-6)
        axis.tick_params(labelsize=6, pad=-2)
        if index == 0:
            axis.legend(loc="upper left", fontsize=7)
    figure.suptitle("Camera trajectories (dot: first frame), training vs test sequences")
    return figure


def plot_blur_pairs(root: str | os.PathLike, records: list[dict], count: int = 4) -> plt.Figure:
    """Sharp / blurred pairs of test frames spanning the blur range (quantiles of extent)."""
    test = sorted((r for r in records if r["split"] == "test"), key=lambda r: r["mean_px"])
    picks = [test[int(q * (len(test) - 1))] for q in np.linspace(0.2, 1.0, count)]
    figure, axes = plt.subplots(2, count, figsize=(2.4 * count, 4.0))
    for column, record in enumerate(picks):
        sequence = next(
            s for s in load_split(root, record["scene"], "test") if s.number == record["sequence"]
        )
        for row, kind in enumerate(("sharp", "color")):
            axis = axes[row, column]
            axis.imshow(read_image(sequence.path(record["frame"], kind)))
            axis.set_xticks([])
            axis.set_yticks([])
            axis.grid(False)
        axes[0, column].set_title(
            f"{record['scene']}: {record['mean_px']:.1f} px at {record['angle_deg']:.0f}°"
        )
    axes[0, 0].set_ylabel("sharp (mid-exposure)")
    axes[1, 0].set_ylabel("blurred + noise (stored)")
    return figure


def plot_blur_histogram(
    records: list[dict], thresholds: tuple[float, float] = (3.0, 8.0)
) -> plt.Figure:
    """Histogram of the per-frame blur extent (mean path length over the exposure, px)."""
    extent = np.array([r["mean_px"] for r in records])
    figure, axis = plt.subplots(figsize=(5.5, 3.0))
    axis.hist(extent, bins=np.arange(0, extent.max() + 1.0, 0.5), color="#555555")
    for value, label, colour in (
        (np.median(extent), "median", "#1f77b4"),
        (np.percentile(extent, 90), "90th percentile", "#d62728"),
    ):
        axis.axvline(value, color=colour, lw=1.5, label=f"{label}: {value:.1f} px")
    for threshold in thresholds:
        axis.axvline(threshold, color="k", ls=":", lw=1)
    axis.set_xlabel("blur extent per frame (px, mean over the image)")
    axis.set_ylabel("frames")
    axis.set_title(f"Blur extent of {extent.size} stand-in frames (dotted: 3 px and 8 px)")
    axis.legend()
    return figure


PAPER_COLOUR = "#999999"
METHOD_COLOURS = {
    "blurred": "#555555",
    "blind_wiener": "#1f77b4",
    "skimage_wiener": "#ff7f0e",
    "unsupervised_wiener": "#2ca02c",
    "richardson_lucy": "#9467bd",
    "wiener": "#1f77b4",
    "rnn": "#d62728",
    "sharp": "#2ca02c",
}


def _image_axis(axis: plt.Axes, image: np.ndarray, title: str, cmap: str = "gray") -> None:
    axis.imshow(np.clip(image, 0, 1) if image.dtype != np.uint8 else image, cmap=cmap)
    axis.set_title(title)
    axis.axis("off")


def plot_kernels(kernels: dict[str, np.ndarray]) -> plt.Figure:
    """Blur kernels (PSFs) side by side, each titled by its label."""
    figure, axes = plt.subplots(1, len(kernels), figsize=(2.0 * len(kernels), 2.2))
    for axis, (label, kernel) in zip(np.atleast_1d(axes), kernels.items(), strict=True):
        axis.imshow(kernel, cmap="magma", interpolation="nearest")
        axis.set_title(label)
        axis.axis("off")
    return figure


def plot_spectra(
    sharp: np.ndarray,
    blurred: np.ndarray,
    spectrum_sharp: np.ndarray,
    spectrum_blurred: np.ndarray,
    length_px: float,
    angle_deg: float,
) -> plt.Figure:
    """Sharp vs blurred image and their log power spectra; the blurred spectrum's dark stripes
    (sinc zeros) run perpendicular to the motion, N / L bins apart (dashed: predicted zeros)."""
    figure, axes = plt.subplots(1, 4, figsize=(11, 2.9))
    _image_axis(axes[0], sharp, "sharp")
    _image_axis(axes[1], blurred, f"blurred: L = {length_px:g} px, θ = {angle_deg:g}°")
    size = spectrum_blurred.shape[0]
    panels = ((axes[2], spectrum_sharp, "log power spectrum, sharp"),
              (axes[3], spectrum_blurred, "log power spectrum, blurred"))  # fmt: skip
    for axis, spectrum, title in panels:
        axis.imshow(spectrum, cmap="viridis", extent=(-size / 2, size / 2, -size / 2, size / 2))
        axis.set_title(title)
        axis.axis("off")
    theta = np.radians(angle_deg)
    direction, normal = np.array([np.cos(theta), np.sin(theta)]), np.array(
        [-np.sin(theta), np.cos(theta)]
    )
    for k in range(1, int(length_px / 2) + 1):  # zeros at r = k N / L along the motion
        for sign in (-1, 1):
            centre = sign * k * size / length_px * direction
            ends = np.array([centre - normal * size, centre + normal * size])
            axes[3].plot(ends[:, 0], ends[:, 1], "w--", lw=0.6)
    axes[3].set_xlim(-size / 2, size / 2)
    axes[3].set_ylim(-size / 2, size / 2)
    return figure


def plot_estimation_accuracy(rows: list[dict], noise_for_length: float) -> plt.Figure:
    """Median (line) and interquartile range (band) of the blind angle and length errors,
    against the true length (at noise ``noise_for_length``) and against the noise sigma."""
    figure, axes = plt.subplots(1, 2, figsize=(10, 3.2))
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
        if column == 0:
            axis.set_title(f"against L (σ = {noise_for_length:g}); band: 25-75th percentile")
            axis.legend(fontsize=7)
        else:
            axis.set_title("against noise (all L)")
    return figure


def plot_detection(
    scores: dict[str, tuple[np.ndarray, np.ndarray]], threshold: float
) -> plt.Figure:
    """Histograms of the detector's score for sharp and blurred frames, one panel per named
    (scores, labels) set, with the threshold."""
    figure, axes = plt.subplots(1, len(scores), figsize=(5 * len(scores), 3), sharex=True)
    for axis, (name, (values, labels)) in zip(np.atleast_1d(axes), scores.items(), strict=True):
        bins = np.linspace(min(values.min(), threshold) - 0.5, values.max() + 0.5, 40)
        axis.hist(values[~labels], bins, alpha=0.6, color="#1f77b4", label="sharp render")
        axis.hist(values[labels], bins, alpha=0.6, color="#d62728", label="blurred (≥ 3 px)")
        axis.axvline(threshold, color="k", lw=1.2, label=f"threshold {threshold:.2f}")
        hit = (values[labels] > threshold).mean()
        correct_sharp = (values[~labels] <= threshold).mean()
        axis.set_title(f"{name}: {hit:.0%} of blurred, {correct_sharp:.0%} of sharp right")
        axis.set_xlabel("blur score ln(P_mid / P_high)")
        axis.legend(fontsize=7)
    return figure


def plot_deblurring_process(rows: list[dict]) -> plt.Figure:
    """Fig. 3, the image deblurring process: blurred image → its log spectrum (with the
    estimated motion direction) → the estimated PSF → the restored image → the sharp truth.
    Each row: dict with blurred, spectrum, angle_deg, kernel, restored, sharp, title."""
    figure, axes = plt.subplots(len(rows), 5, figsize=(13, 2.7 * len(rows)), squeeze=False)
    for row, item in zip(axes, rows, strict=True):
        _image_axis(row[0], item["blurred"], f"{item['title']}: blurred")
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
        _image_axis(row[3], item["restored"], "restored (Wiener)")
        _image_axis(row[4], item["sharp"], "sharp (truth)")
    figure.suptitle("Fig. 3 · The image deblurring process (this package)")
    return figure


def plot_per_scene_metric(
    measured: dict[str, dict[str, float]],
    paper: dict[str, float],
    ylabel: str,
    title: str,
) -> plt.Figure:
    """Grouped bars per scene: each measured method ({method: {scene: value}}) and the paper's
    printed values (hatched grey, labelled "paper")."""
    scenes = list(paper)
    series = [(name, values, METHOD_COLOURS.get(name, None), None)
              for name, values in measured.items()]  # fmt: skip
    series.append(("paper (printed)", paper, PAPER_COLOUR, "//"))
    width = 0.8 / len(series)
    figure, axis = plt.subplots(figsize=(10, 3.4))
    for index, (name, values, colour, hatch) in enumerate(series):
        x = np.arange(len(scenes)) + (index - (len(series) - 1) / 2) * width
        heights = [values.get(scene, np.nan) for scene in scenes]
        axis.bar(x, heights, width, label=name, color=colour, hatch=hatch,
                 edgecolor="white" if hatch is None else "#444444", linewidth=0.5)  # fmt: skip
    axis.set_xticks(np.arange(len(scenes)), scenes)
    axis.set_ylabel(ylabel)
    axis.set_title(title)
    lows = [v for _, values, _, _ in series for v in values.values() if np.isfinite(v)]
    axis.set_ylim(min(lows) * 0.9, max(lows) * 1.03)
    axis.legend(ncol=3, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12))
    return figure


def _box(axis: plt.Axes, x: float, y: float, text: str, colour: str, width: float = 1.5) -> None:
    axis.add_patch(plt.Rectangle((x - width / 2, y - 0.32), width, 0.64, facecolor=colour,
                                 edgecolor="#333333", lw=0.8))  # fmt: skip
    axis.text(x, y, text, ha="center", va="center", fontsize=8)


def _arrow(axis: plt.Axes, start: tuple, end: tuple, text: str = "") -> None:
    axis.annotate("", end, start, arrowprops={"arrowstyle": "->", "lw": 0.9, "color": "#333333"})
    if text:
        axis.text((start[0] + end[0]) / 2, (start[1] + end[1]) / 2 + 0.12, text, fontsize=7,
                  ha="center", color="#555555")  # fmt: skip


def plot_video_network(strip: dict[str, list[np.ndarray]] | None = None) -> plt.Figure:
    """Fig. 4: the recurrent deblurring network of eq. 8-11 as built in
    ``blurloc.models.video_deblur``, and (optionally) a test sequence, one row per method
    ({label: frames})."""
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


def plot_training_curves(
    histories: dict[str, dict], reference_db: float | None = None
) -> plt.Figure:
    """Training loss and validation PSNR against the step, one line per model."""
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


def plot_attention(frame: np.ndarray, weights: np.ndarray, restored: np.ndarray) -> plt.Figure:
    """A blurred frame, the blending weight w_t of eq. 10 (share of the current frame's
    features; the rest comes from the blended past), and the restored frame."""
    figure, axes = plt.subplots(1, 3, figsize=(10, 2.8))
    _image_axis(axes[0], frame, "blurred B_t")
    shown = axes[1].imshow(weights, cmap="viridis", vmin=0, vmax=1)
    axes[1].set_title("w_t (eq. 10): weight of the current frame")
    axes[1].axis("off")
    figure.colorbar(shown, ax=axes[1], fraction=0.04)
    _image_axis(axes[2], restored, "restored L_t")
    return figure


def plot_architecture(stages: list[list[str]], title: str) -> plt.Figure:
    """Fig. 1: the architecture as boxes, one column per stage in data-flow order; alternatives
    of a stage (e.g. image vs video deblurring) are stacked in its column. The box texts come
    from the caller, built from the package's own objects, so the figure follows the code."""
    colours = ["#eeeeee", "#fdd0a2", "#c6dbef", "#c7e9c0", "#dadaeb", "#fcbba1", "#eeeeee"]
    step, width = 2.45, 2.15
    figure, axis = plt.subplots(figsize=(2.0 * len(stages), 3.3))
    axis.set_xlim(-0.1, step * len(stages) - 0.2)
    axis.set_ylim(0, 3.6)
    axis.axis("off")
    centres = []
    for index, boxes in enumerate(stages):
        x = step * index + width / 2
        ys = np.linspace(2.6, 1.0, len(boxes)) if len(boxes) > 1 else [1.8]
        colour = colours[index % len(colours)]
        for y, text in zip(ys, boxes, strict=True):
            axis.add_patch(plt.Rectangle((x - width / 2, y - 0.55), width, 1.1, facecolor=colour,
                                         edgecolor="#333333", lw=0.8))  # fmt: skip
            axis.text(x, y, text, ha="center", va="center", fontsize=7, wrap=True)
        centres.append([(x, y) for y in ys])
    for left, right in itertools.pairwise(centres):
        for x0, y0 in left:
            for x1, y1 in right:
                arrow = {"arrowstyle": "->", "lw": 0.8, "color": "#333333"}
                axis.annotate("", (x1 - width / 2, y1), (x0 + width / 2, y0), arrowprops=arrow)
    axis.set_title(title)
    return figure


def plot_pipeline(panels: list[dict], truth: np.ndarray, predicted: np.ndarray) -> plt.Figure:
    """Fig. 2: one frame through the pipeline. ``panels``: dicts with ``image`` (RGB, grey or a
    2-D map), ``title`` and optional ``cmap``, in processing order; the last panel shows the
    true and predicted camera path (positions (N, 3), seen from above: x vs z)."""
    count = len(panels) + 1
    figure, axes = plt.subplots(1, count, figsize=(2.3 * count, 2.6))
    for axis, panel in zip(axes, panels, strict=False):
        image = panel["image"]
        axis.imshow(image, cmap=panel.get("cmap", "gray"), interpolation="nearest")
        axis.set_title(panel["title"], fontsize=8)
        axis.axis("off")
    axis = axes[-1]
    axis.plot(truth[:, 0], truth[:, 2], "k-", lw=1.4, label="true")
    axis.plot(predicted[:, 0], predicted[:, 2], "-", color="#d62728", lw=1, label="predicted")
    axis.plot(*truth[-1, [0, 2]], "ko", ms=3)
    axis.plot(*predicted[-1, [0, 2]], "o", color="#d62728", ms=3)
    axis.set_aspect("equal", adjustable="datalim")
    axis.set_xlabel("x (m)")
    axis.set_ylabel("z (m)")
    axis.yaxis.set_label_position("right")
    axis.yaxis.tick_right()
    axis.set_title("pose (c, q): path from above", fontsize=8)
    axis.legend(fontsize=6)
    for left, right in itertools.pairwise(axes):
        figure.add_artist(ConnectionPatch((1.02, 0.5), (-0.02, 0.5), "axes fraction",
                                          "axes fraction", axesA=left, axesB=right,
                                          arrowstyle="->", color="#333333"))  # fmt: skip
    return figure


def plot_predicted_views(views: dict[str, dict[str, np.ndarray]], captions: dict[str, str]
                         ) -> plt.Figure:  # fmt: skip
    """Fig. 5: one column per scene ({scene: {row label: image}}), rows in the dicts' order (e.g.
    input, deblurred, ground truth, predicted); ``captions`` under each column."""
    scenes = list(views)
    labels = list(views[scenes[0]])
    figure, axes = plt.subplots(len(labels), len(scenes), squeeze=False,
                                figsize=(1.75 * len(scenes), 1.45 * len(labels) + 0.4))  # fmt: skip
    for column, scene in enumerate(scenes):
        for row, label in enumerate(labels):
            axis = axes[row, column]
            axis.imshow(views[scene][label])
            axis.set_xticks([])
            axis.set_yticks([])
            axis.grid(False)
            if row == 0:
                axis.set_title(scene, fontsize=8)
            if column == 0:
                axis.set_ylabel(label, fontsize=8)
        axes[-1, column].set_xlabel(captions.get(scene, ""), fontsize=7)
    return figure


def plot_error_distributions(
    errors: dict[str, dict[str, np.ndarray]],
    paper: dict[str, dict[str, float]] | None = None,
    ylabel: str = "combined error (eq. 14, per frame)",
) -> plt.Figure:
    """Fig. 10: per scene, the distribution of per-frame errors for each condition
    ({scene: {condition: values}}) as violins with the median marked; optionally a second panel
    with the paper's printed per-scene values ({label: {scene: value}}), labelled "paper"."""
    scenes = list(errors)
    conditions = list(errors[scenes[0]])
    colours = [METHOD_COLOURS.get(c, f"C{i}") for i, c in enumerate(conditions)]
    panels = 2 if paper else 1
    figure, axes = plt.subplots(1, panels, figsize=(11, 3.6), squeeze=False,
                                gridspec_kw={"width_ratios": [3, 1.3][:panels]})  # fmt: skip
    axis = axes[0, 0]
    width = 0.8 / len(conditions)
    for index, (condition, colour) in enumerate(zip(conditions, colours, strict=True)):
        x = np.arange(len(scenes)) + (index - (len(conditions) - 1) / 2) * width
        data = [np.asarray(errors[scene][condition], float) for scene in scenes]
        parts = axis.violinplot(data, x, widths=width * 0.95, showextrema=False,
                                showmedians=True)  # fmt: skip
        for body in parts["bodies"]:
            body.set_facecolor(colour)
            body.set_alpha(0.6)
        parts["cmedians"].set_color("#222222")
        axis.plot([], [], "s", color=colour, alpha=0.6, label=condition)
    axis.set_xticks(np.arange(len(scenes)), scenes)
    axis.set_ylabel(ylabel)
    axis.set_title("measured on the stand-in (violins: per-frame distribution, bar: median)")
    axis.legend(ncol=len(conditions), fontsize=7, loc="upper left")
    if paper:
        axis = axes[0, 1]
        width = 0.8 / len(paper)
        for index, (label, values) in enumerate(paper.items()):
            x = np.arange(len(scenes)) + (index - (len(paper) - 1) / 2) * width
            axis.bar(x, [values.get(s, np.nan) for s in scenes], width, label=label,
                     color=PAPER_COLOUR, alpha=1.0 - 0.45 * index, hatch="//",
                     edgecolor="#444444", linewidth=0.5)  # fmt: skip
        axis.set_xticks(np.arange(len(scenes)), scenes, rotation=60, fontsize=7)
        axis.set_title("paper (printed, 7-Scenes)")
        axis.set_ylim(min(min(v.values()) for v in paper.values()) * 0.85,
                      max(max(v.values()) for v in paper.values()) * 1.05)  # fmt: skip
        axis.legend(fontsize=6, loc="upper left")
    return figure


def plot_ratios(groups: dict[str, list[float]], title: str) -> plt.Figure:
    """Measured / printed ratios, one column of dots per group ({label: ratios}), log scale,
    with the line of agreement at 1."""
    figure, axis = plt.subplots(figsize=(9, 3.2))
    for index, ratios in enumerate(groups.values()):
        spread = np.linspace(-0.15, 0.15, len(ratios))
        axis.plot(np.full(len(ratios), index) + spread, ratios, "o", ms=4, alpha=0.8)
    axis.axhline(1.0, color="#555555", ls=":")
    axis.set_yscale("log")
    axis.set_xticks(range(len(groups)), list(groups), rotation=35, ha="right", fontsize=7)
    axis.set_ylabel("measured / printed")
    axis.set_title(title)
    return figure
