"""TUM RGB-D recordings in the 7-Scenes layout: ground truth at each frame's stamp, sequences, a
held-out split. Torch-free.

A TUM RGB-D recording folder holds ``rgb.txt`` (``stamp file`` lines), the colour frames it
names, and ``groundtruth.txt`` (``stamp tx ty tz qx qy qz qw`` lines: camera-to-world, metres,
motion capture at 100 Hz). :func:`convert_tum` writes it as a 7-Scenes scene
(:mod:`blurloc.data.sevenscenes`): consecutive frames cut into sequences, every
``test_every``-th sequence held out as the test split, so every test view lies between
training views of the same recording.
"""

from __future__ import annotations

import csv
import os
import shutil
from pathlib import Path

import cv2
import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from ..errors import DataError
from ..files import atomic_path, check_output_not_input, decode_image, write_image_file

#: Columns of the ``frames.csv`` that :func:`convert_tum` writes beside the sequences.
FRAME_COLUMNS = ("frame", "sequence", "stamp", "source")


def read_stamped(path: str | os.PathLike) -> list[list[str]]:
    """Non-comment lines of a TUM text file, split on white space.

    Parameters
    ----------
    path : str or os.PathLike
        ``rgb.txt``, ``depth.txt`` or ``groundtruth.txt``.

    Returns
    -------
    list of list of str
        One list of fields per line that is neither empty nor starts with ``#``.
    """
    text = Path(path).read_text()
    return [line.split() for line in text.splitlines() if line and not line.startswith("#")]


def read_groundtruth(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray]:
    """The stamps and poses of a TUM ground-truth file.

    Parameters
    ----------
    path : str or os.PathLike
        ``groundtruth.txt`` (``stamp tx ty tz qx qy qz qw`` lines).

    Returns
    -------
    stamps : numpy.ndarray
        (N,) seconds, increasing.
    rows : numpy.ndarray
        (N, 7): position (metres) and quaternion (x, y, z, w), camera-to-world.

    Raises
    ------
    DataError
        Naming the file when a line does not hold 8 numbers or the stamps do not increase.
    """
    try:
        table = np.array(read_stamped(path), dtype=float)
    except ValueError as error:
        raise DataError(f"{path}: not a TUM ground-truth file ({error})") from None
    if table.ndim != 2 or table.shape[1] != 8 or len(table) < 2:
        raise DataError(f"{path}: needs at least two lines of 8 numbers (stamp tx ty tz qx qy "
                        "qz qw)")  # fmt: skip
    if np.any(np.diff(table[:, 0]) <= 0):
        raise DataError(f"{path}: stamps do not increase")
    return table[:, 0], table[:, 1:]


def pose_at(stamps: np.ndarray, rows: np.ndarray, stamp: float) -> np.ndarray:
    r"""The 4x4 camera-to-world pose of the ground truth at ``stamp``.

    Between the two ground-truth samples around the stamp (times :math:`t_0 \le t \le t_1`):

    .. math::

        w = \frac{t - t_0}{t_1 - t_0}, \quad c = (1 - w)\, c_0 + w\, c_1, \quad
        R = \mathrm{slerp}(R_0, R_1; w)

    Parameters
    ----------
    stamps : numpy.ndarray
        (N,) increasing ground-truth stamps (:func:`read_groundtruth`).
    rows : numpy.ndarray
        (N, 7) positions and quaternions (x, y, z, w).
    stamp : float
        The time wanted, inside ``[stamps[0], stamps[-1]]``.

    Returns
    -------
    numpy.ndarray
        (4, 4) camera-to-world pose, metres.

    Raises
    ------
    ValueError
        If ``stamp`` lies outside the ground truth's time span.
    """
    if not stamps[0] <= stamp <= stamps[-1]:
        raise ValueError(f"stamp {stamp} lies outside the ground truth ({stamps[0]} to "
                         f"{stamps[-1]})")  # fmt: skip
    after = int(np.searchsorted(stamps, stamp))
    before = max(after - 1, 0)
    span = stamps[after] - stamps[before]
    weight = 0.0 if span == 0 else (stamp - stamps[before]) / span
    position = (1 - weight) * rows[before, :3] + weight * rows[after, :3]
    slerp = Slerp(stamps[[before, after]], Rotation.from_quat(rows[[before, after], 3:]))
    pose = np.eye(4)
    pose[:3, :3] = slerp([stamp]).as_matrix()[0]
    pose[:3, 3] = position
    return pose


def write_pose(path: str | os.PathLike, pose: np.ndarray) -> None:
    """Write a 4x4 pose as the 7-Scenes ``frame-XXXXXX.pose.txt`` (9 decimals), atomically.

    Parameters
    ----------
    path : str or os.PathLike
        The pose file to write.
    pose : numpy.ndarray
        (4, 4) camera-to-world transform.
    """
    with atomic_path(path) as temporary:
        np.savetxt(temporary, pose, fmt="%.9f")


def split_sequences(count: int, sequences: int, test_every: int) -> list[tuple[int, bool]]:
    """Which sequence each of ``count`` consecutive frames goes to, and which are held out.

    The frames are cut into ``sequences`` contiguous runs of near-equal length (the first
    ``count % sequences`` one frame longer); sequence ``k`` (numbered from 1) is a test
    sequence when ``k`` is a multiple of ``test_every``.

    Parameters
    ----------
    count : int
        Frames.
    sequences : int
        Sequences to cut them into (1 to ``count``).
    test_every : int
        Every that many-th sequence is held out (>= 2, so that training sequences lie on both
        sides of each test one when there are more sequences than ``test_every``).

    Returns
    -------
    list of (int, bool)
        Per frame: its sequence number (from 1) and whether it is in the test split.

    Raises
    ------
    ValueError
        If the counts do not allow at least one training and one test sequence.
    """
    if not 1 <= sequences <= count:
        raise ValueError(f"sequences must lie in 1..{count} (the frames), got {sequences}")
    if test_every < 2 or test_every > sequences:
        raise ValueError(f"test_every must lie in 2..{sequences} (the sequences), got "
                         f"{test_every}")  # fmt: skip
    numbers = np.concatenate([np.full(len(part), k + 1) for k, part in
                              enumerate(np.array_split(np.arange(count), sequences))])  # fmt: skip
    return [(int(k), bool(k % test_every == 0)) for k in numbers]


