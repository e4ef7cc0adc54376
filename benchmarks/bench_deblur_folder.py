"""Folder deblurring speed: ms per 640x480 RGB frame, reading and writing included.

    python benchmarks/bench_deblur_folder.py [--frames 120] [--folder DIR] [--workers N]
                                             [--out-dir figures]

Makes ``--frames`` 640x480 RGB PNG frames from scikit-image's bundled photographs, each blurred
by a known line kernel (5-25 px, a different angle per frame) with noise σ = 2/255, in a
temporary folder; beside them, in the same run, real camera frames: the 640x480 TUM RGB-D
Kinect frames of the development set (:mod:`blurloc.data.real`, part ``posed``) when it is
present, or the ``*.color.png`` frames of ``--folder`` DIR (e.g. a 7-Scenes sequence). For real
frames the true kernel is unknown: the "true kernel" rows then use a 9 px horizontal line, for
their time only. Then times, on each set of frames (wall clock from the first read to the last
written file, divided by the number of frames):

- the package's folder deblurring (:func:`blurloc.batch_deblur.deblur_files`) blind, with a
  process pool of ``--workers`` (default: every available core; pool start included), and in
  this process alone (1 worker);
- the package's Wiener filter given the true kernel (eq. 4, NSR estimated from the noise), in
  this process;
- scikit-image's ``skimage.restoration.wiener`` given the true kernel (balance 0.01, per
  channel on [0, 1] floats), with the same OpenCV reading and PNG writing, in this process.

Blind deblurring passes frames through where restoring them is not expected to gain (the gate
of :func:`blurloc.deconv.blind_restoration_expected_to_gain`), and a passed-through frame costs
less than a restored one; the table says how many of the frames were restored. Writes
``<out-dir>/bench_deblur_folder.md`` and ``.csv`` with the command, the date, the cores and
the load average before and after: on a machine shared with other work the wall-clock times are
noisy, so read them with the load average and with the CPU time of the one-process runs (the
work per frame; a pool of N idle cores needs about that divided by N).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import cv2
import numpy as np

from blurloc.batch_deblur import available_cores, deblur_file, deblur_files
from blurloc.blur import blur_image, motion_kernel
from blurloc.data import real
from blurloc.tables import add_out_dir_argument, save_benchmark_tables

PHOTOS = ("astronaut", "coffee", "chelsea", "rocket", "immunohistochemistry", "hubble_deep_field")
TARGET_MS = 30.0


def make_frames(folder: Path, count: int, seed: int = 0) -> list[tuple[Path, float, float]]:
    """Write ``count`` blurred 640x480 RGB PNG frames; returns (path, length px, angle deg)."""
    import skimage.data  # here: the pool's workers import this script, and need no scikit-image

    rng = np.random.default_rng(seed)
    photos = [cv2.resize(getattr(skimage.data, name)()[..., :3], (640, 480),
                         interpolation=cv2.INTER_AREA) for name in PHOTOS]  # fmt: skip
    frames = []
    for index in range(count):
        length, angle = 5.0 + 4.0 * (index % 6), float((index * 37) % 180)
        blurred = blur_image(photos[index % len(photos)], motion_kernel(length, angle),
                             2.0 / 255.0, rng=rng)  # fmt: skip
        path = folder / f"frame-{index:06d}.color.png"
        cv2.imwrite(str(path), np.round(np.clip(blurred, 0, 1) * 255).astype(np.uint8)[..., ::-1])
        frames.append((path, length, angle))
    return frames


def skimage_wiener_file(path_in: Path, path_out: Path, kernel: np.ndarray) -> None:
    """Read, deblur with scikit-image's ``wiener`` per channel, write (the comparison)."""
    from skimage.restoration import wiener

    image = cv2.imread(str(path_in))[..., ::-1].astype(np.float64) / 255.0
    restored = np.stack([wiener(image[..., c], kernel, balance=0.01, clip=True)
                         for c in range(3)], axis=-1)  # fmt: skip
    cv2.imwrite(str(path_out), np.round(restored * 255).astype(np.uint8)[..., ::-1])


def ms_per_frame(run: Callable[[], int]) -> tuple[float, float]:
    """Wall time and this process's CPU time of ``run`` (which returns how many frames it did),
    in ms per frame."""
    wall, cpu = time.perf_counter(), time.process_time()
    frames = run()
    return ((time.perf_counter() - wall) / frames * 1000.0,
            (time.process_time() - cpu) / frames * 1000.0)  # fmt: skip


