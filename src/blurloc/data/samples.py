"""Which frames of a 7-Scenes-layout root an experiment reads (a frame budget spread evenly over
every scene and sequence), and the frames and camera paths the figures draw."""

from __future__ import annotations

import math
import os

import numpy as np

from .sevenscenes import SPLIT_FILES, SequenceFrames, list_scenes, load_split, read_image


def frame_stride(total: int, budget: int | None = None) -> int:
    """The stride that reads about ``budget`` of ``total`` frames.

    Parameters
    ----------
    total : int
        Number of frames available.
    budget : int or None
        Number of frames to read (>= 1); None reads every frame.

    Returns
    -------
    int
        ``ceil(total / budget)``, at least 1; 1 when ``budget`` is None.
    """
    if budget is None:
        return 1
    if budget < 1:
        raise ValueError(f"the frame budget must be at least 1, got {budget}")
    return max(1, math.ceil(total / budget))


def split_frames(
    root: str | os.PathLike, split: str, budget: int | None = None
) -> list[tuple[str, SequenceFrames, int]]:
    """The frames of a split that a pass reads: about ``budget`` of them, spread evenly.

    One stride (:func:`frame_stride` of the split's frame count) is applied to every sequence
    of every scene, each from its first frame, so that every scene, sequence and part of a
    sequence is represented in proportion to its length, whatever the split's size. At most
    ``budget`` plus one frame per sequence. Deterministic.

    Parameters
    ----------
    root : str or os.PathLike
        The 7-Scenes-layout root.
    split : str
        ``"train"`` or ``"test"``.
    budget : int or None
        Frames to read from the whole split; None reads every frame.

    Returns
    -------
    list of tuple
        ``(scene, sequence, frame_id)``, scenes in :func:`list_scenes` order, sequences in
        split-file order, frames in order.
    """
    sequences = [(scene, sequence) for scene in list_scenes(root)
                 for sequence in load_split(root, scene, split)]  # fmt: skip
    stride = frame_stride(sum(len(sequence) for _, sequence in sequences), budget)
    return [(scene, sequence, frame) for scene, sequence in sequences
            for frame in sequence.frame_ids[::stride]]  # fmt: skip


def first_test_frames(root: str | os.PathLike, kind: str = "sharp") -> dict[str, np.ndarray]:
    """The first frame of the first test sequence of every scene.

    Parameters
    ----------
    root : str or os.PathLike
        The 7-Scenes-layout root.
    kind : str
        ``"sharp"`` (the stand-in's mid-exposure render) or ``"color"`` (the stored frame).

    Returns
    -------
    dict
        ``{scene: image}``, RGB uint8 (H, W, 3), scenes in :func:`list_scenes` order.
    """
    frames = {}
    for scene in list_scenes(root):
        sequence = load_split(root, scene, "test")[0]
        frames[scene] = read_image(sequence.path(sequence.frame_ids[0], kind))
    return frames


def camera_paths(root: str | os.PathLike) -> dict[str, dict[str, list[np.ndarray]]]:
    """Camera positions of every sequence, by scene and split.

    Parameters
    ----------
    root : str or os.PathLike
        The 7-Scenes-layout root.

    Returns
    -------
    dict
        ``{scene: {"train": [positions], "test": [positions]}}``, each (N, 3), metres, world
        frame, sequences in split-file order.
    """
    return {scene: {split: [s.poses()[:, :3, 3] for s in load_split(root, scene, split)]
                    for split in SPLIT_FILES}
            for scene in list_scenes(root)}  # fmt: skip


def blur_range_frames(
    root: str | os.PathLike, records: list[dict], count: int = 4
) -> tuple[list[dict], list[np.ndarray], list[np.ndarray]]:
    """Test frames spanning the blur range: the 20th to 100th percentiles of the blur extent.

    Parameters
    ----------
    root : str or os.PathLike
        The stand-in root.
    records : list of dict
        Per-frame blur records (:func:`blurloc.data.stats.read_blur_metadata`: split, scene,
        sequence, frame, mean_px, angle_deg).
    count : int
        Number of frames, at evenly spaced quantiles of ``mean_px`` from 0.2 to 1.

    Returns
    -------
    picks : list of dict
        The chosen records, in increasing blur.
    sharp, blurred : list of numpy.ndarray
        Their sharp mid-exposure renders and stored (blurred, noisy) frames, RGB uint8.
    """
    test = sorted((r for r in records if r["split"] == "test"), key=lambda r: r["mean_px"])
    picks = [test[int(q * (len(test) - 1))] for q in np.linspace(0.2, 1.0, count)]
    sharp, blurred = [], []
    for record in picks:
        sequence = next(s for s in load_split(root, record["scene"], "test")
                        if s.number == record["sequence"])  # fmt: skip
        sharp.append(read_image(sequence.path(record["frame"], "sharp")))
        blurred.append(read_image(sequence.path(record["frame"], "color")))
    return picks, sharp, blurred