def convert_tum(
    source: str | os.PathLike,
    out: str | os.PathLike,
    scene: str,
    sequences: int = 10,
    test_every: int = 4,
    width: int | None = None,
    overwrite: bool = False,
) -> Path:
    """Write a TUM RGB-D recording as a 7-Scenes scene.

    Every colour frame of ``rgb.txt`` inside the ground truth's time span is kept, in time
    order, with its pose (:func:`pose_at`); the frames are cut into sequences
    (:func:`split_sequences`), numbered from ``frame-000000`` in each. ``TrainSplit.txt`` and
    ``TestSplit.txt`` name the sequences; ``frames.csv`` gives each frame's file, sequence,
    TUM stamp and source file. Frames are copied byte for byte, or, with ``width``, shrunk to
    that width (height in proportion, rounded) with area interpolation and written as PNG.

    Parameters
    ----------
    source : str or os.PathLike
        The recording folder (``rgb.txt``, ``groundtruth.txt`` and the frames).
    out : str or os.PathLike
        The 7-Scenes root; the scene is written to ``out/scene``.
    scene : str
        Scene name.
    sequences : int
        Sequences to cut the recording into.
    test_every : int
        Every that many-th sequence is the test split.
    width : int, optional
        Width of the written frames, px (None: the source frames unchanged).
    overwrite : bool
        Replace an existing ``out/scene`` (refused without it).

    Returns
    -------
    pathlib.Path
        The scene folder.

    Raises
    ------
    DataError
        Naming the file, when ``rgb.txt``, ``groundtruth.txt`` or a frame is missing or
        unreadable, or no frame lies inside the ground truth's time span.
    ValueError
        If ``out/scene`` exists without ``overwrite``, ``scene`` is not a plain folder name,
        ``out/scene`` is the recording, holds it or lies inside it, ``width`` is not positive or
        the counts do not allow a split (:func:`split_sequences`).
    """
    source, folder = Path(source), Path(out) / scene
    if width is not None and width < 1:
        raise ValueError(f"width must be > 0, got {width}")
    if scene in ("", ".", "..") or Path(scene).name != scene:
        raise ValueError(f"scene {scene!r}: give a plain folder name (no separator, '.' or '..')")
    check_output_not_input(folder, source)
    if folder.resolve() in (source.resolve(), *source.resolve().parents):
        raise ValueError(f"{folder}: holds the recording {source}; choose another place")
    if folder.exists():
        if not overwrite:
            raise ValueError(f"{folder}: exists; give overwrite=True (--overwrite) to replace it")
        shutil.rmtree(folder)
    for name in ("rgb.txt", "groundtruth.txt"):
        if not (source / name).is_file():
            raise DataError(f"{source / name}: missing (not a TUM RGB-D recording folder)")
    stamps, rows = read_groundtruth(source / "groundtruth.txt")
    frames = [(float(stamp), name) for stamp, name, *_ in read_stamped(source / "rgb.txt")]
    frames = [(stamp, name) for stamp, name in frames if stamps[0] <= stamp <= stamps[-1]]
    if not frames:
        raise DataError(f"{source / 'rgb.txt'}: no frame inside the ground truth's time span")
    plan = split_sequences(len(frames), sequences, test_every)
    table, index, previous = [], 0, 0
    for (stamp, name), (number, _) in zip(frames, plan, strict=True):
        index = index + 1 if number == previous else 0
        previous = number
        sequence = folder / f"seq-{number:02d}"
        sequence.mkdir(parents=True, exist_ok=True)
        frame = f"frame-{index:06d}"
        _write_frame(source / name, sequence / f"{frame}.color.png", width)
        write_pose(sequence / f"{frame}.pose.txt", pose_at(stamps, rows, stamp))
        table.append([f"seq-{number:02d}/{frame}.color.png", f"seq-{number:02d}", f"{stamp:.6f}",
                      name])  # fmt: skip
    with atomic_path(folder / "frames.csv") as temporary, temporary.open("w", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(FRAME_COLUMNS)
        writer.writerows(table)
    held_out = sorted({number for number, test in plan if test})
    kept = sorted({number for number, test in plan if not test})
    for name, numbers in (("TrainSplit.txt", kept), ("TestSplit.txt", held_out)):
        with atomic_path(folder / name) as temporary:
            temporary.write_text("".join(f"sequence{k}\n" for k in numbers))
    return folder


def _write_frame(path: Path, target: Path, width: int | None) -> None:
    """Copy a colour frame, or write it shrunk to ``width`` px as PNG."""
    if not path.is_file():
        raise DataError(f"{path}: colour frame named in rgb.txt is missing")
    if width is None:
        with atomic_path(target) as temporary:
            shutil.copyfile(path, temporary)
        return
    image = decode_image(path, cv2.IMREAD_COLOR)
    height = max(1, round(image.shape[0] * width / image.shape[1]))
    small = cv2.resize(image, (width, height), interpolation=cv2.INTER_AREA)
    write_image_file(target, small[..., ::-1])  # BGR -> RGB
