"""Renderer of the synthetic stand-in for 7-Scenes, written in the 7-Scenes layout: the
orchestration (every sequence of every scene, in worker processes, under the render lock).

Each stored frame is made the way the GoPro deblurring benchmark is made: the camera moves along a
continuous handheld trajectory, sharp frames are rendered at poses spread over the exposure, and
their average *in linear light* (gamma 2.2) is the blurred frame, which the camera model
(:mod:`~blurloc.data.camera_model`) turns into the stored frame: optics blur, sensor noise,
encoding. Beside it the
stand-in stores the sharp render at mid-exposure (the ground truth that real 7-Scenes lacks), the
pose at mid-exposure, the depth, and per-frame blur metadata.

Layout written under ``root``::

    standin.json                      the settings and seed that made it
    <scene>/TrainSplit.txt, TestSplit.txt   ("sequenceN" lines)
    <scene>/seq-XX/frame-XXXXXX.color.png   blurred, noisy (what the camera captured)
    <scene>/seq-XX/frame-XXXXXX.sharp.png   sharp render at mid-exposure (stand-in only)
    <scene>/seq-XX/frame-XXXXXX.pose.txt    4x4 camera-to-world at mid-exposure, metres
    <scene>/seq-XX/frame-XXXXXX.depth.png   uint16 z-depth in millimetres (0: no surface)
    <scene>/seq-XX/blur.csv                  per frame: blur extent (mean/max px), direction

The parts live in their own modules and are re-exported here: the settings
(:mod:`~blurloc.data.synth_config`), the handheld camera paths (:mod:`~blurloc.data.camera_motion`),
one frame's exposure (:mod:`~blurloc.data.exposure`), the splits (:mod:`~blurloc.data.splits`) and
the manifest and lock (:mod:`~blurloc.data.manifest`).
"""

from __future__ import annotations

import json
import multiprocessing
import os
import shutil
import sys
from pathlib import Path

import cv2
import numpy as np
from tqdm.auto import tqdm

from ..config import write_rows
from ..files import atomic_path, dataset_folder, write_image_file
from ..geometry import intrinsics
from ..processes import watch_parent
from .camera_model import capture
from .camera_motion import (
    ROUTE_UNITS_PER_1000_FRAMES,
    HandheldTrajectory,
    scene_route,
    sequence_seed,
    sequence_trajectory,
)
from .exposure import (
    BlurInfo,
    blur_from_motion,
    displacement_angles,
    exposure_tracks,
    path_lengths,
    render_exposure,
)
from .layout import SCENE_NAMES
from .manifest import (
    FORMAT_VERSION,
    LOCK_FILE,
    STANDIN_MANIFEST,
    is_foreign_dataset,
    is_up_to_date,
    manifest_expectations,
    manifest_record,
    render_lock,
)
from .splits import split_sequences
from .synth_config import (
    MAX_BLUR_STRENGTH,
    MAX_SIZE,
    MAX_SUPERSAMPLE,
    MIN_SIZE,
    REAL_7SCENES_MOTION,
    SynthConfig,
    is_integer,
)

#: Columns of each sequence's ``blur.csv``: frame index, mean and largest extent over the image
#: (px), direction (degrees, image y up) and the number of sharp renders averaged
#: (:class:`~blurloc.data.exposure.BlurInfo`).
BLUR_COLUMNS = ("frame", "mean_px", "max_px", "angle_deg", "samples")

__all__ = [
    "BLUR_COLUMNS",
    "FORMAT_VERSION",
    "LOCK_FILE",
    "MAX_BLUR_STRENGTH",
    "MAX_SIZE",
    "MAX_SUPERSAMPLE",
    "MIN_SIZE",
    "REAL_7SCENES_MOTION",
    "ROUTE_UNITS_PER_1000_FRAMES",
    "STANDIN_MANIFEST",
    "BlurInfo",
    "HandheldTrajectory",
    "SynthConfig",
    "blur_from_motion",
    "displacement_angles",
    "exposure_tracks",
    "manifest_expectations",
    "path_lengths",
    "prepare_data_root",
    "render_exposure",
    "render_lock",
    "render_sequence",
    "scene_route",
    "sequence_trajectory",
    "split_sequences",
    "synthesize",
]


