"""Figures of the synthetic stand-in (notebook 00): scenes, how a blurred frame is made, camera
paths, sharp/blurred pairs and the blur extent; they draw arrays the caller has read."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np

from ..data.exposure import path_lengths
from .style import SPLIT_COLOURS, label_metres_3d, styled


@styled
def plot_scene_gallery(frames: dict[str, np.ndarray]) -> plt.Figure:
    """One frame per scene, four to a row.

    Parameters
    ----------
    frames : dict
        ``{scene: image}``, RGB (H, W, 3) (:func:`blurloc.data.samples.first_test_frames`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    columns = 4
    rows = -(-len(frames) // columns)
    figure, axes = plt.subplots(rows, columns, figsize=(2.4 * columns, 1.95 * rows))
    for axis in np.ravel(axes):
        axis.axis("off")
    for axis, (scene, image) in zip(np.ravel(axes), frames.items(), strict=False):
        axis.imshow(image)
        axis.set_title(scene)
    figure.suptitle("The seven stand-in scenes (first test frame, sharp render)")
    return figure


@styled
def plot_exposure(
    sub_frames: Sequence[np.ndarray],
    blurred: np.ndarray,
    tracks: np.ndarray,
    times_ms: Sequence[float],
) -> plt.Figure:
    """How a blurred frame is made: sharp renders over the exposure, their average in linear
    light, and the image paths of scene points over the exposure (they differ from point to
    point).

    Parameters
    ----------
    sub_frames : sequence of numpy.ndarray
        Sharp renders (H, W, 3) at times over the exposure.
    blurred : numpy.ndarray
        Their average (H, W, 3), gamma-encoded.
    tracks : numpy.ndarray
        (samples, points, 2): image positions of scene points over the exposure, pixels.
    times_ms : sequence of float
        Time of each sub-frame from mid-exposure, milliseconds.

    Returns
    -------
    matplotlib.figure.Figure
    """
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
    axis.imshow(np.full(blurred.shape, 255, np.uint8))
    length = path_lengths(tracks)
    colours = plt.cm.viridis(length / max(length.max(), 1e-9))
    for point in range(tracks.shape[1]):
        axis.plot(tracks[:, point, 0], tracks[:, point, 1], color=colours[point], lw=1.2)
    axis.set_xlim(0, blurred.shape[1])
    axis.set_ylim(blurred.shape[0], 0)
    axis.set_title(f"point paths: {length.min():.1f}-{length.max():.1f} px")
    axis.axis("off")
    return figure


@styled
def plot_trajectories(paths: dict[str, dict[str, list[np.ndarray]]]) -> plt.Figure:
    """Camera positions of every sequence in 3-D, one panel per scene, coloured by split.

    Parameters
    ----------
    paths : dict
        ``{scene: {split: [positions (N, 3), metres]}}``
        (:func:`blurloc.data.samples.camera_paths`); a dot marks each first frame.

    Returns
    -------
    matplotlib.figure.Figure
    """
    columns = 4
    rows = -(-len(paths) // columns)
    figure = plt.figure(figsize=(3.0 * columns, 2.8 * rows))
    for index, (scene, splits) in enumerate(paths.items()):
        axis = figure.add_subplot(rows, columns, index + 1, projection="3d")
        for split, sequences in splits.items():
            for number, xyz in enumerate(sequences):
                label = split if number == 0 else None
                axis.plot(*xyz.T, color=SPLIT_COLOURS[split], lw=1.0, label=label)
                axis.scatter(*xyz[0], color=SPLIT_COLOURS[split], s=6)
        axis.set_title(scene)
        label_metres_3d(axis, labelpad=-6)
        axis.tick_params(labelsize=6, pad=-2)
        if index == 0:
            axis.legend(loc="upper left", fontsize=7)
    figure.suptitle("Camera trajectories (dot: first frame), training vs test sequences")
    return figure


@styled
def plot_blur_pairs(
    picks: list[dict], sharp: list[np.ndarray], blurred: list[np.ndarray]
) -> plt.Figure:
    """Sharp / blurred pairs of frames, one column per frame.

    Parameters
    ----------
    picks : list of dict
        Blur records of the frames (scene, mean_px, angle_deg) for the titles.
    sharp, blurred : list of numpy.ndarray
        The frames' sharp mid-exposure renders and stored blurred frames, RGB
        (:func:`blurloc.data.samples.blur_range_frames` returns all three).

    Returns
    -------
    matplotlib.figure.Figure
    """
    count = len(picks)
    figure, axes = plt.subplots(2, count, figsize=(2.4 * count, 4.0))
    for column, record in enumerate(picks):
        for row, image in enumerate((sharp[column], blurred[column])):
            axis = axes[row, column]
            axis.imshow(image)
            axis.set_xticks([])
            axis.set_yticks([])
            axis.grid(False)
        axes[0, column].set_title(
            f"{record['scene']}: {record['mean_px']:.1f} px at {record['angle_deg']:.0f}°"
        )
    axes[0, 0].set_ylabel("sharp (mid-exposure)")
    axes[1, 0].set_ylabel("blurred + noise (stored)")
    return figure


@styled
def plot_blur_histogram(
    records: list[dict], thresholds: tuple[float, float] = (3.0, 8.0)
) -> plt.Figure:
    """Histogram of the per-frame blur extent, with its median, 90th percentile and two
    thresholds.

    Parameters
    ----------
    records : list of dict
        Per-frame blur records with ``mean_px`` (mean path length over the exposure, pixels).
    thresholds : (float, float)
        Extents drawn as dotted lines, pixels.

    Returns
    -------
    matplotlib.figure.Figure
    """
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


@styled
def plot_realism(
    statistics: dict[str, dict[str, tuple[float, float, float]]],
    examples: dict[str, Sequence[np.ndarray]],
) -> plt.Figure:
    """Image statistics of stand-in and real frames side by side, and example frames.

    Parameters
    ----------
    statistics : dict
        ``{statistic: {image set: (25th percentile, median, 75th percentile)}}``; every
        statistic lists the same image sets, in the order they are drawn (top to bottom).
    examples : dict
        ``{row label: images}``: example frames (H, W, 3) of each row, the same number per row.

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = list(statistics)
    sets = list(next(iter(statistics.values())))
    columns = max(len(names), max(len(images) for images in examples.values()))
    rows = len(examples)
    figure = plt.figure(figsize=(2.3 * columns, 2.6 + 1.45 * rows))
    grid = figure.add_gridspec(1 + rows, columns, height_ratios=[2.6] + [1.45] * rows)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for column, name in enumerate(names):
        axis = figure.add_subplot(grid[0, column])
        for row, label in enumerate(sets):
            low, median, high = statistics[name][label]
            axis.errorbar(median, -row, xerr=[[median - low], [high - median]], fmt="o",
                          color=colours[row % len(colours)], capsize=2)  # fmt: skip
        axis.set_yticks(-np.arange(len(sets)), sets if column == 0 else [])
        axis.set_title(name, fontsize="small")
        axis.tick_params(axis="x", labelsize="x-small")
    for row, (label, images) in enumerate(examples.items()):
        for column in range(columns):
            axis = figure.add_subplot(grid[1 + row, column])
            axis.axis("off")
            if column < len(images):
                axis.imshow(images[column])
            if column == 0:
                axis.set_title(label, loc="left", fontsize="small")
    figure.suptitle("Stand-in frames beside real camera frames at 160x120 "
                    "(median and 25th-75th percentiles)")  # fmt: skip
    return figure
