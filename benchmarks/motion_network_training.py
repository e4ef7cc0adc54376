"""The recurrent network after the deconvolution by the video's own motion: shipped as it is
(trained on blurred frames), or trained on deconvolved frames?

    python benchmarks/motion_network_training.py --standin data/standin
        --clean-standin data/standin-clean-s8 [--seeds 0 1 2] [--steps 1200]
        [--train-frames 40] [--photo-videos 14] [--test-frames 50] [--workers 2]
        [--out build/motion_network] [--out-dir figures]

The paper's shipped network (:data:`~blurloc.inference.DEFAULT_CHECKPOINT`) learnt to restore
blurred frames; run over frames that the deconvolution
(:func:`~blurloc.video_wiener.deblur_video_motion`, the share read from each video) has already
restored, it sees inputs it never learnt. Here the same network (eq. 8-11, the shipped settings,
:class:`~blurloc.models.video_deblur.VideoDeblurConfig`) is trained, once per ``--seeds``, for
``--steps`` steps on what it then sees: deconvolved frames, against the sharp ones, so its
residual reconstruction (eq. 11) starts from the deconvolution (a Wiener step before a learnt
refinement, as in Dong, Roth and Schiele's deep Wiener deconvolution, NeurIPS 2020).

Training videos (every one deconvolved as in use): the first ``--train-frames`` frames of every
training sequence of ``--standin`` (as rendered, with the camera model's noise) and of
``--clean-standin`` (rendered without noise), and ``--photo-videos`` GoPro-style videos of
training photographs (:func:`~blurloc.experiments.photo_video.photo_training_videos`, 12 frames)
without noise and as many with sigma = 0.01. Validation: the next 20 frames of the first training
sequence of every scene of both stand-ins and 2 + 2 more photo videos. Test sets, never trained
or validated on: the first ``--test-frames`` frames of every test sequence of both stand-ins,
against the sharp renders, and the 15 test photo videos (8 frames; photographs not trained on)
without noise and with sigma = 0.01.

Arms, each scored on the same videos: ``motion alone`` (the deconvolution), ``shipped after
motion`` (the paper's shipped network over the deconvolved frames), ``retrained after motion`` (the
network trained here, one per seed; the method's own shipped checkpoint,
:data:`~blurloc.inference.MOTION_CHECKPOINT`, is this recipe at the full budget) and ``shipped
alone`` (the network on the blurred frames). A video's gain: its mean per-frame PSNR (eq. 6) minus
its blurred frames'. Per arm and test set: the mean gain over videos (seed by seed for the
retrained arm: mean, min and max over seeds), the worst video; paired rows: ``retrained after
motion`` minus each other arm, per seed (a t-interval over the seeds' mean gains) and per video
(seeds averaged; a t-interval over the videos). Writes
``<out-dir>/motion_network_training.md``/``.csv`` (``-pairs.csv``; ``-videos.csv``: each video's
gain per arm, seeds averaged). Finished trainings in ``--out`` are reused.
"""

from __future__ import annotations

import argparse
import pickle
import time
from pathlib import Path

import numpy as np
import torch

from blurloc.data import list_scenes, load_split
from blurloc.experiments.photo_video import photo_training_videos, photo_video_set
from blurloc.inference import DEFAULT_CHECKPOINT, VideoRestorer
from blurloc.intervals import paired_interval
from blurloc.metrics import mean_frame_psnr
from blurloc.models.video_deblur import VideoDeblurConfig
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import VideoTrainConfig
from blurloc.train.loop import parallel_map
from blurloc.train.video import train_video_deblur
from blurloc.video_wiener import deblur_video_motion

#: Frames after the training frames of each scene's first training sequence, for validation.
VALIDATION_FRAMES = 20
#: Photo-video seeds (photo_training_videos): training without and with noise, validation.
PHOTO_SEEDS = {"train 0": 0, "train 0.01": 2, "validation": 3}
RETRAINED = "retrained after motion"
OTHER_ARMS = ("motion alone", "shipped after motion", "shipped alone")

#: A video: blurred frames, their deconvolution and the sharp frames (uint8 (T, H, W, 3)).
Video = tuple[np.ndarray, np.ndarray, np.ndarray]


def deconvolved(blurred: np.ndarray, sharp: np.ndarray) -> Video:
    """The video with its deconvolution by its own motion (share read from it), as in use."""
    return blurred, deblur_video_motion(blurred, None), sharp


