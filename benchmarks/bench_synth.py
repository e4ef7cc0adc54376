"""Rendering speed of the stand-in: the fast renderer beside the reference ray cast, and the
projected time of the full stand-in.

    python benchmarks/bench_synth.py [--frames 20] [--workers 2] [--width 160 --height 120]
                                     [--repeats 2] [--synth-frames 100] [--skip-synth]
                                     [--out-dir figures]

1. The same frames (the first ``--frames`` of one sequence of every scene, blurred as the
   stand-in makes them: every sub-exposure sample rendered and averaged) are rendered with the
   reference ray cast (``render_exposure(reference=True)``: format 4's renderer, on the same
   textures) and with the fast renderer, each over ``--workers`` processes; prints frames/s and
   CPU time per frame of both, and the ratios.
2. ``synthesize`` (the fast renderer, PNGs written) on 2 sequences of ``--synth-frames`` frames
   per scene (fixed costs, such as starting the workers, are included), then the
   projected time of the full default stand-in and of 7-Scenes' 43,000 frames at 160x120
   (target: <= 10 minutes on 2 cores), and the time of the quick stand-in (target: <= 20 s).

Wall-clock rates and projections depend on the machine's load (other jobs beside it); CPU times
vary less. Writes ``<out-dir>/bench_synth.md``/``.csv`` (the side-by-side renderers) and, unless
``--skip-synth``, ``bench_synth-synthesize.csv`` (part 2).
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np

from blurloc.data.scenes import SCENE_NAMES
from blurloc.data.synth import (
    SynthConfig,
    render_exposure,
    render_sequence,
    sequence_trajectory,
    synthesize,
)
from blurloc.data.textures import TEXTURE_NAMES, texture_pyramid
from blurloc.geometry import intrinsics
from blurloc.tables import add_out_dir_argument, save_benchmark_tables

SEVEN_SCENES_FRAMES = 43_000


_SEQUENCES: dict[str, tuple] = {}  # per process: scene name -> (scene, trajectory)


def render_frames(job: tuple[str, SynthConfig, bool]) -> tuple[int, float]:
    """Render (without writing) every frame of sequence 1 of a scene; returns the count and
    the CPU seconds it took."""
    scene_name, config, reference = job
    cv2.setNumThreads(1)
    scene, trajectory = _SEQUENCES[scene_name]
    camera = intrinsics(config.width, config.height)
    frames = config.frames_for(scene_name)
    start = time.process_time()
    for frame in range(frames):
        render_exposure(scene, trajectory, frame / config.fps, config, camera, reference)
    return frames, time.process_time() - start


def prepare(config: SynthConfig) -> None:
    """Load every texture and make every trajectory (once per process, as a long render
    does), outside the timing."""
    for name in TEXTURE_NAMES:
        texture_pyramid(name)
    for name in SCENE_NAMES:
        _SEQUENCES[name] = sequence_trajectory(name, 1, config)


def frames_per_second(config: SynthConfig, reference: bool, workers: int) -> tuple[float, float]:
    """Frames/s (wall clock) of rendering the first frames of every scene over ``workers``
    processes, and the CPU seconds per frame."""
    jobs = [(name, config, reference) for name in SCENE_NAMES]
    method = "forkserver" if sys.platform.startswith("linux") else "spawn"
    with multiprocessing.get_context(method).Pool(workers, prepare, (config,)) as pool:
        pool.map(time.sleep, [0.5] * workers, chunksize=1)  # every worker is prepared
        start = time.perf_counter()
        frames, cpu = np.sum(pool.map(render_frames, jobs, chunksize=1), axis=0)
        return frames / (time.perf_counter() - start), cpu / frames


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=20, help="frames per scene to compare")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--width", type=int, default=160)
    parser.add_argument("--height", type=int, default=120)
    parser.add_argument("--repeats", type=int, default=2, help="timings of each renderer")
    parser.add_argument("--synth-frames", type=int, default=100, help="per sequence, part 2")
    parser.add_argument("--skip-synth", action="store_true", help="only the side-by-side part")
    add_out_dir_argument(parser)
    args = parser.parse_args()

    config = replace(
        SynthConfig(), width=args.width, height=args.height, frames_per_sequence=args.frames
    )
    paths = ("reference ray cast", "fast renderer")
    rates, cpu = dict.fromkeys(paths, 0.0), dict.fromkeys(paths, np.inf)
    for _ in range(args.repeats):  # alternated, best of each: other jobs share the machine
        for name in paths:
            rate, seconds = frames_per_second(config, name == paths[0], args.workers)
            rates[name], cpu[name] = max(rates[name], rate), min(cpu[name], seconds)
    compared = sum(config.frames_for(name) for name in SCENE_NAMES)
    print(
        f"same {compared} blurred frames ({args.width}x{args.height}, first {args.frames} of a "
        f"sequence per scene), {args.workers} worker(s), best of {args.repeats}:"
    )
    for name in paths:
        print(f"  {name:18s} {rates[name]:7.2f} frames/s  {1000 * cpu[name]:7.1f} ms CPU/frame")
    print(
        f"  ratio {rates[paths[1]] / rates[paths[0]]:.1f}x (frames/s), "
        f"{cpu[paths[0]] / cpu[paths[1]]:.1f}x (CPU time)"
    )
    tables = {
        "renderers": [
            {
                "renderer": name,
                "width": args.width,
                "height": args.height,
                "frames": compared,
                "workers": args.workers,
                "best_of": args.repeats,
                "frames_per_s": round(rates[name], 3),
                "cpu_ms_per_frame": round(1000 * cpu[name], 2),
            }
            for name in paths
        ]
    }
    if not args.skip_synth:
        tables["synthesize"] = time_synthesize(args.synth_frames, args.workers)
    saved = save_benchmark_tables(
        "bench_synth",
        tables,
        args.out_dir,
        "Rendering speed of the stand-in",
        notes=f"Load average at the end {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores.",
    )
    print(f"wrote {saved.markdown}")


def time_synthesize(synth_frames: int, workers: int) -> list[dict]:
    """Time ``synthesize`` on 2 sequences of ``synth_frames`` frames per scene, the quick
    stand-in, and one sequence in this process; print and return the projections."""

    full = SynthConfig()
    counts = {name: (1, 1) for name in SCENE_NAMES}
    sample = replace(full, frames_per_sequence=synth_frames, sequence_counts=counts)
    total_sample = sum(2 * sample.frames_for(name) for name in SCENE_NAMES)
    total_full = sum(sum(full.sequence_counts[n]) * full.frames_for(n) for n in SCENE_NAMES)
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        synthesize(folder, config=sample, workers=workers, progress=False)
        seconds = time.perf_counter() - start
        start = time.perf_counter()
        synthesize(
            os.path.join(folder, "quick"),
            config=SynthConfig.quick(),
            workers=workers,
            progress=False,
        )
        quick_seconds = time.perf_counter() - start
        start = time.process_time()
        frames = render_sequence(Path(folder) / "one", "office", 1, sample, seed=0)
        frame_cpu = (time.process_time() - start) / frames
    rate = total_sample / seconds
    print(
        f"synthesize: {total_sample} frames ({full.width}x{full.height}, 14 sequences, PNGs "
        f"written), {workers} worker(s):\n  {seconds:.1f} s, {rate:.1f} frames/s"
    )
    print(f"  full default stand-in ({total_full} frames): {total_full / rate / 60:.1f} min")
    print(
        f"  {SEVEN_SCENES_FRAMES} frames: {SEVEN_SCENES_FRAMES / rate / 60:.1f} min "
        f"(target <= 10 min on 2 cores)"
    )
    print(f"one sequence in this process: {1000 * frame_cpu:.1f} ms CPU/frame (PNGs written)")
    print(
        f"  {SEVEN_SCENES_FRAMES} frames on {workers} free cores: "
        f"{SEVEN_SCENES_FRAMES * frame_cpu / workers / 60:.1f} min"
    )
    print(f"quick stand-in: {quick_seconds:.1f} s (target <= 20 s)")
    return [
        {"quantity": "synthesize frames", "value": total_sample},
        {"quantity": "synthesize seconds", "value": round(seconds, 2)},
        {"quantity": "synthesize frames/s", "value": round(rate, 2)},
        {
            "quantity": f"full default stand-in ({total_full} frames), min",
            "value": round(total_full / rate / 60, 2),
        },
        {
            "quantity": f"{SEVEN_SCENES_FRAMES} frames, min (target <= 10 on 2 cores)",
            "value": round(SEVEN_SCENES_FRAMES / rate / 60, 2),
        },
        {
            "quantity": "one sequence in this process, ms CPU/frame",
            "value": round(1000 * frame_cpu, 2),
        },
        {
            "quantity": f"{SEVEN_SCENES_FRAMES} frames on {workers} free cores, min",
            "value": round(SEVEN_SCENES_FRAMES * frame_cpu / workers / 60, 2),
        },
        {"quantity": "quick stand-in, s (target <= 20)", "value": round(quick_seconds, 2)},
    ]


if __name__ == "__main__":
    main()
