"""Where the video network's gain lies: variants of it trained with one budget over several
seeds, scored on the stand-in's test sequences, with the paired difference to the first variant.

    python benchmarks/ablate_video_deblur.py --root data/standin [--variants full half_resolution]
        [--seeds 0 1 2] [--steps 400] [--frames 100] [--out build/video_ablation]

Each variant is trained as notebook 03 trains its ablations (``VideoTrainConfig`` with ``--steps``
optimiser steps, on the first 250 frames of every training sequence), once per seed, and scored
on the first ``--frames`` frames of every test sequence (PSNR against the sharp renders; mean of
the per-scene means). Printed: each run's gain over the blurred input, each variant's mean and
spread over seeds, and for every other variant its paired difference to the first (same seeds)
with a 95 % t-interval. Finished trainings in ``--out`` are reused. Variants: ``full``,
``half_resolution``, ``wide``, ``single_frame``, ``no_aux``, ``no_blending``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from blurloc.experiments.deblurring import per_scene_means
from blurloc.experiments.video import evaluate_video_deblurring
from blurloc.inference import VideoRestorer
from blurloc.intervals import paired_interval
from blurloc.models.video_deblur import VideoDeblurConfig
from blurloc.train.config import VideoTrainConfig
from blurloc.train.video import load_video_splits, train_video_deblur

VARIANTS = {
    "full": VideoDeblurConfig(),
    "half_resolution": VideoDeblurConfig(feature_stride=2),
    "wide": VideoDeblurConfig(channels=48, hidden=32),
    "single_frame": VideoDeblurConfig(aux_state=False, blending=False, recurrent=False),
    "no_aux": VideoDeblurConfig(aux_state=False),
    "no_blending": VideoDeblurConfig(blending=False),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="stand-in root (needs sharp frames)")
    parser.add_argument("--variants", nargs="+", default=["full", "half_resolution"],
                        choices=sorted(VARIANTS))  # fmt: skip
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--frames", type=int, default=100, help="test frames per sequence")
    parser.add_argument("--out", default="build/video_ablation")
    args = parser.parse_args()
    if len(args.seeds) < 2:
        parser.error("--seeds: at least two, for a paired interval")

    splits = load_video_splits(args.root, frames_per_sequence=250)
    gains: dict[str, list[float]] = {name: [] for name in args.variants}
    for name in args.variants:
        for seed in args.seeds:
            run = Path(args.out) / f"{name}-seed{seed}-steps{args.steps}"
            config = VideoTrainConfig(steps=args.steps, validate_every=100, seed=seed,
                                      model=VARIANTS[name])  # fmt: skip
            started = time.perf_counter()
            train_video_deblur(splits, run, config, progress=False)
            trained = time.perf_counter() - started
            methods = {"blurred": np.asarray, "restored": VideoRestorer(run / "best.pt", "cpu")}
            rows = evaluate_video_deblurring(args.root, methods, "test",
                                             frames_per_sequence=args.frames)  # fmt: skip
            means = per_scene_means(rows, "psnr_db")
            gain = means["restored"]["mean"] - means["blurred"]["mean"]
            gains[name].append(gain)
            print(f"{name:16s} seed {seed}: {means['restored']['mean']:.2f} dB, "
                  f"gain {gain:+.2f} dB over the blurred input ({trained:.0f} s training)",
                  flush=True)  # fmt: skip
    first = args.variants[0]
    print(f"\n{args.steps} steps, seeds {args.seeds}, first {args.frames} frames of every test "
          "sequence; gain over the blurred input, mean [min, max] over seeds:")  # fmt: skip
    for name in args.variants:
        values = np.array(gains[name])
        line = f"  {name:16s} {values.mean():+.2f} dB [{values.min():+.2f}, {values.max():+.2f}]"
        if name != first:
            interval = paired_interval(values - np.array(gains[first]), method="t")
            line += (f"; minus {first}: {interval.mean:+.2f} dB, 95 % t-interval "
                     f"[{interval.low:+.2f}, {interval.high:+.2f}]")  # fmt: skip
        print(line)


if __name__ == "__main__":
    main()