def render_sequence(
    root: Path, scene_name: str, sequence: int, config: SynthConfig, seed: int
) -> int:
    """Render and write one sequence; returns its number of frames."""
    cv2.setNumThreads(1)
    scene, trajectory = sequence_trajectory(scene_name, sequence, config, seed)
    frames = config.frames_for(scene_name)
    noise_rng = np.random.default_rng([*sequence_seed(seed, scene_name, sequence), 1])
    camera = intrinsics(config.width, config.height)
    folder = root / scene_name / f"seq-{sequence:02d}"
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for frame in range(frames):
        blurred, sharp, depth, blur = render_exposure(
            scene, trajectory, frame / config.fps, config, camera
        )
        color, sharp = capture(blurred, sharp, config, noise_rng)
        depth_mm = np.clip(np.round(depth * 1000.0), 0, 65535).astype(np.uint16)
        pose = trajectory.poses([frame / config.fps])[0]
        _write_frame_files(folder / f"frame-{frame:06d}", color, sharp, depth_mm, pose)
        rows.append(
            {
                "frame": frame,
                "mean_px": f"{blur.mean_px:.4f}",
                "max_px": f"{blur.max_px:.4f}",
                "angle_deg": f"{blur.angle_deg:.2f}",
                "samples": blur.samples,
            }
        )
    write_rows(rows, folder / "blur.csv", columns=BLUR_COLUMNS)
    return frames


def _render_job(job: tuple) -> int:
    return render_sequence(*job)


def _clear_scenes(root: Path) -> None:
    """Remove the scene folders a stand-in holds (and only those), so a render with other
    settings leaves no stale frames beside the new ones."""
    for name in SCENE_NAMES:
        if (root / name).is_dir():
            shutil.rmtree(root / name)


def prepare_data_root(
    root: str | os.PathLike, quick: bool = False, seed: int = 0, progress: bool = True
) -> Path:
    """The root a notebook reads: the stand-in at ``root``, rendered if missing or out of date
    (:func:`synthesize` with the default or quick settings), or, when ``root`` holds another
    dataset (a non-empty folder without ``standin.json``, e.g. the real 7-Scenes), ``root``
    untouched."""
    root = Path(root)
    if is_foreign_dataset(root):
        return root
    config = SynthConfig.quick() if quick else SynthConfig()
    return synthesize(root, config=config, seed=seed, progress=progress)


