"""Does the video network remove blur, not only noise? The project's deblurring targets, measured
side by side for the shipped network, the Wiener copy alone, the network retrained on blur that
can be restored, and the network with a Wiener step before it (``wiener_input``).

    blurloc synth --out data/standin-s60-clean --frames 60 --shot-noise 0 --read-noise 0
    blurloc synth --out data/standin-s60 --frames 60
    python benchmarks/bench_deblur_targets.py --clean-root data/standin-s60-clean
        --noisy-root data/standin-s60 [--seeds 0 1] [--steps 1200] [--photo-videos 14]
        [--test-frames 20] [--photo-frames 8] [--stability-frames 600] [--threads 1]
        [--out results/deblur_targets] [--out-dir figures]

The two stand-ins are rendered from the same seed and camera paths, one without sensor noise
(``--shot-noise 0 --read-noise 0``; JPEG is off by default), one with the default camera model.
Arms, each scored on the same frames:

- ``shipped``: the shipped network (``src/blurloc/weights/video_deblur.pt``);
- ``wiener only``: each frame's blind Wiener copy
  (:func:`~blurloc.models.video_deblur.wiener_guides`: the conditioning alone);
- ``retrained``: the network of the shipped settings, trained here once per ``--seeds`` on the
  training mix below;
- ``wiener input``: the same network with ``wiener_input`` (eq. 8-11 fed the frame and its
  Wiener copy), trained on the same mix with the same seeds and steps.

Each training is :class:`~blurloc.train.config.VideoTrainConfig` with ``--steps`` steps, validated
twice (halfway and at the end). Training mix (every video drawn equally often): the training
sequences of both stand-ins (the ends of the first training sequence of each scene for validation),
plus ``--photo-videos`` GoPro-style videos from photographs with sensor noise 0.01 and as many
without noise (:func:`~blurloc.experiments.photo_video.photo_training_videos`: photographs disjoint
from the scored photo-video set), with 2 + 2 more for validation. Trainings in ``--out`` are reused
when finished (resumed when not).

Scored (PSNR, eq. 6, against the sharp frames): the first ``--test-frames`` frames of every test
sequence of each stand-in; the photo-video set without noise (5 photographs never trained on x
3 pan speeds, ``--photo-frames`` frames each); the real GoPro blurred/sharp pair (the blurred
photograph repeated as a 3-frame video, the last frame scored, at its own size). A seeded arm's
per-frame PSNR is the mean over its seeds. Gains are per-frame PSNR minus the blurred frame's;
intervals are 95 % t-intervals over videos (each video's mean per-frame difference: frames of
one video are not independent), paired because every arm restores the same frames. Stability:
the ``wiener input`` network (first seed) and the shipped network run over the first
``--stability-frames`` frames of the real 160x120 recording (its sequences in order, one
continuous video); the mean absolute change they make
to the frames (0-255) over the last 100 frames against the first 100 is printed.

Writes ``<out-dir>/bench_deblur_targets.md`` and ``.csv`` (gain per arm and test set) with
``-comparisons.csv`` (paired differences between arms), ``-per_seed.csv``,
``-photo_videos.csv`` (each photo video's gain) and ``-network.csv`` (parameters, frames per
second at 160x120, stability).
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import skimage.data
import torch

from blurloc.data.frames import list_frames, read_frames
from blurloc.data.real import load_pairs, recording_root
from blurloc.experiments.photo_video import (
    PHOTO_VIDEO_PHOTOS,
    PHOTO_VIDEO_SPEEDS,
    photo_training_videos,
    photo_video,
)
from blurloc.inference import (
    DEFAULT_CHECKPOINT,
    load_video_deblur,
    restore_sequence,
    to_tensor,
    to_uint8,
)
from blurloc.intervals import paired_interval, verdict
from blurloc.metrics import psnr
from blurloc.models.video_deblur import VideoDeblurConfig, parameter_count, wiener_guides
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import VideoTrainConfig
from blurloc.train.video import Video, load_video_splits, train_video_deblur

Restore = Callable[[np.ndarray], np.ndarray]
#: The arms trained here, with the network settings each trains.
TRAINED = {"retrained": VideoDeblurConfig(), "wiener input": VideoDeblurConfig(wiener_input=True)}
#: Targets of the project per test set (gain of the mean PSNR, dB).
TARGETS = {"stand-in, no noise": 2.0, "stand-in, noisy": 3.0, "photo videos, no noise": 2.0,
           "real GoPro pair": 0.0}  # fmt: skip


def training_mix(clean_root: str, noisy_root: str, photo_videos: int) -> dict[str, list[Video]]:
    """Training and validation videos: both stand-ins and photo videos with and without noise."""
    splits: dict[str, list[Video]] = {"train": [], "validation": []}
    for root in (clean_root, noisy_root):
        part = load_video_splits(root, with_test=False, validation_per_scene=1)
        splits["train"] += part["train"]
        splits["validation"] += part["validation"]
    for noise, (train_seed, validation_seed) in ((0.01, (0, 1)), (0.0, (2, 3))):
        splits["train"] += photo_training_videos(photo_videos, seed=train_seed, noise_sigma=noise)
        splits["validation"] += photo_training_videos(2, seed=validation_seed, noise_sigma=noise)
    return splits


def test_sets(args: argparse.Namespace) -> dict[str, list[Video]]:
    """The scored videos per test set (see the module's docstring)."""
    sets = {}
    for name, root in (("stand-in, no noise", args.clean_root),
                       ("stand-in, noisy", args.noisy_root)):  # fmt: skip
        sets[name] = load_video_splits(root, frames_per_sequence=args.test_frames)["test"]
    sets["photo videos, no noise"] = [
        photo_video(getattr(skimage.data, photo)(), args.photo_frames, step_px=step,
                    angle_deg=37.0 * index, noise_sigma=0.0, seed=index)
        for index, photo in enumerate(PHOTO_VIDEO_PHOTOS) for step in PHOTO_VIDEO_SPEEDS
    ]  # fmt: skip
    sets["real GoPro pair"] = [(np.stack([blurred] * 3), np.stack([sharp] * 3))
                               for _, blurred, sharp in load_pairs()]  # fmt: skip
    return sets


def frame_psnrs(restore: Restore | None, videos: list[Video], last_only: bool) -> list[np.ndarray]:
    """Per-frame PSNR of each video restored (``None``: the blurred frames themselves)."""
    scores = []
    for blurred, sharp in videos:
        output = blurred if restore is None else restore(blurred)
        values = np.array([psnr(s, o, 255.0) for o, s in zip(output, sharp, strict=True)])
        scores.append(values[-1:] if last_only else values)
    return scores


def network_restorer(path: str | Path) -> Restore:
    """The network of a checkpoint as a function of a uint8 video."""
    model = load_video_deblur(path)
    return lambda blurred: restore_sequence(model, blurred)


def wiener_only(blurred: np.ndarray) -> np.ndarray:
    """Each frame's blind Wiener copy (the conditioning alone)."""
    return to_uint8(wiener_guides(to_tensor(blurred)[None])[0])


def interval_text(per_video: list[float]) -> tuple[str, str]:
    """Mean [95 % t-interval] of per-video values and its verdict (> 0 claimed)."""
    if len(per_video) < 2:
        return f"{np.mean(per_video):+.2f} (one video: no interval)", ""
    interval = paired_interval(np.array(per_video), method="t")
    return (f"{interval.mean:+.2f} [{interval.low:+.2f}, {interval.high:+.2f}]",
            verdict(interval, claimed_sign=1))  # fmt: skip


def change_per_frame(restore: Restore, frames: np.ndarray) -> np.ndarray:
    """Mean absolute change (0-255) the restorer makes to each frame of a long video."""
    output = restore(frames)
    return np.abs(output.astype(np.float32) - frames.astype(np.float32)).mean(axis=(1, 2, 3))


def throughput(restore: Restore, threads: int, frames: int = 100) -> float:
    """Frames per second at 160x120 over a random video, after a warm-up."""
    video = (np.random.default_rng(0).random((frames, 120, 160, 3)) * 255).astype(np.uint8)
    previous = torch.get_num_threads()
    torch.set_num_threads(threads)
    restore(video[:8])
    start = time.perf_counter()
    restore(video)
    torch.set_num_threads(previous)
    return frames / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clean-root", required=True, help="stand-in rendered without noise")
    parser.add_argument("--noisy-root", required=True, help="the same stand-in with noise")
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1])
    parser.add_argument("--steps", type=int, default=1200)
    parser.add_argument("--photo-videos", type=int, default=14,
                        help="photo training videos per noise level")  # fmt: skip
    parser.add_argument("--test-frames", type=int, default=20)
    parser.add_argument("--photo-frames", type=int, default=8)
    parser.add_argument("--stability-frames", type=int, default=600)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--out", default="results/deblur_targets", help="training runs")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    torch.set_num_threads(args.threads)

    splits = training_mix(args.clean_root, args.noisy_root, args.photo_videos)
    print(f"training mix: {len(splits['train'])} videos, "
          f"{sum(len(b) for b, _ in splits['train'])} frames")  # fmt: skip
    checkpoints: dict[str, list[Path]] = {}
    for seed in args.seeds:  # seed by seed: a paired pair of networks at a time
        for arm, model in TRAINED.items():
            folder = Path(args.out) / f"{arm.replace(' ', '_')}-seed{seed}"
            config = VideoTrainConfig(steps=args.steps, seed=seed, threads=args.threads,
                                      validate_every=max(1, args.steps // 2), device="cpu",
                                      model=model)  # fmt: skip
            started = time.perf_counter()
            history = train_video_deblur(splits, folder, config, progress=False)
            print(f"{arm} seed {seed}: best validation {max(history['val_psnr']):.2f} dB, "
                  f"{history['seconds'][-1]:.0f} s training "
                  f"({time.perf_counter() - started:.0f} s this call)")  # fmt: skip
            checkpoints.setdefault(arm, []).append(folder / "best.pt")

    arms: dict[str, list[Restore]] = {"shipped": [network_restorer(DEFAULT_CHECKPOINT)],
                                      "wiener only": [wiener_only]}  # fmt: skip
    arms |= {arm: [network_restorer(path) for path in paths] for arm, paths in checkpoints.items()}
    gain_rows, seed_rows, comparison_rows, photo_rows = [], [], [], []
    for set_name, videos in test_sets(args).items():
        last_only = set_name == "real GoPro pair"
        blurred = frame_psnrs(None, videos, last_only)
        blurred_mean = float(np.mean(np.concatenate(blurred)))
        scores = {}
        for arm, restorers in arms.items():
            per_seed = [frame_psnrs(restore, videos, last_only) for restore in restorers]
            scores[arm] = [np.mean(runs, axis=0) for runs in zip(*per_seed, strict=True)]
            seeds = args.seeds if arm in TRAINED else [None]
            seed_rows += [{"test_set": set_name, "arm": arm, "seed": seed,
                           "gain_db": round(float(np.mean(np.concatenate(runs))) - blurred_mean, 3)}
                          for seed, runs in zip(seeds, per_seed, strict=True)]  # fmt: skip
            gains = [float(np.mean(a - b)) for a, b in zip(scores[arm], blurred, strict=True)]
            mean_gain = float(np.mean(np.concatenate(scores[arm]))) - blurred_mean
            text, _ = interval_text(gains)
            target = TARGETS[set_name]
            met = mean_gain > target and (set_name != "photo videos, no noise" or min(gains) >= 0)
            gain_rows.append({"test_set": set_name, "arm": arm, "videos": len(videos),
                              "frames": int(sum(len(b) for b in blurred)),
                              "blurred_psnr_db": round(blurred_mean, 2),
                              "gain_db": round(mean_gain, 3), "gain_per_video_95": text,
                              "worst_video_gain_db": round(min(gains), 3),
                              "target_db": f">= {target:+.0f}" if target else "> 0",
                              "met": met})  # fmt: skip
            print(f"{set_name:24s} {arm:14s} gain {mean_gain:+.2f} dB  per video {text}")
            if set_name == "photo videos, no noise":
                names = [(photo, step) for photo in PHOTO_VIDEO_PHOTOS
                         for step in PHOTO_VIDEO_SPEEDS]  # fmt: skip
                photo_rows += [
                    {"arm": arm, "photo": photo, "step_px": step, "gain_db": round(gain, 3)}
                    for (photo, step), gain in zip(names, gains, strict=True)
                ]
        for other in ("shipped", "wiener only", "retrained"):
            pairs = zip(scores["wiener input"], scores[other], strict=True)
            text, said = interval_text([float(np.mean(a - b)) for a, b in pairs])
            comparison_rows.append({"test_set": set_name,
                                    "difference": f"wiener input - {other}",
                                    "mean_db_95": text,
                                    "verdict (wiener input higher)": said})  # fmt: skip
            print(f"{set_name:24s} wiener input - {other}: {text} {said}")

    network_rows = []
    recording = [path for folder in sorted(recording_root().glob("*/seq-*"))
                 for path in list_frames(folder)][: args.stability_frames]  # fmt: skip
    frames = np.stack(list(read_frames(recording)))
    for arm, restore in (("shipped", arms["shipped"][0]),
                         ("wiener input", arms["wiener input"][0])):  # fmt: skip
        model = load_video_deblur(DEFAULT_CHECKPOINT if arm == "shipped"
                                  else checkpoints["wiener input"][0])  # fmt: skip
        change = change_per_frame(restore, frames)
        row = {"arm": arm, "parameters": parameter_count(model),
               "frames_per_s_1_thread": round(throughput(restore, 1), 1),
               "frames_per_s_2_threads": round(throughput(restore, 2), 1),
               "stability_frames": len(frames),
               "change_first_100": round(float(change[:100].mean()), 3),
               "change_last_100": round(float(change[-100:].mean()), 3),
               "finite": bool(np.isfinite(change).all())}  # fmt: skip
        network_rows.append(row)
        print(row)
    notes = (f"Settings: seeds {args.seeds}, {args.steps} steps per training, "
             f"{args.photo_videos} photo training videos per noise level, first "
             f"{args.test_frames} frames of every test sequence, {args.photo_frames} frames per "
             f"photo video, {args.threads} torch thread(s). Gains: mean per-frame PSNR minus the "
             "blurred frames', dB; intervals: 95 % t over videos (per-video mean differences); "
             "seeded arms: per-frame PSNR averaged over seeds. Throughput measured on a shared "
             "2-core machine (other jobs running).")  # fmt: skip
    tables = {"gains": gain_rows, "comparisons": comparison_rows, "per seed": seed_rows,
              "photo videos": photo_rows, "network": network_rows}  # fmt: skip
    title = ("Deblurring targets: shipped network, Wiener copy, retrained network and "
             "Wiener-conditioned network")  # fmt: skip
    save_benchmark_tables("bench_deblur_targets", tables, args.out_dir, title=title, notes=notes)


if __name__ == "__main__":
    main()
