"""Reader of the Microsoft 7-Scenes layout (the real dataset or the synthetic stand-in).

::

    <root>/<scene>/TrainSplit.txt, TestSplit.txt    lines "sequence1", "sequence2", ...
    <root>/<scene>/seq-01/frame-000000.color.png    colour frame
    <root>/<scene>/seq-01/frame-000000.pose.txt     4x4 camera-to-world pose, metres
    <root>/<scene>/seq-01/frame-000000.depth.png    uint16 depth, millimetres (optional here)

Every problem is reported as a :class:`DataError` naming the offending file.
"""

from __future__ import annotations

import os
import re
import shutil
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from pathlib import Path

import cv2
import numpy as np
from tqdm.auto import tqdm

from ..errors import DataError
from ..files import decode_image, link_or_copy
from ..geometry import rotation_defect
from .manifest import STANDIN_MANIFEST, manifest_expectations

SPLIT_FILES = {"train": "TrainSplit.txt", "test": "TestSplit.txt"}
ROTATION_TOLERANCE = 1e-2  # real 7-Scenes rotations are orthonormal to about 4e-4
_FRAME = re.compile(r"^frame-(\d+)\.(color\.png|pose\.txt)$")
_SPLIT_LINE = re.compile(r"^sequence(\d+)$", re.IGNORECASE)


def read_pose(path: str | os.PathLike) -> np.ndarray:
    """Read a 4x4 camera-to-world pose (whitespace separated, CRLF tolerated) and validate it."""
    path = Path(path)
    try:
        values = np.array(path.read_text().split(), dtype=float)
    except FileNotFoundError:
        raise DataError(f"{path}: pose file is missing") from None
    except ValueError as error:
        raise DataError(f"{path}: pose file holds a non-number ({error})") from None
    if values.size != 16:
        raise DataError(f"{path}: pose must hold 16 numbers (4x4), found {values.size}")
    pose = values.reshape(4, 4)
    if not np.all(np.isfinite(pose)):
        raise DataError(f"{path}: pose holds NaN or inf")
    if not np.allclose(pose[3], [0, 0, 0, 1], atol=ROTATION_TOLERANCE):
        raise DataError(f"{path}: last row of the pose must be 0 0 0 1, found {pose[3]}")
    defect = rotation_defect(pose[:3, :3], ROTATION_TOLERANCE)
    if defect:
        raise DataError(f"{path}: {defect}")
    return pose


def read_image(path: str | os.PathLike) -> np.ndarray:
    """Read a colour image as RGB uint8 (H, W, 3); DataError names a missing or damaged file."""
    try:
        return decode_image(path, cv2.IMREAD_COLOR)[..., ::-1].copy()
    except ValueError as error:
        raise DataError(str(error)) from None


def read_depth(path: str | os.PathLike) -> np.ndarray:
    """Read a depth image (millimetres, one channel) as metres (float32); 0 where the sensor
    has no reading.

    The file is decoded as colour frames are (:func:`~blurloc.files.decode_image`): its header
    is checked against the pixel cap and for truncation first. DataError names a missing,
    damaged, truncated, oversized or multi-channel file.
    """
    try:
        depth = decode_image(path, cv2.IMREAD_UNCHANGED)
    except ValueError as error:
        raise DataError(str(error)) from None
    if depth.ndim != 2:
        raise DataError(f"{path}: depth image has {depth.shape[2]} channels, expected one")
    return depth.astype(np.float32) / 1000.0


def _parse_split(path: Path) -> list[int]:
    """Sequence numbers of one split file, in order; DataError on a bad or repeated line."""
    if not path.is_file():
        raise DataError(f"{path}: split file is missing")
    numbers: list[int] = []
    for line_number, line in enumerate(path.read_text().splitlines(), start=1):
        line = line.strip()
        if not line:
            continue
        match = _SPLIT_LINE.match(line)
        if not match:
            raise DataError(f"{path}:{line_number}: expected 'sequenceN', found {line!r}")
        if int(match.group(1)) in numbers:
            raise DataError(f"{path}:{line_number}: {line} is listed twice")
        numbers.append(int(match.group(1)))
    return numbers