def standin_part(root: Path, split: str, start: int, frames: int, first_only: bool) -> list:
    """(label, blurred, sharp) for frames ``start`` to ``start + frames`` of every ``split``
    sequence under ``root`` (of each scene's first only, with ``first_only``)."""
    videos = []
    for scene in list_scenes(root):
        sequences = load_split(root, scene, split)
        for sequence in sequences[:1] if first_only else sequences:
            ids = sequence.frame_ids[start : start + frames]
            if len(ids) < 2:  # a sequence too short for this part (the stand-in's stairs)
                continue
            label = f"{root.name} {scene} {sequence.folder.name}"
            videos.append((label, sequence.images("color", ids), sequence.images("sharp", ids)))
    return videos


def training_data(args: argparse.Namespace) -> dict[str, list[Video]]:
    """The deconvolved training and validation videos (module docstring)."""
    train, validation = [], []
    for root in (args.standin, args.clean_standin):
        train += [deconvolved(b, s) for _, b, s in
                  standin_part(root, "train", 0, args.train_frames, first_only=False)]  # fmt: skip
        validation += [deconvolved(b, s) for _, b, s in standin_part(
            root, "train", args.train_frames, VALIDATION_FRAMES, first_only=True)]  # fmt: skip
    for noise, seed in ((0.0, PHOTO_SEEDS["train 0"]), (0.01, PHOTO_SEEDS["train 0.01"])):
        photos = photo_training_videos(args.photo_videos, seed=seed, noise_sigma=noise)
        train += [deconvolved(b, s) for b, s in photos]
        validation += [deconvolved(b, s) for b, s in
                       photo_training_videos(2, seed=PHOTO_SEEDS["validation"],
                                             noise_sigma=noise)]  # fmt: skip
    return {"train": train, "validation": validation}