def synthesize(
    root: str | os.PathLike,
    scenes: list[str] | None = None,
    config: SynthConfig | None = None,
    seed: int = 0,
    workers: int | None = None,
    progress: bool = True,
    overwrite: bool = False,
) -> Path:
    """Render the stand-in into ``root`` in the 7-Scenes layout and return ``root``.

    Idempotent: if ``root/standin.json`` records the same settings, nothing is rendered again.
    Otherwise the scene folders of the earlier stand-in are removed first, so frames of other
    settings never stay beside the new ones; an interrupted render (its manifest says
    ``"incomplete": true``) is rendered again in full. The same seed gives byte-identical
    files, whatever the number of workers. One render at a time holds ``root/.synth.lock``;
    workers stop when the parent process dies.

    Parameters
    ----------
    root : str or os.PathLike
        Folder to write: missing, empty, or an earlier stand-in (with ``standin.json``). A
        folder holding anything else is never written into.
    scenes : list of str, optional
        Scenes to render (default: all of SCENE_NAMES).
    config : SynthConfig, optional
        Settings (default: ``SynthConfig()``).
    seed : int
        Non-negative seed of every trajectory and of the sensor noise.
    workers : int, optional
        Processes (>= 1; default: one per core, at most one per sequence).
    progress : bool
        Show a progress bar of frames.
    overwrite : bool
        Render even when the manifest records the same settings.

    Returns
    -------
    pathlib.Path
        ``root``.

    Raises
    ------
    ValueError
        On a bad argument (naming it and its ``blurloc synth`` option), a foreign ``root``, a
        ``root`` inside another dataset (:func:`~blurloc.files.dataset_folder`), or a
        render already running into ``root``; all before anything is written.
    """
    root = Path(root)
    config = config or SynthConfig()
    scenes = list(scenes or SCENE_NAMES)
    unknown = sorted(set(scenes) - set(SCENE_NAMES))
    if unknown:
        raise ValueError(f"unknown scene(s) {unknown} (--scenes); choose from "
                         f"{', '.join(SCENE_NAMES)}")  # fmt: skip
    if not is_integer(seed) or seed < 0:
        raise ValueError(f"seed (--seed) must be an integer >= 0, got {seed!r}")
    if workers is not None and (not is_integer(workers) or workers < 1):
        raise ValueError(f"workers (--workers) must be an integer >= 1, got {workers!r}")
    if root.exists() and not root.is_dir():
        raise ValueError(f"{root}: exists and is not a folder")
    manifest = manifest_record(config, seed, scenes)
    manifest_path = root / STANDIN_MANIFEST
    if not overwrite and is_up_to_date(manifest_path, manifest):
        return root
    if is_foreign_dataset(root):
        raise ValueError(f"{root}: not empty and not a stand-in (no {STANDIN_MANIFEST}); "
                         "refusing to render into it")  # fmt: skip
    if (holder := dataset_folder(root.parent)) is not None:
        raise ValueError(f"{root}: lies inside the dataset {holder}; render the stand-in "
                         "elsewhere")  # fmt: skip
    root.mkdir(parents=True, exist_ok=True)
    with render_lock(root):
        if not overwrite and is_up_to_date(manifest_path, manifest):  # another run just finished it
            return root
        # an interrupted render stays a stand-in, marked unfinished
        manifest_path.write_text(json.dumps({"incomplete": True}))
        _clear_scenes(root)
        _render(root, scenes, config, seed, workers, progress)
        with atomic_path(manifest_path) as temporary:
            temporary.write_text(json.dumps(manifest, indent=2))
    return root


def _write_frame_files(
    stem: Path, color: np.ndarray, sharp: np.ndarray, depth_mm: np.ndarray, pose: np.ndarray
) -> None:
    """Write one frame's colour, sharp and depth images and pose, each whole (then renamed)."""
    for kind, pixels in {"color": color, "sharp": sharp, "depth": depth_mm}.items():
        write_image_file(f"{stem}.{kind}.png", pixels)
    with atomic_path(f"{stem}.pose.txt") as temporary:
        np.savetxt(temporary, pose, fmt="%.9e", delimiter="\t")


def _render(
    root: Path,
    scenes: list[str],
    config: SynthConfig,
    seed: int,
    workers: int | None,
    progress: bool,
) -> None:
    """Write the split files and render every sequence of ``scenes``, long jobs first."""
    jobs = []
    for scene in scenes:
        train, test = split_sequences(scene, config)
        (root / scene).mkdir(parents=True, exist_ok=True)
        for name, numbers in (("TrainSplit.txt", train), ("TestSplit.txt", test)):
            with atomic_path(root / scene / name) as temporary:
                temporary.write_text("".join(f"sequence{n}\n" for n in numbers))
        jobs += [(root, scene, n, config, seed) for n in sorted(train + test)]
    jobs.sort(key=lambda job: -config.frames_for(job[1]))  # long jobs first: better balance
    total = sum(config.frames_for(job[1]) for job in jobs)

    workers = workers or min(len(jobs), os.cpu_count() or 1)
    with tqdm(total=total, unit="frame", desc="stand-in", disable=not progress) as bar:
        if workers == 1:
            for job in jobs:
                bar.update(_render_job(job))
        else:
            method = "forkserver" if sys.platform.startswith("linux") else "spawn"
            context = multiprocessing.get_context(method)
            with context.Pool(workers, watch_parent, (os.getpid(),)) as pool:
                for frames in pool.imap_unordered(_render_job, jobs):
                    bar.update(frames)