def time_frames(
    frames: list[tuple[Path, float, float]], target: Path, workers: int
) -> tuple[list[dict], int]:
    """Every method's ms per frame on ``frames`` (written into ``target``), and how many frames
    blind deblurring restored."""
    pairs = [(path, target / path.name) for path, _, _ in frames]
    kernels = [motion_kernel(length, angle) for _, length, angle in frames]
    runs = {
        f"package, blind, pool of {workers}":
            lambda: sum(1 for _ in deblur_files(pairs, workers=workers)),
        "package, blind, 1 process":
            lambda: sum(1 for _ in deblur_files(pairs, workers=1)),
        "package, true kernel, 1 process":
            lambda: sum(1 for pair, k in zip(pairs, kernels, strict=True)
                        if deblur_file(*pair, kernel=k) is not None),
        "scikit-image wiener, true kernel, 1 process":
            lambda: sum(1 for pair, k in zip(pairs, kernels, strict=True)
                        if skimage_wiener_file(*pair, k) is None),
    }  # fmt: skip
    rows, restored = [], 0
    for name, run in runs.items():
        wall, cpu = ms_per_frame(run)
        in_pool = "pool" in name  # the workers' CPU time is not this process's
        rows.append({"method": name, "ms_per_frame": round(wall, 1),
                     "cpu_ms_per_frame": "" if in_pool else round(cpu, 1)})  # fmt: skip
        if name.startswith("package, blind, pool"):  # a passed-through frame is a copy
            restored = sum(a.read_bytes() != b.read_bytes() for a, b in pairs)
    return rows, restored


def real_frames(folder: Path | None, count: int) -> tuple[str, list[tuple[Path, float, float]]]:
    """The real frames to time (``--folder``'s, else the development set's posed frames, else
    none) and their description."""
    if folder is None and real.files_present("posed"):
        folder = real.posed_root() / real.POSED_SCENE / "seq-01"
        name = "real TUM RGB-D fr1_rpy Kinect frames"
    else:
        name = str(folder)
    if folder is None:
        return "", []
    paths = sorted(folder.glob("*.color.png"))[:count]
    if not paths:
        raise SystemExit(f"{folder}: no *.color.png frames")
    return name, [(path, 9.0, 0.0) for path in paths]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=120)
    parser.add_argument("--folder", type=Path, help="real *.color.png frames to time as well")
    parser.add_argument("--workers", type=int, default=available_cores())
    add_out_dir_argument(parser)
    args = parser.parse_args()
    load_before = os.getloadavg()
    table, described = [], []
    with tempfile.TemporaryDirectory() as scratch:
        source = Path(scratch, "in")
        source.mkdir()
        sets = {"line-blurred photographs": make_frames(source, args.frames)}
        real_name, frames = real_frames(args.folder, args.frames)
        if frames:
            sets[real_name] = frames
        for name, frames in sets.items():
            target = Path(scratch, f"out-{len(described)}")
            target.mkdir()
            rows, restored = time_frames(frames, target, args.workers)
            described.append(f"{name}: {len(frames)} frames, {restored} restored by blind "
                             "deblurring")  # fmt: skip
            table += [{"frames_from": name, **row, "frames": len(frames), "restored": restored}
                      for row in rows]  # fmt: skip
    load_after = os.getloadavg()
    for row in table:
        print(
            f"{row['frames_from'][:24]:<25} {row['method']:<44} {row['ms_per_frame']:7.1f} "
            f"ms/frame (CPU {row['cpu_ms_per_frame'] or 'n/a'})"
        )
    context = (f"{'; '.join(described)}. {available_cores()} cores available, "
               f"load average {load_before[0]:.2f} before, {load_after[0]:.2f} after")  # fmt: skip
    machine = {"cores": available_cores(), "load_before": round(load_before[0], 2),
               "load_after": round(load_after[0], 2)}  # fmt: skip
    saved = save_benchmark_tables(
        "bench_deblur_folder",
        {"times": [{**row, **machine} for row in table]},
        args.out_dir,
        "Folder deblurring: ms per 640x480 RGB frame, reading and writing included",
        notes=f"{context}. Target: <= {TARGET_MS:g} ms per frame for the package's folder "
        "deblurring. Wall-clock times on a shared machine are noisy: read them with the load "
        "average. cpu_ms_per_frame: this process's CPU time (empty for the pool).",
    )
    print(f"wrote {saved.markdown} and {saved.csv.name} ({context})")


if __name__ == "__main__":
    main()
