"""Does the video network deblur, or does it denoise? The same network trained and scored on two
renders of one stand-in that differ only in the sensor noise.

    blurloc synth --out data/standin-noise0 --frames 200 --noise 0
    blurloc synth --out data/standin-noise0.01 --frames 200 --noise 0.01
    python benchmarks/train_without_noise.py --clean-root data/standin-noise0 \
        --noisy-root data/standin-noise0.01 [--seeds 0 1 2 3] [--steps 1200] [--frames 100] \
        [--out build/noise_free] [--workers 2] [--out-dir figures]

Both renders use the same seed, so they hold the same scenes, camera paths and sharp frames;
the blurred frames differ only in the Gaussian sensor noise (sigma 0.01 on [0, 1] intensities,
the package's default, or none). Every stand-in frame the package trains on carries that noise,
and part of any gain on it is denoising (the noise-only control, ``bench_noise_control.py``);
the blurred frames without noise isolate the deblurring. Networks: ``shipped`` (the shipped
checkpoint), ``noisy`` (the full network of notebook 03 trained on the noisy render, as every
network of the package is) and ``clean`` (the same, trained on the noise-free render); one
budget per seed (``VideoTrainConfig`` with ``--steps`` steps; all the frames of every training
sequence before its validation part, the last 15 % of one sequence per scene; in ``--workers``
one-thread processes). Each is scored on the first ``--frames`` frames of every test sequence
of both renders (mean of the per-scene means). Printed: each network's PSNR gain over the
blurred input per seed and test render, the paired difference ``clean - noisy`` with its 95 %
t-interval on each (:func:`blurloc.experiments.video_ablation.ablation_intervals`), and how the
noisy-trained network's output on the noisy frames compares with the noise-free blurred frames:
a network that also deblurs ends above them; one that only denoises cannot.
Finished trainings in ``--out`` are reused; one made with other settings is refused. The tables go
to ``<out-dir>/train_without_noise.md`` with one CSV each: ``train_without_noise.csv`` (intervals
on the clean test frames), ``train_without_noise-noisy_test.csv`` and
``train_without_noise-versus_noise-free_input.csv``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from blurloc.experiments.deblurring import per_scene_means
from blurloc.experiments.video import evaluate_video_deblurring
from blurloc.experiments.video_ablation import (
    INTERVAL_COLUMNS,
    ablation_gains,
    ablation_intervals,
    train_ablations,
)
from blurloc.inference import DEFAULT_CHECKPOINT, VideoRestorer
from blurloc.models.video_deblur import VideoDeblurConfig, VideoDeblurNet, parameter_count
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import VideoTrainConfig


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clean-root", required=True, help="stand-in rendered with --noise 0")
    parser.add_argument("--noisy-root", required=True, help="the same render with sensor noise")
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2, 3])
    parser.add_argument("--steps", type=int, default=1200)
    parser.add_argument("--frames", type=int, default=100, help="test frames per sequence")
    parser.add_argument("--out", default="build/noise_free")
    parser.add_argument("--workers", type=int, default=2, help="processes that train at once")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    if len(args.seeds) < 2:
        parser.error("--seeds: at least two, for a paired interval")

    roots = {"clean": args.clean_root, "noisy": args.noisy_root}
    budget = VideoTrainConfig(steps=args.steps, validate_every=100)
    started, runs = time.perf_counter(), []
    for name, root in roots.items():
        runs += train_ablations(root, {name: VideoDeblurConfig()}, args.seeds, budget, args.out,
                                workers=args.workers, validation_per_scene=1)  # fmt: skip
    seconds = time.perf_counter() - started
    parameters = dict.fromkeys(roots, parameter_count(VideoDeblurNet()))
    rows = {test: score(root, runs, args.frames, args.workers) for test, root in roots.items()}
    unblurred = {frame_key(row) for row in rows["clean"]
                 if row["method"] == "blurred" and np.isinf(row["psnr_db"])}  # fmt: skip
    means = {test: {name: value["mean"] for name, value in per_scene_means(
                 [row for row in test_rows if frame_key(row) not in unblurred], "psnr_db").items()}
             for test, test_rows in rows.items()}  # fmt: skip
    print(f"{len(unblurred)} test frames left out: without noise they equal their sharp render "
          f"(no motion in the exposure), so their PSNR is infinite")  # fmt: skip
    tables = {}
    for test, root in roots.items():
        gains = {name: {run.seed: means[test][f"{name}-seed{run.seed}"] - means[test]["blurred"]
                        for run in runs if run.variant == name} for name in roots}  # fmt: skip
        shipped = means[test]["shipped"] - means[test]["blurred"]
        print(f"\ntest frames {'with' if test == 'noisy' else 'without'} sensor noise ({root}): "
              f"blurred input {means[test]['blurred']:.2f} dB; shipped checkpoint "
              f"{shipped:+.2f} dB")  # fmt: skip
        for name, by_seed in gains.items():
            print(f"  trained {name:6s} " + ", ".join(f"seed {s}: {g:+.2f} dB"
                                                     for s, g in by_seed.items()))  # fmt: skip
        intervals = ablation_intervals(gains, parameters, reference="noisy",
                                       below="below the noisy-trained network",
                                       above="above the noisy-trained network")  # fmt: skip
        tables[f"{test} test"] = [
            {
                key: round(row[key], 3) if isinstance(row.get(key), float) else row.get(key, "")
                for key in INTERVAL_COLUMNS
            }
            for row in intervals
        ]
    print(f"({seconds:.0f} s of training; steps {args.steps}, seeds {args.seeds}, first "
          f"{args.frames} frames of every test sequence)")  # fmt: skip
    print(
        "restored noisy frames minus the noise-free blurred frames (the same frames without "
        "noise), dB:"
    )
    versus = []
    for name in ["shipped", *(f"{run.variant}-seed{run.seed}" for run in runs), "blurred"]:
        difference = means["noisy"][name] - means["clean"]["blurred"]
        versus.append(
            {"network": name, "noisy_output_minus_clean_blurred_db": round(difference, 3)}
        )
        if name != "blurred":
            print(f"  {name:14s} {difference:+.2f}")
    print(f"  (the noisy blurred input itself: {difference:+.2f})")
    tables["versus noise-free input"] = versus
    saved = save_benchmark_tables(
        "train_without_noise",
        tables,
        args.out_dir,
        "Video network trained with and without sensor noise: gains on both renders",
        notes=f"{seconds:.0f} s of training; steps {args.steps}, seeds {args.seeds}, first "
        f"{args.frames} frames of every test sequence; {len(unblurred)} frames without motion "
        "left out. Intervals: 95 % t-intervals over the seeds, paired against the "
        "noisy-trained network.",
    )
    print(saved.markdown.read_text())


def score(root: str, runs: list, frames: int, workers: int) -> list[dict]:
    """Per-frame PSNR rows of the blurred input, every trained network and the shipped
    checkpoint on the first ``frames`` frames of every test sequence of ``root``."""
    _, rows = ablation_gains(root, runs, frames_per_sequence=frames, workers=workers)
    return rows + evaluate_video_deblurring(
        root, {"shipped": VideoRestorer(DEFAULT_CHECKPOINT)}, "test",
        frames_per_sequence=frames, with_ssim=False,
    )  # fmt: skip


def frame_key(row: dict) -> tuple:
    """Which test frame a row scores."""
    return row["scene"], row["sequence"], row["frame"]


if __name__ == "__main__":
    main()
