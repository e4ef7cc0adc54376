"""Does the video network gain more on strong or real-looking camera blur when it is trained on
a wider range of blur or on natural image content, and what does that cost it on the stand-in's
own blur?

    blurloc synth --out data/standin-strong --blur-strength 6.6 --frames 120 --seed 1
    python benchmarks/train_blur_range.py --root data/standin --strong-root data/standin-strong \
        [--seeds 0 1 2] [--steps 1200] [--frames 100] [--out build/blur_range] [--workers 2]
    python benchmarks/train_blur_range.py --root data/standin --photo-videos 14 \
        [--photos-only] --out build/photo_mix [--out-dir figures]

The stand-in's blur is a few pixels at 160x120 (its ``blur.csv`` records it); the
GoPro-style photo videos (:func:`blurloc.experiments.photo_video.photo_video_gains`) carry about
4.5, 9 and 13.5 px, and real high-frame-rate footage averaged the GoPro way is often longer.
Trainings per seed with one budget (``VideoTrainConfig`` with ``--steps`` steps, the full
network of notebook 03, in ``--workers`` one-thread processes): ``standin``, on the first 250
frames of every training sequence of ``--root`` (as notebook 03's ablations); with
``--strong-root``, ``blur_range``, on those plus the training sequences of a second stand-in
rendered with a longer exposure and another seed (other camera paths); with
``--photo-videos N``, ``photo_mix``, on those plus N 30-frame GoPro-style videos made from
photographs that the photo-video set does not show
(:func:`blurloc.experiments.photo_video.photo_training_videos`, seed 0; 14 beside the default
stand-in's 28 training sequences: a third of the clips). Clips are drawn from the union, every
video equally often. Each network keeps its best checkpoint on the validation frames of what it
trains on (the last 15 % of one whole training sequence per scene of each root; N // 2, at
least one, more photo videos, seed 1, for ``photo_mix``). With ``--photos-only``,
``photos_only`` trains on the N photo videos alone and validates on those N // 2.
Every network is scored on the first ``--frames`` frames of every test sequence of each root
and on the photo videos; with ``--photo-videos``, also on the photo videos ``photo_mix`` trained
on (``photo_training``: how well a network fits them, not a test). Printed: each network's
PSNR gain over the blurred input per seed, and, per test set, the paired difference to
``standin`` with its 95 % t-interval
(:func:`blurloc.experiments.video_ablation.ablation_intervals`).
Finished trainings in ``--out`` are reused; one made with other settings is refused (runs
from before bounded recurrent states became the package's default among them: delete them).
The table goes to ``<out-dir>/train_blur_range-<networks>.md``/``.csv``, ``<networks>`` naming
the networks compared with ``standin`` (e.g. ``blur_range`` or ``photo_mix-photos_only``).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from blurloc.experiments.photo_video import (
    add_photo_videos,
    photo_training_videos,
    photo_video_gains,
    restoration_psnr,
)
from blurloc.experiments.video_ablation import (
    INTERVAL_COLUMNS,
    AblationRun,
    ablation_gains,
    ablation_intervals,
    training_videos,
)
from blurloc.inference import VideoRestorer
from blurloc.models.video_deblur import VideoDeblurNet, parameter_count
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import VideoTrainConfig
from blurloc.train.loop import parallel_map
from blurloc.train.video import train_video_deblur

TRAINING_FRAMES = 250  # per sequence of --root, as notebook 03's trainings


def training_splits(root: str | None, strong_root: str | None, photo_videos: int) -> dict:
    """Training and validation videos of ``root`` (first 250 frames of every training sequence;
    none when None), with those of ``strong_root`` and ``photo_videos`` photo videos
    (:func:`~blurloc.experiments.photo_video.add_photo_videos`) appended when given."""
    parts = [training_videos(root, TRAINING_FRAMES, 1)] if root else []
    if strong_root:
        parts.append(training_videos(strong_root, None, 1))
    splits = {name: [video for part in parts for video in part[name]]
              for name in ("train", "validation")}  # fmt: skip
    return add_photo_videos(splits, photo_videos)


def photo_training_gain(folder: Path, videos: list) -> float:
    """Mean over ``videos`` of the PSNR gain (dB) of the network in ``folder`` over the
    blurred input, each video restored as one."""
    restore = VideoRestorer(folder / "best.pt")
    gains = []
    for blurred, sharp in videos:
        before, after = restoration_psnr(restore, blurred, sharp)
        gains.append(after - before)
    return float(np.mean(gains))


def train_one(job: tuple) -> AblationRun:
    """Train (or reuse) one network: job = (name, seed, root or None, strong root or None,
    photo videos, config, folder)."""
    name, seed, root, strong_root, photo_videos, config, folder = job
    history = train_video_deblur(training_splits(root, strong_root, photo_videos), folder,
                                 config, progress=False)  # fmt: skip
    return AblationRun(name, seed, Path(folder), history)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="the stand-in (needs sharp frames)")
    parser.add_argument("--strong-root", help="a stand-in with longer exposure")
    parser.add_argument(
        "--photo-videos",
        type=int,
        default=0,
        help="photo training videos added for the photo_mix network",
    )
    parser.add_argument(
        "--photos-only",
        action="store_true",
        help="also train photos_only, on the photo training videos alone",
    )
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    parser.add_argument("--steps", type=int, default=1200)
    parser.add_argument("--frames", type=int, default=100, help="test frames per sequence")
    parser.add_argument("--out", default="build/blur_range")
    parser.add_argument("--workers", type=int, default=2, help="processes that train at once")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    if len(args.seeds) < 2:
        parser.error("--seeds: at least two, for a paired interval")
    if args.photo_videos < 0:
        parser.error(f"--photo-videos must be >= 0, got {args.photo_videos}")
    if args.photos_only and not args.photo_videos:
        parser.error("--photos-only needs --photo-videos")
    if args.strong_root is None and not args.photo_videos:
        parser.error("give --strong-root, --photo-videos or both: something to compare with")

    budget = VideoTrainConfig(steps=args.steps, validate_every=100)
    if args.workers > 1:
        budget = replace(budget, threads=1)  # one thread per worker process
    parameters = parameter_count(VideoDeblurNet(budget.model))  # the same network for every variant
    training = {"standin": (args.root, None, 0)}  # name: root, strong root, photo videos
    if args.strong_root is not None:
        training["blur_range"] = (args.root, args.strong_root, 0)
    if args.photo_videos:
        training["photo_mix"] = (args.root, None, args.photo_videos)
    if args.photos_only:
        training["photos_only"] = (None, None, args.photo_videos)
    jobs = [(name, seed, root, strong, photos, replace(budget, seed=seed),
             f"{args.out}/{name}-seed{seed}")
            for name, (root, strong, photos) in training.items()
            for seed in args.seeds]  # fmt: skip
    started = time.perf_counter()
    runs = list(parallel_map(train_one, jobs, args.workers))
    print(f"{len(runs)} trainings of {args.steps} steps in {time.perf_counter() - started:.0f} s")

    gains = {}  # test set -> network -> seed -> gain (dB)
    for test, root in (("standin", args.root), ("strong", args.strong_root)):
        if root is not None:
            gains[test], _ = ablation_gains(
                root, runs, frames_per_sequence=args.frames, workers=args.workers
            )
    gains["photo_videos"] = {}
    for run in runs:
        rows = photo_video_gains(VideoRestorer(run.folder / "best.pt"))
        mean = float(np.mean([row["gain_db"] for row in rows]))
        gains["photo_videos"].setdefault(run.variant, {})[run.seed] = mean
        worst = min(rows, key=lambda row: row["gain_db"])
        by_speed = {step: np.mean([r["gain_db"] for r in rows if r["step_px"] == step])
                    for step in sorted({r["step_px"] for r in rows})}  # fmt: skip
        print(
            f"{run.variant} seed {run.seed}: photo videos mean {mean:+.2f} dB, lowest "
            f"{worst['gain_db']:+.2f} dB ({worst['photo']}, {worst['step_px']} px); by speed "
            + ", ".join(f"{step} px: {gain:+.2f}" for step, gain in by_speed.items())
        )

    if args.photo_videos:  # the videos photo_mix trained on: how well each network fits them
        videos = photo_training_videos(args.photo_videos, seed=0)
        gains["photo_training"] = {}
        for run in runs:
            gain = photo_training_gain(run.folder, videos)
            gains["photo_training"].setdefault(run.variant, {})[run.seed] = gain

    table = []
    for test, by_network in gains.items():
        for name, by_seed in by_network.items():
            print(
                f"{test:14s} {name:11s} "
                + ", ".join(f"seed {s}: {g:+.2f} dB" for s, g in by_seed.items())
            )
        rows = ablation_intervals(by_network, dict.fromkeys(by_network, parameters),
                                  reference="standin", below="lower than the stand-in alone",
                                  above="higher than the stand-in alone")  # fmt: skip
        table += [{"test_set": test, **{key: round(row[key], 3)
                                        if isinstance(row.get(key), float) else row.get(key, "")
                                        for key in INTERVAL_COLUMNS}}
                  for row in rows]  # fmt: skip
    saved = save_benchmark_tables(
        "train_blur_range-" + "-".join(list(training)[1:]),
        {"gains": table},
        args.out_dir,
        "Video network trained on the stand-in alone or with more data",
        notes=f"Networks {', '.join(training)}; {args.steps} steps, seeds {args.seeds}, first "
        f"{args.frames} frames of every test sequence: PSNR gain over the blurred input (dB, "
        "mean, min and max over seeds) and the paired difference to the stand-in-only network "
        "with its 95 % t-interval.",
    )
    print(saved.markdown.read_text())


if __name__ == "__main__":
    main()
