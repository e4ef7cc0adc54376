"""Statistics of a 7-Scenes-layout root: camera motion per frame and (stand-in) blur extent."""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np

from ..blur import BLURRED_FROM_PX, SHARP_BELOW_PX, blur_score
from ..geometry import frame_to_frame_motion
from .samples import split_frames
from .sevenscenes import SPLIT_FILES, list_scenes, load_split, read_image

MOTION_COLUMNS = (
    "scene", "sequences", "frames", "step_median_mm", "step_p95_mm", "rotation_median_deg",
    "rotation_p95_deg", "extent_x_m", "extent_y_m", "extent_z_m",
)  # fmt: skip


def motion_statistics(root: str | os.PathLike) -> list[dict]:
    """Per scene (and ``all``): camera step and rotation between consecutive frames.

    Steps in millimetres, rotations in degrees (median and 95th percentile over all frame pairs
    of both splits); extents are the median over sequences of each axis' range, in metres.
    """
    rows, all_steps, all_turns, all_extents, totals = [], [], [], [], [0, 0]
    for scene in list_scenes(root):
        steps, turns, extents, frames, count = [], [], [], 0, 0
        for split in SPLIT_FILES:
            for sequence in load_split(root, scene, split):
                poses = sequence.poses()
                step, turn = frame_to_frame_motion(poses)
                steps.append(step)
                turns.append(turn)
                extents.append(np.ptp(poses[:, :3, 3], axis=0))
                frames += len(poses)
                count += 1
        rows.append(_motion_row(scene, count, frames, steps, turns, extents))
        all_steps += steps
        all_turns += turns
        all_extents += extents
        totals[0] += count
        totals[1] += frames
    rows.append(_motion_row("all", *totals, all_steps, all_turns, all_extents))
    return rows


def _motion_row(
    scene: str, sequences: int, frames: int, steps: list, turns: list, extents: list
) -> dict:
    step = np.concatenate(steps) * 1000.0
    turn = np.concatenate(turns)
    extent = np.median(np.stack(extents), axis=0)
    return {
        "scene": scene,
        "sequences": sequences,
        "frames": frames,
        "step_median_mm": round(float(np.median(step)), 2),
        "step_p95_mm": round(float(np.percentile(step, 95)), 2),
        "rotation_median_deg": round(float(np.median(turn)), 3),
        "rotation_p95_deg": round(float(np.percentile(turn, 95)), 3),
        "extent_x_m": round(float(extent[0]), 3),
        "extent_y_m": round(float(extent[1]), 3),
        "extent_z_m": round(float(extent[2]), 3),
    }


def read_blur_metadata(root: str | os.PathLike) -> list[dict]:
    """Every frame's blur record of a stand-in root (from each sequence's ``blur.csv``).

    Each row: scene, split, sequence, frame, mean_px, max_px, angle_deg, samples.
    """
    rows = []
    for scene in list_scenes(root):
        for split in SPLIT_FILES:
            for sequence in load_split(root, scene, split):
                path = Path(sequence.folder) / "blur.csv"
                if not path.is_file():
                    raise FileNotFoundError(f"{path}: no blur metadata (is this the stand-in?)")
                with open(path, newline="") as handle:
                    for record in csv.DictReader(handle):
                        rows.append({
                            "scene": scene, "split": split, "sequence": sequence.number,
                            "frame": int(record["frame"]), "mean_px": float(record["mean_px"]),
                            "max_px": float(record["max_px"]),
                            "angle_deg": float(record["angle_deg"]),
                            "samples": int(record["samples"]),
                        })  # fmt: skip
    return rows


def blur_detection_samples(
    root: str | os.PathLike,
    split: str,
    min_blur_px: float = BLURRED_FROM_PX,
    budget: int | None = None,
    sharp_below_px: float = SHARP_BELOW_PX,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Detector scores of a stand-in split's frames.

    For each frame read, its sharp render (labelled sharp) and its stored frame: labelled
    blurred when its mean blur extent is >= ``min_blur_px``, sharp when it is under
    ``sharp_below_px`` (so little blur that deblurring cannot help), left out in between.

    Parameters
    ----------
    root : str or os.PathLike
        The stand-in root (with ``blur.csv`` per sequence).
    split : str
        ``"train"`` (to calibrate a threshold) or ``"test"`` (to check it).
    min_blur_px : float
        Smallest mean blur extent (px) of a blurred example.
    budget : int or None
        About how many frames of the split to read, spread evenly
        (:func:`~blurloc.data.samples.split_frames`); None reads every frame.
    sharp_below_px : float
        Stored frames with less blur than this (px) are sharp examples.

    Returns
    -------
    scores : np.ndarray
        (N,) :func:`blurloc.blur.blur_score` values, px.
    labels : np.ndarray
        (N,) bool, True = blurred.
    extents : np.ndarray
        (N,) recorded blur extents, px (0 for sharp renders).
    """
    extents = {
        (row["scene"], row["sequence"], row["frame"]): row["mean_px"]
        for row in read_blur_metadata(root)
        if row["split"] == split
    }
    scores, labels, lengths = [], [], []
    for scene, sequence, frame in split_frames(root, split, budget):
        extent = extents[(scene, sequence.number, frame)]
        scores.append(blur_score(read_image(sequence.path(frame, "sharp"))))
        labels.append(False)
        lengths.append(0.0)
        if extent >= min_blur_px or extent < sharp_below_px:
            scores.append(blur_score(read_image(sequence.path(frame, "color"))))
            labels.append(extent >= min_blur_px)
            lengths.append(extent)
    return np.array(scores), np.array(labels), np.array(lengths)
