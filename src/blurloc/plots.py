"""Figures and tables, one function per figure, in one consistent style; saved as PNG + PDF."""

from __future__ import annotations

import csv
import os
from collections.abc import Sequence
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

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