def read_split(scene_dir: str | os.PathLike, split: str) -> list[int]:
    """Sequence numbers listed in a scene's TrainSplit.txt or TestSplit.txt.

    Parameters
    ----------
    scene_dir : str or os.PathLike
        The scene folder holding the split files.
    split : {"train", "test"}
        Which split.

    Returns
    -------
    list of int
        Sequence numbers in file order.

    Raises
    ------
    DataError
        Naming the file: missing, a line that is not ``sequenceN``, a sequence listed twice, or
        a sequence that the other split lists too (train and test must not share frames).
    """
    if split not in SPLIT_FILES:
        raise ValueError(f"split must be one of {sorted(SPLIT_FILES)}, got {split!r}")
    path = Path(scene_dir) / SPLIT_FILES[split]
    numbers = _parse_split(path)
    (other,) = (Path(scene_dir) / name for key, name in SPLIT_FILES.items() if key != split)
    if other.is_file():
        shared = sorted(set(numbers) & set(_parse_split(other)))
        if shared:
            raise DataError(f"{path}: sequence(s) {shared} are listed in {other.name} too; "
                            "a sequence belongs to one split")  # fmt: skip
    return numbers


def frame_path(folder: Path, frame_id: int, kind: str) -> Path:
    """``folder/frame-XXXXXX.<kind>.png`` (``.pose.txt`` for kind ``pose``)."""
    suffix = "pose.txt" if kind == "pose" else f"{kind}.png"
    return folder / f"frame-{frame_id:06d}.{suffix}"


@dataclass(frozen=True)
class SequenceFrames:
    """The ordered frames of one sequence folder ``<scene>/seq-XX``."""

    scene: str
    number: int
    folder: Path
    frame_ids: tuple[int, ...]

    def path(self, frame_id: int, kind: str = "color") -> Path:
        """File of a frame: kind ``color``, ``sharp`` or ``depth`` (PNG), or ``pose`` (txt)."""
        return frame_path(self.folder, frame_id, kind)

    def __len__(self) -> int:
        return len(self.frame_ids)

    def first(self, count: int | None) -> SequenceFrames:
        """The same sequence cut to its first ``count`` frames (all of them when None)."""
        return replace(self, frame_ids=self.frame_ids[:count])

    def poses(self) -> np.ndarray:
        """All camera-to-world poses (N, 4, 4), validated."""
        return np.stack([read_pose(self.path(i, "pose")) for i in self.frame_ids])

    def images(self, kind: str = "color", frame_ids: Sequence[int] | None = None) -> np.ndarray:
        """The sequence's colour frames (``color``) or sharp renders (``sharp``) as one video.

        Parameters
        ----------
        kind : str
            ``color`` (the recorded, blurred frames) or ``sharp`` (a stand-in's renders).
        frame_ids : sequence of int, optional
            Which frames, in that order (all of :attr:`frame_ids` when None).

        Returns
        -------
        numpy.ndarray
            RGB uint8 (T, H, W, 3).

        Raises
        ------
        DataError
            Naming a missing or damaged file, or the first frame whose size differs from the
            first one's.
        """
        frame_ids = self.frame_ids if frame_ids is None else tuple(frame_ids)
        if not frame_ids:
            raise DataError(f"{self.folder}: no frames to read")
        images = [read_image(self.path(frame, kind)) for frame in frame_ids]
        for frame, image in zip(frame_ids, images, strict=True):
            if image.shape != images[0].shape:
                raise DataError(f"{self.path(frame, kind)}: {image.shape[1]}x{image.shape[0]} "
                                f"px, but {self.path(frame_ids[0], kind)} is "
                                f"{images[0].shape[1]}x{images[0].shape[0]}")  # fmt: skip
        return np.stack(images)


