"""Frames and camera paths read from a 7-Scenes-layout root for the figures, which draw arrays."""

from __future__ import annotations

import os

import numpy as np

from .sevenscenes import SPLIT_FILES, list_scenes, load_split, read_image


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
