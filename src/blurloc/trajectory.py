"""Trajectory files: TUM format (``timestamp tx ty tz qx qy qz qw``, camera-to-world), their
association by timestamp, and pose errors between two trajectories (``blurloc pose-error``).

TUM files store the quaternion scalar last; in memory it is scalar first, ``w >= 0``, as
everywhere in the package (:mod:`blurloc.poses`).
"""

from __future__ import annotations

import heapq
import os
import warnings
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from .data.sevenscenes import list_sequence
from .errors import DataError
from .files import atomic_path
from .geometry import quaternion_to_rotation, rotation_to_quaternion
from .metrics import error_statistics, orientation_errors_deg, position_errors
from .poses import PosePair, to_quaternions

#: Quaternions whose norm differs from 1 by more than this are refused (not silently fixed).
UNIT_TOLERANCE = 1e-3
#: Below this share of either trajectory's poses matched, ``compare_trajectories`` warns.
MIN_MATCHED_SHARE = 0.5


def format_stamp(stamp: float) -> str:
    """A stamp at full precision without an exponent (``1311868229.576``, ``12``).

    Parameters
    ----------
    stamp : float
        Seconds, or a frame number.

    Returns
    -------
    str
        The shortest decimal that reads back as the same float.
    """
    return np.format_float_positional(float(stamp), trim="-")


def write_tum(path: str | os.PathLike, stamps: np.ndarray, poses: np.ndarray) -> Path:
    """Write camera-to-world poses as a TUM trajectory file.

    Parameters
    ----------
    path : str or os.PathLike
        File to write (parent folders are created); written whole or not at all.
    stamps : numpy.ndarray
        Shape (N,), seconds (or frame numbers).
    poses : numpy.ndarray
        Shape (N, 4, 4), camera-to-world, metres.

    Returns
    -------
    pathlib.Path
        ``path``; one line ``stamp tx ty tz qx qy qz qw`` per pose, ``w >= 0``.
    """
    path = Path(path)
    lines = []
    quaternions = Rotation.from_matrix(np.asarray(poses)[:, :3, :3]).as_quat(canonical=True)
    for stamp, pose, (x, y, z, w) in zip(stamps, poses, quaternions, strict=True):
        tx, ty, tz = pose[:3, 3]
        lines.append(
            f"{format_stamp(stamp)} {tx:.6f} {ty:.6f} {tz:.6f} {x:.8f} {y:.8f} {z:.8f} {w:.8f}"
        )
    with atomic_path(path) as temporary:
        temporary.write_text("\n".join(lines) + "\n")
    return path


def _text(path: Path) -> str:
    if path.is_dir():
        raise DataError(f"{path}: is a folder, not a TUM trajectory file")
    if not path.is_file():
        raise DataError(f"{path}: trajectory file is missing")
    try:
        return path.read_text()
    except UnicodeDecodeError:
        raise DataError(f"{path}: not a text file (TUM lines expected)") from None