def list_sequence(scene_dir: str | os.PathLike, number: int) -> SequenceFrames:
    """Frames of sequence ``number`` of a scene; every colour frame needs a pose and vice versa."""
    scene_dir = Path(scene_dir)
    folder = scene_dir / f"seq-{number:02d}"
    if not folder.is_dir():
        raise DataError(f"{folder}: sequence named in the split is missing")
    colours, poses = set(), set()
    for entry in os.scandir(folder):
        match = _FRAME.match(entry.name)
        if match:
            (colours if match.group(2) == "color.png" else poses).add(int(match.group(1)))
    if not colours and not poses:
        raise DataError(f"{folder}: sequence holds no frames")
    for frame_id in sorted(colours ^ poses):
        kind = "pose" if frame_id in colours else "color"
        raise DataError(f"{frame_path(folder, frame_id, kind)}: {kind} file is missing")
    return SequenceFrames(scene_dir.name, number, folder, tuple(sorted(colours)))


def list_scenes(root: str | os.PathLike) -> list[str]:
    """Scene folders of a root: those holding a TrainSplit.txt or TestSplit.txt."""
    root = Path(root)
    if not root.is_dir():
        raise DataError(f"{root}: data root is not a folder")
    scenes = sorted(
        entry.name
        for entry in os.scandir(root)
        if entry.is_dir() and any((Path(entry.path) / f).is_file() for f in SPLIT_FILES.values())
    )
    if not scenes:
        raise DataError(f"{root}: no scene folders (with TrainSplit.txt / TestSplit.txt) found")
    return scenes


def _promised(root: str | os.PathLike) -> tuple[Path, dict[str, tuple[int, int, int]]] | None:
    """A stand-in's manifest and, per scene, the (frames per sequence, height, width) it
    records; None for a root that is not a stand-in. DataError names a bad manifest."""
    try:
        promised = manifest_expectations(root)
    except ValueError as error:
        raise DataError(str(error)) from None
    return None if promised is None else (Path(root) / STANDIN_MANIFEST, promised)


def _check_promise(sequence: SequenceFrames, promised: tuple[Path, dict] | None) -> None:
    """DataError when a stand-in sequence holds other frames than its manifest records."""
    if promised is None:
        return
    manifest, scenes = promised
    if sequence.scene not in scenes:
        raise DataError(f"{sequence.folder.parent}: scene not made by the render that "
                        f"{manifest} records")  # fmt: skip
    if len(sequence) != scenes[sequence.scene][0]:
        raise DataError(f"{sequence.folder}: {len(sequence)} frames, but {manifest} records "
                        f"{scenes[sequence.scene][0]}")  # fmt: skip


def load_split(root: str | os.PathLike, scene: str, split: str) -> list[SequenceFrames]:
    """The sequences of one split of one scene, in split-file order.

    Parameters
    ----------
    root : str or os.PathLike
        A 7-Scenes-layout root (real or stand-in).
    scene : str
        Scene folder name, e.g. ``"chess"``.
    split : {"train", "test"}
        Which split.

    Returns
    -------
    list of SequenceFrames
        One per sequence the split file lists.

    Raises
    ------
    DataError
        Naming the file: see :func:`read_split` and :func:`list_sequence`; on a stand-in also
        an unfinished render or a frame count other than ``standin.json`` records.
    """
    scene_dir = Path(root) / scene
    if not scene_dir.is_dir():
        raise DataError(f"{scene_dir}: scene folder is missing")
    promised = _promised(root)
    sequences = [list_sequence(scene_dir, n) for n in read_split(scene_dir, split)]
    for sequence in sequences:
        _check_promise(sequence, promised)
    return sequences