def train_one(job: tuple) -> Path:
    """Train (or reuse) the network on deconvolved frames for one seed; its ``best.pt``."""
    data_path, out, steps, seed = job
    with open(data_path, "rb") as handle:
        data = pickle.load(handle)
    splits = {name: [(restored, sharp) for _, restored, sharp in videos]
              for name, videos in data.items()}  # fmt: skip
    config = VideoTrainConfig(steps=steps, validate_every=max(1, steps // 4), threads=1,
                              seed=seed, device="cpu", model=VideoDeblurConfig())  # fmt: skip
    folder = Path(out) / f"retrained-seed{seed}"
    torch.set_num_threads(1)
    train_video_deblur(splits, folder, config, progress=False)
    return folder / "best.pt"


def test_sets(args: argparse.Namespace) -> dict[str, list[tuple[str, Video]]]:
    """The scored videos, deconvolved once (module docstring)."""
    sets = {}
    for name, root in (("stand-in as rendered (noisy)", args.standin),
                       ("stand-in without noise", args.clean_standin)):  # fmt: skip
        videos = standin_part(root, "test", 0, args.test_frames, first_only=False)
        sets[name] = [(label, deconvolved(b, s)) for label, b, s in videos]
    for noise in (0.0, 0.01):
        sets[f"photo videos, sigma {noise}"] = [
            (f"{video.photo} {video.step_px} px", deconvolved(video.blurred, video.sharp))
            for video in photo_video_set(8, noise_sigma=noise)]  # fmt: skip
    return sets


def gain(output: np.ndarray, blurred: np.ndarray, sharp: np.ndarray) -> float:
    """Mean per-frame PSNR of ``output`` minus that of ``blurred`` (dB)."""
    return mean_frame_psnr([(output, sharp)]) - mean_frame_psnr([(blurred, sharp)])


def main() -> None:
    """Deconvolve, train, score, write the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--standin", type=Path, required=True)
    parser.add_argument("--clean-standin", type=Path, required=True)
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    parser.add_argument("--steps", type=int, default=1200)
    parser.add_argument("--train-frames", type=int, default=40)
    parser.add_argument("--photo-videos", type=int, default=14)
    parser.add_argument("--test-frames", type=int, default=50)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=Path("build/motion_network"))
    add_out_dir_argument(parser)
    args = parser.parse_args()
    start = time.perf_counter()
    args.out.mkdir(parents=True, exist_ok=True)
    data_path = args.out / "training_videos.pkl"
    if not data_path.exists():
        data = training_data(args)
        with open(data_path.with_suffix(".tmp"), "wb") as handle:
            pickle.dump(data, handle)
        data_path.with_suffix(".tmp").rename(data_path)
    print(f"training videos ready after {time.perf_counter() - start:.0f} s", flush=True)
    jobs = [(data_path, args.out, args.steps, seed) for seed in args.seeds]
    checkpoints = list(parallel_map(train_one, jobs, workers=args.workers))
    print(f"trained after {time.perf_counter() - start:.0f} s", flush=True)
    torch.set_num_threads(2)
    shipped = VideoRestorer(DEFAULT_CHECKPOINT)
    retrained = [VideoRestorer(checkpoint) for checkpoint in checkpoints]
    summary, pairs, video_rows = [], [], []
    for set_name, videos in test_sets(args).items():
        gains = {arm: [] for arm in OTHER_ARMS}
        per_seed = np.zeros((len(args.seeds), len(videos)))
        for index, (label, (blurred, restored, sharp)) in enumerate(videos):
            gains["motion alone"].append(gain(restored, blurred, sharp))
            gains["shipped after motion"].append(gain(shipped(restored), blurred, sharp))
            gains["shipped alone"].append(gain(shipped(blurred), blurred, sharp))
            for seed_index, network in enumerate(retrained):
                per_seed[seed_index, index] = gain(network(restored), blurred, sharp)
            video_rows += [
                {"set": set_name, "video": label, "arm": arm, "gain_db": round(values[-1], 3)}
                for arm, values in gains.items()
            ]
            video_rows.append({"set": set_name, "video": label, "arm": RETRAINED,
                               "gain_db": round(float(per_seed[:, index].mean()), 3)})  # fmt: skip
        seed_means, video_means = per_seed.mean(axis=1), per_seed.mean(axis=0)
        summary.append({"set": set_name, "arm": RETRAINED, "videos": len(videos),
                        "seeds": len(args.seeds),
                        "mean_gain_db": round(float(seed_means.mean()), 3),
                        "seed_min_db": round(float(seed_means.min()), 3),
                        "seed_max_db": round(float(seed_means.max()), 3),
                        "worst_video_db": round(float(video_means.min()), 3)})  # fmt: skip
        for arm, values in gains.items():
            summary.append(
                {
                    "set": set_name,
                    "arm": arm,
                    "videos": len(videos),
                    "seeds": "",
                    "mean_gain_db": round(float(np.mean(values)), 3),
                    "seed_min_db": "",
                    "seed_max_db": "",
                    "worst_video_db": round(float(np.min(values)), 3),
                }
            )
            over_seeds = paired_interval(seed_means - np.mean(values), method="t")
            over_videos = paired_interval(video_means - np.array(values), method="t")
            pairs.append({"set": set_name, "difference": f"{RETRAINED} - {arm}",
                          "mean_db": round(over_videos.mean, 3),
                          "over_seeds_95": f"[{over_seeds.low:+.3f}, {over_seeds.high:+.3f}]",
                          "over_videos_95": f"[{over_videos.low:+.3f}, {over_videos.high:+.3f}]",
                          "verdict": verdict(over_seeds.low, over_seeds.high)})  # fmt: skip
        print(set_name, [(row["arm"], row["mean_gain_db"]) for row in summary[-4:]], flush=True)
    notes = (
        f"Seeds {args.seeds}, {args.steps} steps per training (one thread, {args.workers} "
        f"processes); {args.train_frames} training frames per training sequence of "
        f"{args.standin} and {args.clean_standin}, {args.photo_videos} photo training "
        f"videos per noise level; first {args.test_frames} frames of every test sequence; "
        "gains: mean per-frame PSNR minus the blurred frames', dB; verdict from the "
        f"interval over seeds. {time.perf_counter() - start:.0f} s on 2 CPU cores."
    )
    saved = save_benchmark_tables("motion_network_training",
                                  {"gains": summary, "pairs": pairs, "videos": video_rows},
                                  args.out_dir, notes=notes)  # fmt: skip
    print(f"tables: {saved}")


def verdict(low: float, high: float) -> str:
    """The retrained arm against another, worded from the interval of their difference."""
    if low > 0:
        return "retrained higher"
    if high < 0:
        return "retrained lower"
    return f"not resolved (±{(high - low) / 2:.2f} dB)"


if __name__ == "__main__":
    main()
