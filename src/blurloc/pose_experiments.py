"""The pose experiment matrix of notebook 04: per scene, train on one kind of input frames
(blurred, blind-Wiener, network-deblurred or sharp) with one head, test on the same kind."""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import numpy as np
from tqdm.auto import tqdm

from .data.sevenscenes import load_split
from .geometry import rotation_to_quaternion
from .inference import load_pose_model, predict_poses
from .metrics import combined_errors, pose_summary, position_errors, quaternion_errors_deg
from .train.config import PoseTrainConfig
from .train.pose import train_pose

CONDITIONS = ("blurred", "wiener", "rnn", "sharp")


def condition_roots(data_root: str | os.PathLike, results_dir: str | os.PathLike) -> dict:
    """Where each condition's frames live: the stand-in itself (blurred; sharp renders for
    ``sharp``) and the deblurred copies notebook 03 writes under ``results/deblurred``."""
    results_dir = Path(results_dir)
    return {"blurred": Path(data_root), "wiener": results_dir / "deblurred" / "wiener",
            "rnn": results_dir / "deblurred" / "rnn", "sharp": Path(data_root)}  # fmt: skip


def run_pose_matrix(
    roots: dict[str, Path],
    scenes: list[str],
    runs: list[tuple[str, str]],
    config: PoseTrainConfig,
    out_dir: str | os.PathLike,
    progress: bool = False,
) -> tuple[list[dict], list[dict]]:
    """Train and test every (condition, head) of ``runs`` on every scene. Returns one summary
    row per run and scene (:func:`~blurloc.metrics.pose_summary`, flattened) and one row per
    test frame (position and orientation error, and eq. 14's per-frame value)."""
    summaries, frames = [], []
    jobs = [(condition, head, scene) for condition, head in runs for scene in scenes]
    for condition, head, scene in tqdm(jobs, disable=not progress, desc="pose runs"):
        run_config = replace(config, image="sharp" if condition == "sharp" else "color",
                             model=replace(config.model, head=head))  # fmt: skip
        folder = Path(out_dir) / condition / head / scene
        history = train_pose(roots[condition], scene, folder, run_config, progress=False)
        model, _ = load_pose_model(folder / "best.pt")
        test = load_split(roots[condition], scene, "test")
        pair = predict_poses(model, test, run_config)
        positions, quaternions = pair.estimate_positions, pair.estimate_quaternions
        true_positions, true_quaternions = pair.reference_positions, pair.reference_quaternions
        summary = pose_summary(true_positions, true_quaternions, positions, quaternions,
                               config.beta)  # fmt: skip
        row = {"scene": scene, "condition": condition, "head": head,
               "train_seconds": round(history["seconds"][-1], 1)}  # fmt: skip
        for key, value in summary.items():
            if isinstance(value, dict):
                row.update({f"{key}_{stat}": v for stat, v in value.items()})
            else:
                row[key] = value
        summaries.append(row)
        position = position_errors(true_positions, positions)
        orientation = quaternion_errors_deg(true_quaternions, quaternions)
        combined = combined_errors(true_positions, true_quaternions, positions, quaternions,
                                   config.beta)  # fmt: skip
        for index in range(len(position)):
            frames.append({"scene": scene, "condition": condition, "head": head,
                           "index": index, "position_m": float(position[index]),
                           "orientation_deg": float(orientation[index]),
                           "combined": float(combined[index])})  # fmt: skip
    return summaries, frames


def mean_pose_baseline(root: str | os.PathLike, scene: str) -> dict:
    """Errors of predicting the mean training position and the chordal-mean training rotation
    for every test frame: what a regressor must beat to have learned anything."""
    train = np.concatenate([s.poses() for s in load_split(root, scene, "train")])
    test = np.concatenate([s.poses() for s in load_split(root, scene, "test")])
    u, _, vt = np.linalg.svd(train[:, :3, :3].sum(axis=0))
    mean_rotation = u @ np.diag([1, 1, np.linalg.det(u @ vt)]) @ vt
    true_q = rotation_to_quaternion(test[:, :3, :3])
    mean_q = np.tile(rotation_to_quaternion(mean_rotation), (len(test), 1))
    mean_p = np.tile(train[:, :3, 3].mean(axis=0), (len(test), 1))
    return pose_summary(test[:, :3, 3], true_q, mean_p, mean_q)


def predict_test_frames(model_path: str | os.PathLike, root: str | os.PathLike,
                           scene: str) -> dict:  # fmt: skip
    """A saved pose model's predictions for every test frame of ``scene`` under ``root``, with
    each frame's identity: ``frames`` [(sequence, frame id)], ``position``, ``quaternion``, the
    true ``true_position``/``true_quaternion``, and per-frame ``position_error`` (m, eq. 12) and
    ``orientation_error`` (degrees, eq. 13); rows in sequence order, then frame order."""
    model, config = load_pose_model(model_path, scene=scene)
    sequences = load_split(root, scene, "test")
    pair = predict_poses(model, sequences, config)
    position, quaternion = pair.estimate_positions, pair.estimate_quaternions
    true_position, true_quaternion = pair.reference_positions, pair.reference_quaternions
    return {"frames": [(s, frame) for s in sequences for frame in s.frame_ids],
            "position": position, "quaternion": quaternion,
            "true_position": true_position, "true_quaternion": true_quaternion,
            "position_error": position_errors(true_position, position),
            "orientation_error": quaternion_errors_deg(true_quaternion, quaternion)}  # fmt: skip