def check_data(root: str | os.PathLike, progress: bool = False, workers: int = 4) -> dict:
    """Validate every scene under ``root`` and count its sequences and frames per split.

    Reads every pose and decodes every colour image. All frames of a scene must share one
    size; on a stand-in, ``standin.json`` must record a finished render, and the frame counts
    and sizes must be the ones it records (so stale frames of another render are caught).

    Parameters
    ----------
    root : str or os.PathLike
        A 7-Scenes-layout root (real or stand-in).
    progress : bool
        Show a progress bar per scene and split.
    workers : int
        Threads decoding images.

    Returns
    -------
    dict
        ``{"scenes": {scene: {"train": {"sequences": N, "frames": N}, "test": {...}}}}``.

    Raises
    ------
    DataError
        Naming the file, on the first problem.
    """
    promised = _promised(root)
    summary: dict[str, dict] = {}
    for scene in list_scenes(root):
        counts = {}
        first = None  # (where the scene's frame size comes from, (height, width))
        if promised is not None and scene in promised[1]:
            first = (promised[0], promised[1][scene][1:])
        for split in SPLIT_FILES:
            sequences = load_split(root, scene, split)
            counts[split] = {"sequences": len(sequences), "frames": sum(map(len, sequences))}
            frames = [seq.path(i) for seq in sequences for i in seq.frame_ids]
            for sequence in sequences:
                sequence.poses()
            with ThreadPoolExecutor(workers) as pool:  # OpenCV decodes without the GIL
                images = pool.map(lambda path: (path, read_image(path).shape), frames)
                for path, shape in tqdm(
                    images,
                    total=len(frames),
                    desc=f"{scene}/{split}",
                    disable=not progress,
                    leave=False,
                ):
                    first = first or (path, shape[:2])
                    if shape[:2] != first[1]:
                        height, width = first[1]
                        raise DataError(f"{path}: {shape[1]}x{shape[0]} frame in a scene of "
                                        f"{width}x{height} frames ({first[0]})")  # fmt: skip
        if counts["train"]["frames"] + counts["test"]["frames"] == 0:
            raise DataError(f"{Path(root) / scene}: scene has no frames in its splits")
        summary[scene] = counts
    return {"scenes": summary}


def validation_root(
    data: str | os.PathLike, scene: str, held_out: Sequence[int], folder: str | os.PathLike
) -> Path:
    """A root that holds some training sequences out for validation, the test ones out of reach.

    How settings are chosen without the test split: ``folder/<scene>`` links every training
    sequence of ``data``; its TrainSplit.txt lists them minus ``held_out`` and its
    TestSplit.txt lists ``held_out``. The test sequences of ``data`` are neither linked nor
    listed, so nothing trained or scored on the new root can read them. The split files are
    rewritten on every call; existing links are kept.

    Parameters
    ----------
    data : str or os.PathLike
        A 7-Scenes-layout root.
    scene : str
        Its scene.
    held_out : sequence of int
        Training sequences of ``data`` held out for validation (numbers as in the split files).
    folder : str or os.PathLike
        The root to make.

    Returns
    -------
    Path
        ``folder``.

    Raises
    ------
    DataError
        When a held-out sequence is not a training sequence of ``data``, or none would be left
        to train on.
    """
    data, folder = Path(data), Path(folder)
    train = read_split(data / scene, "train")
    if not set(held_out) <= set(train) or len(set(held_out)) >= len(train):
        raise DataError(f"{data / scene}: held-out sequences {list(held_out)} must be some, not "
                        f"all, of the training sequences {train}")  # fmt: skip
    scene_dir = folder / scene
    scene_dir.mkdir(parents=True, exist_ok=True)
    for number in train:
        link = scene_dir / f"seq-{number:02d}"
        if not link.exists():
            link.symlink_to((data / scene / f"seq-{number:02d}").resolve())
    splits = {"train": [n for n in train if n not in held_out], "test": list(held_out)}
    for split, numbers in splits.items():
        (scene_dir / SPLIT_FILES[split]).write_text("".join(f"sequence{n}\n" for n in numbers))
    return folder