def read_tum(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read a TUM trajectory file.

    Comment lines (#) are skipped. A stamp given on several lines keeps its first line, as evo
    reads such files (the ground truth of TUM RGB-D's ``fr2/desk`` repeats one stamp with two
    slightly different poses); a warning says how many lines were dropped.

    Parameters
    ----------
    path : str or os.PathLike
        Text file of lines ``stamp tx ty tz qx qy qz qw``.

    Returns
    -------
    stamps : numpy.ndarray
        Shape (N,), as written.
    positions : numpy.ndarray
        Shape (N, 3), metres.
    quaternions : numpy.ndarray
        Shape (N, 4), ``(w, x, y, z)``, ``w >= 0``.

    Raises
    ------
    DataError
        (a ValueError) naming the file (and line) for a folder, a binary file, a malformed line,
        a non-finite value or a quaternion that is not unit length.
    """
    path = Path(path)
    rows = []
    for number, line in enumerate(_text(path).splitlines(), 1):
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
    positions = table[:, 1:4]
    quaternions = to_quaternions(Rotation.from_quat(table[:, 4:]))  # TUM: scalar last
    _, first = np.unique(table[:, 0], return_index=True)
    if len(first) == len(table):
        return table[:, 0], positions, quaternions
    keep = np.sort(first)
    repeated = table[np.setdiff1d(np.arange(len(table)), keep), 0]
    warnings.warn(f"{path}: {len(table) - len(keep)} line(s) repeat an earlier stamp (first: "
                  f"{format_stamp(repeated[0])}); the first line of each stamp is kept",
                  stacklevel=2)  # fmt: skip
    return table[keep, 0], positions[keep], quaternions[keep]


def associate(
    stamps_a: np.ndarray, stamps_b: np.ndarray, max_difference: float = 0.01
) -> list[tuple[int, int]]:
    """Pair the stamps of two trajectories, closest pairs first, each stamp used at most once.

    The greedy rule of the TUM benchmark's ``associate.py``: repeatedly take the closest pair
    (ties: lower index in ``a``, then in ``b``) still unused, while it is closer than
    ``max_difference``. On a line the closest unused pair is always adjacent in the merged
    sorted order of the unused stamps, so only neighbours are ever compared: O((N + M) log(N + M))
    time and O(N + M) memory (not the N x M table of differences).

    Parameters
    ----------
    stamps_a, stamps_b : numpy.ndarray
        Shapes (N,) and (M,), seconds, any order, distinct within each.
    max_difference : float
        Largest accepted difference (exclusive), seconds; must be > 0.

    Returns
    -------
    list of (int, int)
        Index pairs (i into ``a``, j into ``b``), sorted.
    """
    if not max_difference > 0:  # also refuses NaN
        raise ValueError(f"max_difference must be a positive number of seconds, got "
                         f"{max_difference}")  # fmt: skip
    stamps_a, stamps_b = np.asarray(stamps_a, float), np.asarray(stamps_b, float)
    for stamps in (stamps_a, stamps_b):
        if len(np.unique(stamps)) < len(stamps):
            raise ValueError("the stamps of each trajectory must be distinct")
    stamps = np.concatenate([stamps_a, stamps_b])
    order = np.argsort(stamps, kind="stable")
    is_b = (order >= len(stamps_a)).tolist()
    index = np.where(order >= len(stamps_a), order - len(stamps_a), order).tolist()
    stamps = stamps[order].tolist()
    size = len(stamps)
    previous, following = list(range(-1, size - 1)), list(range(1, size + 1))
    used = [False] * size

    def candidate(left: int, right: int) -> tuple[float, int, int, int, int] | None:
        if left < 0 or right >= size or is_b[left] == is_b[right]:
            return None
        difference = abs(stamps[right] - stamps[left])
        if not difference < max_difference:
            return None
        if is_b[left]:
            return difference, index[right], index[left], left, right
        return difference, index[left], index[right], left, right

    heap = [c for c in map(candidate, range(size - 1), range(1, size)) if c is not None]
    heapq.heapify(heap)
    pairs = []
    while heap:
        _, i, j, left, right = heapq.heappop(heap)
        if used[left] or used[right] or following[left] != right:
            continue
        used[left] = used[right] = True
        pairs.append((i, j))
        before, after = previous[left], following[right]
        if before >= 0:
            following[before] = after
        if after < size:
            previous[after] = before
        new = candidate(before, after)
        if new is not None:
            heapq.heappush(heap, new)
    return sorted(pairs)


def _load(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A TUM file, or a 7-Scenes sequence folder ``seq-XX`` (stamps = frame numbers)."""
    if not path.is_dir():
        return read_tum(path)
    number = path.name.split("-")[-1]
    if not (path.name.startswith("seq-") and number.isdigit()):
        raise DataError(f"{path}: a folder, but not a 7-Scenes sequence folder seq-XX")
    sequence = list_sequence(path.parent, int(number))
    poses = sequence.poses()
    stamps = np.array(sequence.frame_ids, float)
    return stamps, poses[:, :3, 3], rotation_to_quaternion(poses[:, :3, :3])


def compare_trajectories(
    ground_truth: str | os.PathLike, estimate: str | os.PathLike, max_difference: float = 0.01
) -> dict:
    """Position and orientation errors between two trajectories associated by timestamp.

    No registration or scale alignment is done (absolute poses, as camera relocalisation is
    evaluated). A warning says so when fewer than :data:`MIN_MATCHED_SHARE` of either
    trajectory's poses are matched (the errors then describe only part of it).

    Parameters
    ----------
    ground_truth, estimate : str or os.PathLike
        TUM files, or 7-Scenes sequence folders (stamps = frame numbers).
    max_difference : float
        Largest stamp difference of an associated pair (:func:`associate`), seconds.

    Returns
    -------
    dict
        ``{"frames", "position_m": {median, mean, rmse}, "orientation_deg": {...}}``.

    References
    ----------
    Eq. 12-13 of the paper.
    """
    stamps_a, positions_a, quaternions_a = _load(Path(ground_truth))
    stamps_b, positions_b, quaternions_b = _load(Path(estimate))
    pairs = associate(stamps_a, stamps_b, max_difference)
    if not pairs:
        raise DataError(f"{estimate}: no timestamp matches {ground_truth} within "
                        f"{max_difference} s")  # fmt: skip
    for path, count in ((ground_truth, len(stamps_a)), (estimate, len(stamps_b))):
        if len(pairs) < MIN_MATCHED_SHARE * count:
            warnings.warn(f"{path}: only {len(pairs)} of its {count} poses are matched within "
                          f"{max_difference} s (under {MIN_MATCHED_SHARE:.0%}); the errors "
                          "describe that part only", stacklevel=2)  # fmt: skip
    a, b = np.array(pairs).T
    pair = PosePair(positions_a[a], quaternions_a[a], positions_b[b], quaternions_b[b])
    return {"frames": len(pairs), "position_m": error_statistics(position_errors(pair)),
            "orientation_deg": error_statistics(orientation_errors_deg(pair))}  # fmt: skip


def quaternions_to_poses(positions: np.ndarray, quaternions: np.ndarray) -> np.ndarray:
    """Camera-to-world matrices from positions and quaternions.

    Parameters
    ----------
    positions : numpy.ndarray
        Shape (N, 3), metres.
    quaternions : numpy.ndarray
        Shape (N, 4), ``(w, x, y, z)``; normalised first.

    Returns
    -------
    numpy.ndarray
        Shape (N, 4, 4).
    """
    poses = np.tile(np.eye(4), (len(positions), 1, 1))
    poses[:, :3, :3] = quaternion_to_rotation(quaternions)
    poses[:, :3, 3] = positions
    return poses
