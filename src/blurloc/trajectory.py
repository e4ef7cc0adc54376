"""Trajectory files: TUM format (``timestamp tx ty tz qx qy qz qw``, camera-to-world), their
association by timestamp, and pose errors between two trajectories (``blurloc pose-error``)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .data.sevenscenes import DataError, list_sequence
from .geometry import quaternion_to_rotation, rotation_to_quaternion
from .metrics import error_statistics, position_errors, quaternion_errors_deg

#: Quaternions whose norm differs from 1 by more than this are refused (not silently fixed).
UNIT_TOLERANCE = 1e-3


def write_tum(path: str | os.PathLike, stamps: np.ndarray, poses: np.ndarray) -> Path:
    """Write camera-to-world poses (N, 4, 4) as TUM lines ``stamp tx ty tz qx qy qz qw``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = []
    quaternions = rotation_to_quaternion(np.asarray(poses)[:, :3, :3])
    for stamp, pose, (w, x, y, z) in zip(stamps, poses, quaternions, strict=True):
        tx, ty, tz = pose[:3, 3]
        lines.append(f"{stamp:g} {tx:.6f} {ty:.6f} {tz:.6f} {x:.8f} {y:.8f} {z:.8f} {w:.8f}")
    path.write_text("\n".join(lines) + "\n")
    return path


def read_tum(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Stamps (N,), positions (N, 3) and quaternions (N, 4; w, x, y, z) of a TUM file. Comment
    lines (#) are skipped; a malformed line, a non-finite value or a quaternion that is not unit
    length raises DataError naming the file and line."""
    path = Path(path)
    if not path.is_file():
        raise DataError(f"{path}: trajectory file is missing")
    rows = []
    for number, line in enumerate(path.read_text().splitlines(), 1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        try:
            values = [float(v) for v in text.replace(",", " ").split()]
        except ValueError as error:
            raise DataError(f"{path}:{number}: not numbers: {text[:60]!r}") from error
        if len(values) != 8 or not np.isfinite(values).all():
            raise DataError(f"{path}:{number}: need 8 finite values: stamp tx ty tz qx qy qz qw")
        norm = np.linalg.norm(values[4:])
        if abs(norm - 1.0) > UNIT_TOLERANCE:
            raise DataError(f"{path}:{number}: quaternion norm {norm:.4f} is not 1")
        rows.append(values)
    if not rows:
        raise DataError(f"{path}: no poses in this file")
    table = np.array(rows)
    return table[:, 0], table[:, 1:4], table[:, [7, 4, 5, 6]]


def associate(
    stamps_a: np.ndarray, stamps_b: np.ndarray, max_difference: float = 0.01
) -> list[tuple[int, int]]:
    """Pairs (i, j) of stamps closer than ``max_difference``, each used at most once, closest
    pairs first (the greedy rule of the TUM tools and evo)."""
    stamps_a, stamps_b = np.asarray(stamps_a, float), np.asarray(stamps_b, float)
    difference = np.abs(stamps_a[:, None] - stamps_b[None, :])
    candidates = np.argwhere(difference < max_difference)
    order = np.argsort(difference[candidates[:, 0], candidates[:, 1]], kind="stable")
    used_a, used_b, pairs = set(), set(), []
    for i, j in candidates[order]:
        if i not in used_a and j not in used_b:
            used_a.add(int(i))
            used_b.add(int(j))
            pairs.append((int(i), int(j)))
    return sorted(pairs)


def _load(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A TUM file, or a 7-Scenes sequence folder (stamps = frame numbers)."""
    if path.is_dir():
        sequence = list_sequence(path.parent, int(path.name.split("-")[-1]))
        poses = sequence.poses()
        quaternions = rotation_to_quaternion(poses[:, :3, :3])
        return np.array(sequence.frame_ids, float), poses[:, :3, 3], quaternions
    return read_tum(path)


def compare_trajectories(
    ground_truth: str | os.PathLike, estimate: str | os.PathLike, max_difference: float = 0.01
) -> dict:
    """Position (eq. 12, metres) and orientation (degrees) errors between two trajectories,
    associated by timestamp: ``{"frames", "position_m": {median, mean, rmse},
    "orientation_deg": {median, mean, rmse}}``. No registration or scale alignment is done
    (absolute poses, as camera relocalisation is evaluated)."""
    stamps_a, positions_a, quaternions_a = _load(Path(ground_truth))
    stamps_b, positions_b, quaternions_b = _load(Path(estimate))
    pairs = associate(stamps_a, stamps_b, max_difference)
    if not pairs:
        raise DataError(f"{estimate}: no timestamp matches {ground_truth} within "
                        f"{max_difference} s")  # fmt: skip
    a, b = np.array(pairs).T
    position = position_errors(positions_a[a], positions_b[b])
    orientation = quaternion_errors_deg(quaternions_a[a], quaternions_b[b])
    return {"frames": len(pairs), "position_m": error_statistics(position),
            "orientation_deg": error_statistics(orientation)}


def quaternions_to_poses(positions: np.ndarray, quaternions: np.ndarray) -> np.ndarray:
    """Camera-to-world 4x4 matrices from positions (N, 3) and quaternions (N, 4; w first)."""
    poses = np.tile(np.eye(4), (len(positions), 1, 1))
    poses[:, :3, :3] = quaternion_to_rotation(quaternions)
    poses[:, :3, 3] = positions
    return poses