def split_one_sequence(
    sequence_folder: str | os.PathLike,
    out_root: str | os.PathLike,
    scene: str,
    train_frames: int,
    blocks: int = 1,
) -> Path:
    """Cut one recorded sequence into a training and a test sequence of a new root.

    How a single long recording (a real 1000-frame 7-Scenes sequence, or one of the stand-in's)
    becomes something ``blurloc train-pose`` can learn from and be tested on: its first
    ``train_frames`` frames become ``<scene>/seq-01`` (TrainSplit.txt), the rest
    ``<scene>/seq-02`` (TestSplit.txt), numbered from 0 again. With ``blocks > 1`` the
    recording is first cut into that many consecutive blocks of (nearly) equal length, and each
    block is cut the same way (its share of ``train_frames`` first): training sequences
    ``seq-01`` to ``seq-<blocks>``, test sequences after them, so that the test views lie
    between training views (a check of how much the test views' place in the recording
    matters). Each frame's files (colour, sharp, depth, pose, whichever exist) are hard-linked
    where the file system allows it, copied otherwise: a hard link shares the source's data, so
    never edit the cut's files in place. The stand-in's ``blur.csv`` is not carried over. The
    scene is written under a temporary name and renamed when complete, so an interrupted cut
    leaves no half-written scene behind.

    Parameters
    ----------
    sequence_folder : str or os.PathLike
        A ``seq-XX`` folder of a 7-Scenes-layout root.
    out_root : str or os.PathLike
        The root to write (created). It must not be a stand-in (``standin.json``) nor hold
        ``<scene>`` already.
    scene : str
        Scene folder name to write under ``out_root``.
    train_frames : int
        Frames of the training part; both parts of every block must keep at least two frames.
    blocks : int
        Consecutive blocks, each cut into a training and a test sequence (default 1).

    Returns
    -------
    Path
        ``out_root``.

    Raises
    ------
    DataError
        Naming the folder: not a ``seq-XX`` folder, no frames, a colour frame without its pose,
        too few frames for the cut, an existing scene folder or a stand-in manifest in
        ``out_root``.
    """
    source = Path(sequence_folder)
    match = re.match(r"^seq-(\d+)$", source.name)
    if not match or source.name != f"seq-{int(match.group(1)):02d}":
        raise DataError(f"{source}: expected a seq-XX folder (seq-01, seq-02, ...)")
    sequence = list_sequence(source.parent, int(match.group(1)))
    if blocks < 1:
        raise DataError(f"{source}: blocks must be >= 1, got {blocks}")
    ends = [round(k * len(sequence) / blocks) for k in range(blocks + 1)]
    trains = [round(k * train_frames / blocks) for k in range(blocks + 1)]
    cuts = [(ends[k], ends[k] + trains[k + 1] - trains[k], ends[k + 1]) for k in range(blocks)]
    if not all(cut - start >= 2 and end - cut >= 2 for start, cut, end in cuts):
        raise DataError(f"{source}: {len(sequence)} frames cannot be cut into {blocks} block(s) "
                        f"with {train_frames} training frames (every part needs at least "
                        "two)")  # fmt: skip
    out_root = Path(out_root)
    if (out_root / STANDIN_MANIFEST).exists():
        raise DataError(f"{out_root}: a stand-in root ({STANDIN_MANIFEST}); cut into another")
    scene_dir = out_root / scene
    if scene_dir.exists():
        raise DataError(f"{scene_dir}: already exists; choose another root or remove it")
    partial = out_root / f".{scene}.partial"
    shutil.rmtree(partial, ignore_errors=True)
    ids = sequence.frame_ids
    parts = {**{k + 1: ids[start:cut] for k, (start, cut, _) in enumerate(cuts)},
             **{blocks + k + 1: ids[cut:end] for k, (_, cut, end) in enumerate(cuts)}}  # fmt: skip
    for number, frame_ids in parts.items():
        folder = partial / f"seq-{number:02d}"
        folder.mkdir(parents=True)
        for new_id, frame_id in enumerate(frame_ids):
            for kind in ("color", "sharp", "depth", "pose"):
                origin = sequence.path(frame_id, kind)
                if origin.is_file():
                    link_or_copy(origin, frame_path(folder, new_id, kind))
    for split, numbers in (("train", range(1, blocks + 1)),
                           ("test", range(blocks + 1, 2 * blocks + 1))):  # fmt: skip
        (partial / SPLIT_FILES[split]).write_text("".join(f"sequence{n}\n" for n in numbers))
    partial.rename(scene_dir)
    return out_root
