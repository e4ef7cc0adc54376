"""Rendering speed of the stand-in: frames per second, and the projected time of the full one.

    python benchmarks/bench_synth.py [--frames 30] [--workers 2]

Renders a few sequences with the default settings into a temporary folder and prints frames/s
(per process and in all), then the time the full default stand-in would take (target: <= 10
minutes on 2 cores) and the time of the quick one (target: <= 20 s).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from dataclasses import replace

from blurloc.data.scenes import SCENE_NAMES
from blurloc.data.synth import SynthConfig, synthesize


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=30, help="frames per sequence to time")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args()

    full = SynthConfig()
    counts = {name: (1, 1) for name in SCENE_NAMES}
    sample = replace(full, frames_per_sequence=args.frames, sequence_counts=counts)
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
        f"rendered {total_sample} frames ({full.width}x{full.height}, 14 sequences) "
        f"in {seconds:.1f} s with {args.workers} worker(s)"
    )
    print(f"frames per second: {rate:.1f} in all, {rate / args.workers:.1f} per worker")
    print(
        f"full default stand-in: {total_full} frames, projected {total_full / rate / 60:.1f} min "
        f"(target <= 10 min on 2 cores)"
    )
    print(f"quick stand-in: {quick_seconds:.1f} s (target <= 20 s)")


if __name__ == "__main__":
    main()
