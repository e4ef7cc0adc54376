"""Video deblurring over whole roots: per-frame scores of several methods against the
stand-in's sharp frames, and deblurred copies of a root in the 7-Scenes layout (so the pose
stage reads them with the same reader)."""

from __future__ import annotations

import os
import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np
from tqdm.auto import tqdm

from ..data.sevenscenes import SPLIT_FILES, SequenceFrames, list_scenes, load_split
from ..deconv import deblur_blind
from ..files import atomic_path, check_output_not_input, link_or_copy, write_image_file
from ..images import as_float_image
from ..metrics import psnr, ssim
from ..train.loop import parallel_map


def wiener_sequence(blurred: np.ndarray) -> np.ndarray:
    """Blind Wiener deblurring (eq. 4) of every frame of a video, frame by frame.

    Parameters
    ----------
    blurred : numpy.ndarray
        uint8 (T, H, W, 3).

    Returns
    -------
    numpy.ndarray
        uint8 (T, H, W, 3).
    """
    return np.stack([deblur_blind(frame) for frame in blurred])


def evaluate_video_deblurring(
    root: str | os.PathLike,
    methods: dict[str, Callable[[np.ndarray], np.ndarray]],
    split: str = "test",
    progress: bool = False,
    frames_per_sequence: int | None = None,
    with_ssim: bool = True,
) -> list[dict]:
    """PSNR (eq. 5) and SSIM (eq. 7) of every frame restored by each method.

    Parameters
    ----------
    root : str or os.PathLike
        A stand-in root (it needs the sharp frames).
    methods : dict
        Name -> function of a whole uint8 (T, H, W, 3) sequence returning one of that shape.
    split : str
        ``train`` or ``test``.
    progress : bool
        Show a progress bar.
    frames_per_sequence : int, optional
        Restore and score only the first that many frames of every sequence (all when None).
    with_ssim : bool
        Score SSIM too (it takes about ten times as long as PSNR).

    Returns
    -------
    list of dict
        One row per frame and method: ``scene``, ``sequence``, ``frame``, ``method``,
        ``psnr_db`` and, with ``with_ssim``, ``ssim`` (data range 1, against the sharp frame).
    """
    rows = []
    sequences = [s.first(frames_per_sequence) for scene in list_scenes(root)
                 for s in load_split(root, scene, split)]  # fmt: skip
    for sequence in tqdm(sequences, disable=not progress, desc=f"evaluate {split}"):
        blurred = sequence.images("color")
        sharp = [as_float_image(image) for image in sequence.images("sharp")]
        for name, method in methods.items():
            restored = method(blurred)
            for index, frame in enumerate(sequence.frame_ids):
                estimate = as_float_image(restored[index])
                row = {"scene": sequence.scene, "sequence": sequence.number, "frame": frame,
                       "method": name, "psnr_db": psnr(sharp[index], estimate, 1.0)}  # fmt: skip
                if with_ssim:
                    row["ssim"] = ssim(sharp[index], estimate, 1.0)
                rows.append(row)
    return rows


def write_deblurred_root(
    root: str | os.PathLike,
    out_root: str | os.PathLike,
    method: Callable[[np.ndarray], np.ndarray],
    progress: bool = False,
    workers: int = 1,
) -> Path:
    """Copy a 7-Scenes-layout root with every colour frame replaced by ``method``'s output.

    Poses, split files and the stand-in's sharp frames are carried over, so the pose stage
    reads the copy like the original. Every file is written whole (write, then rename), so an
    interrupted copy holds no half-written frame. One sequence is held in memory at a time per
    process.

    Parameters
    ----------
    root : str or os.PathLike
        The root to copy.
    out_root : str or os.PathLike
        Where the copy is written.
    method : callable
        Function of a whole uint8 (T, H, W, 3) sequence returning one of that shape; with
        ``workers > 1`` it must be picklable (a module-level function such as
        :func:`wiener_sequence`, or :class:`~blurloc.inference.VideoRestorer`).
    progress : bool
        Show a progress bar.
    workers : int
        Processes that deblur sequences at once, each with one PyTorch thread (1: in this
        process).

    Returns
    -------
    pathlib.Path
        ``out_root``.

    Raises
    ------
    ValueError
        If ``workers`` is not positive, or ``out_root`` is ``root`` or lies inside it (checked
        before anything is written).
    """
    root, out_root = Path(root), Path(out_root)
    check_output_not_input(out_root, root)
    jobs = [(sequence, out_root / scene / sequence.folder.name, method)
            for scene in list_scenes(root) for split in SPLIT_FILES
            for sequence in load_split(root, scene, split)]  # fmt: skip
    done = parallel_map(_write_deblurred_sequence, jobs, workers)  # lazy: nothing runs yet
    for scene in list_scenes(root):
        (out_root / scene).mkdir(parents=True, exist_ok=True)
        for name in SPLIT_FILES.values():
            with atomic_path(out_root / scene / name) as temporary:
                shutil.copyfile(root / scene / name, temporary)
    for _ in tqdm(done, total=len(jobs), disable=not progress, desc="write deblurred"):
        pass
    return out_root


def _write_deblurred_sequence(
    job: tuple[SequenceFrames, Path, Callable[[np.ndarray], np.ndarray]],
) -> None:
    """Deblur one sequence of :func:`write_deblurred_root` into ``folder``."""
    sequence, folder, method = job
    folder.mkdir(parents=True, exist_ok=True)
    restored = method(sequence.images("color"))
    for index, frame in enumerate(sequence.frame_ids):
        write_image_file(folder / sequence.path(frame, "color").name, restored[index])
        for kind in ("pose", "sharp"):
            source = sequence.path(frame, kind)
            if source.is_file():
                link_or_copy(source, folder / source.name)
