"""Does telling the video network each frame's blur make it deblur? The recurrent network
(eq. 8-11) as shipped, beside the same network conditioned on each frame's blur
(``blur_condition``): once on the package's blind estimate, once on the true blur; and beside
the network that reads each frame's blind Wiener copy (``wiener_input``) made with the gradient
regulariser; and beside the network that reads each frame deconvolved with the kernel of its own
motion in the video.

    python benchmarks/deblur_conditioned.py --root data/standin [--seeds 0 1 2]
        [--steps 1200] [--train-frames 200] [--photo-videos 14] [--test-frames 50]
        [--photo-frames 8] [--arms plain estimated told] [--workers 2]
        [--out build/conditioned] [--out-dir figures] [--stem deblur_conditioned]

On line blur the network gains much more when every frame carries one blur it never has to
find than when each frame carries its own (``deblur_known_blur.py``). Conditioning hands it
each frame's blur as three numbers (:func:`~blurloc.models.video_deblur.blur_descriptor`) that
scale and shift its features. Arms, one network each per seed, at one budget:

- ``plain``: the shipped settings (:class:`~blurloc.models.video_deblur.VideoDeblurConfig`);
- ``estimated``: ``blur_condition``, told each frame's blind estimate (length and angle of a
  line, :func:`~blurloc.blur.estimate_motion_blur`), in training and in use: the method;
- ``told``: ``blur_condition``, trained and scored with each frame's true line (an oracle: the
  upper bound of what conditioning can give; validation, which picks the kept network, reads
  blind estimates);
- ``wiener``: ``wiener_input`` with ``wiener_gradient``: the encoder reads each
  frame beside its blind Wiener deconvolution by the estimated line, with the NSR that keeps the
  mean (:func:`~blurloc.models.video_deblur.wiener_guides`): a deconvolution step before the
  recurrent refinement, told nothing;
- ``motion``: ``wiener_input`` with ``wiener_motion``: the Wiener copies are made with the
  kernel of each frame's exposure path, measured from the video's own motion between frames
  (:func:`~blurloc.models.video_deblur.motion_guides`). Its tables add the Wiener step alone
  (``motion Wiener alone``, :func:`~blurloc.video_wiener.deblur_video_motion`, no network) and
  the network's paired difference to it, so that what the recurrent refinement adds to its
  Wiener step is measured.

``--arms`` picks them (default: the first three; ``plain`` always runs).

Training mix, without any sensor noise (the test of blur removal, not of denoising): the first
``--train-frames`` frames of every training sequence of the stand-in under ``root``, each sharp
render convolved with a straight line of its frame's recorded length and direction
(``blur.csv``: eq. 1 without noise, on the 8-bit frames, rounded back), and ``--photo-videos``
GoPro-style videos from photographs (:func:`~blurloc.experiments.photo_video.
photo_training_videos`, noise 0; their true line: :func:`~blurloc.experiments.photo_video.
photo_training_lines`). Validation: the next 30 frames of the first training sequence of every
scene and 2 more photo videos. Each training: ``VideoTrainConfig`` with ``--steps`` steps, one
thread, in ``--workers`` processes.

Scored (PSNR, eq. 6, against the sharp frames; a video's gain is its mean per-frame PSNR
minus its blurred frames'): the first ``--test-frames`` frames of every test sequence under
its recorded lines, no noise; the same frames as rendered (the stand-in's own blur and sensor
noise: outside the training's domain; the told arm reads the recorded lines, which only
approximate the rendered blur); the photo-video set without noise (5 photographs never trained
on x 3 pan speeds; the told arm reads the line of the pan, which leaves out its wobble and so
is far from the true blur on slow pans: :func:`~blurloc.experiments.photo_video.
photo_training_lines`); and the real GoPro blurred/sharp pair of the
development set (a 3-frame video of the blurred photograph, the last frame scored; no true
line, so the told arm reads the estimate there). Per arm and seed the mean gain over the
videos; each conditioned arm minus ``plain``, paired by seed, with its 95 % t-interval
(:func:`~blurloc.experiments.video_ablation.ablation_intervals`).

Writes ``<out-dir>/<stem>.md`` (``--stem``, default ``deblur_conditioned``) with
``<stem>.csv`` (gain per test set, arm and seed), ``-versus_plain.csv`` (the paired
differences), ``-videos.csv`` (each video's gain, seeds averaged) and ``-network.csv``
(parameters and frames per second at 160x120, blur estimate and Wiener copies included); with
the motion arm also ``-motion_network_versus_its_Wiener_step.csv``. Finished trainings in
``--out`` are reused.
"""

from __future__ import annotations

import argparse
import functools
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import torch
from deblur_known_blur import blur_maker

from blurloc.data import list_scenes, load_split
from blurloc.data.real import load_pairs
from blurloc.data.stats import read_blur_metadata
from blurloc.experiments.photo_video import (
    photo_training_lines,
    photo_training_videos,
    photo_video_set,
)
from blurloc.experiments.video_ablation import INTERVAL_COLUMNS, ablation_intervals
from blurloc.inference import frames_from_tensor, load_video_deblur, to_tensor
from blurloc.metrics import psnr
from blurloc.models.video_deblur import (
    VideoDeblurConfig,
    VideoDeblurNet,
    blur_descriptor,
    parameter_count,
)
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import VideoTrainConfig
from blurloc.train.loop import parallel_map
from blurloc.train.video import train_video_deblur
from blurloc.video_wiener import deblur_video_motion

#: Arm -> (network settings, whether it reads the true blur).
ARMS = {
    "plain": (VideoDeblurConfig(), False),
    "estimated": (VideoDeblurConfig(blur_condition=True), False),
    "told": (VideoDeblurConfig(blur_condition=True), True),
    "wiener": (VideoDeblurConfig(wiener_input=True, wiener_gradient=True), False),
    "motion": (VideoDeblurConfig(wiener_input=True, wiener_motion=True), False),
}
#: The motion arm's Wiener step without the network, scored beside it.
MOTION_WIENER = "motion Wiener alone"
#: Sub-frames of a photo video (:func:`~blurloc.experiments.photo_video.photo_video`'s default).
SUBFRAMES = 9
VALIDATION_FRAMES = 30

#: A test or training video: blurred, sharp (uint8 (T, H, W, 3)) and the true descriptors
#: ((T, 3), or None where the true blur is not known).
Video = tuple[np.ndarray, np.ndarray, np.ndarray | None]


def true_descriptors(lines: list[tuple[float, float]]) -> np.ndarray:
    """(T, 3) descriptors of each frame's true line (length px, angle degrees)."""
    return np.stack([blur_descriptor(length, angle) for length, angle in lines])


@functools.cache
def standin_videos(root: str, split: str, start: int, frames: int, blur: str) -> list[Video]:
    """Frames ``start`` to ``start + frames`` of every ``split`` sequence (``train``: of the
    first training sequence of each scene only when ``start`` > 0, the validation part) under
    ``blur`` (``recorded lines`` or ``rendered``), with their recorded lines' descriptors."""
    make = blur_maker(root, blur)
    records = {(r["scene"], r["sequence"], r["frame"]): r for r in read_blur_metadata(root)}
    videos = []
    for scene in list_scenes(root):
        sequences = load_split(root, scene, split)
        for sequence in sequences[:1] if start > 0 else sequences:
            ids = sequence.frame_ids[start : start + frames]
            blurred, sharp = make(scene, sequence, ids)
            lines = [(records[(scene, sequence.number, i)]["mean_px"],
                      records[(scene, sequence.number, i)]["angle_deg"]) for i in ids]  # fmt: skip
            videos.append((blurred, sharp, true_descriptors(lines)))
    return videos


def training_splits(args: argparse.Namespace, told: bool) -> dict[str, list[tuple]]:
    """The training mix (module docstring); with ``told`` each training video carries its true
    descriptors, which the trainer then feeds instead of the blind estimates."""
    train = standin_videos(args.root, "train", 0, args.train_frames, "recorded lines")
    validation = standin_videos(args.root, "train", args.train_frames, VALIDATION_FRAMES,
                                "recorded lines")  # fmt: skip
    photos = photo_training_videos(args.photo_videos, seed=0, noise_sigma=0.0)
    lines = photo_training_lines(args.photo_videos, seed=0)
    train = list(train) + [
        (blurred, sharp, true_descriptors([line] * len(blurred)))
        for (blurred, sharp), line in zip(photos, lines, strict=True)
    ]
    validation = list(validation) + [(b, s, None) for b, s in
                                     photo_training_videos(2, seed=1, noise_sigma=0.0)]  # fmt: skip
    return {"train": [(b, s, d) if told else (b, s) for b, s, d in train],
            "validation": [(b, s) for b, s, _ in validation]}  # fmt: skip


def train_one(job: tuple) -> Path:
    """Train (or reuse) one arm's network for one seed; returns its ``best.pt``."""
    args, arm, seed = job
    model, told = ARMS[arm]
    config = VideoTrainConfig(steps=args.steps, validate_every=max(1, args.steps // 4), threads=1,
                              seed=seed, device="cpu", model=model)  # fmt: skip
    folder = Path(args.out) / f"{arm}-seed{seed}"
    torch.set_num_threads(1)
    train_video_deblur(training_splits(args, told), folder, config, progress=False)
    return folder / "best.pt"


@functools.cache
def test_sets(root: str, test_frames: int, photo_frames: int) -> dict[str, list[Video]]:
    """The scored videos per test set (module docstring)."""
    sets = {
        "stand-in, line blur, no noise": standin_videos(root, "test", 0, test_frames,
                                                         "recorded lines"),
        "stand-in as rendered (noisy)": standin_videos(root, "test", 0, test_frames, "rendered"),
    }  # fmt: skip
    sets["photo videos, no noise"] = [
        (video.blurred, video.sharp,
         true_descriptors([(SUBFRAMES * video.step_px, (-video.angle_deg) % 180.0)] * photo_frames))
        for video in photo_video_set(photo_frames, noise_sigma=0.0)
    ]  # fmt: skip
    sets["real GoPro pair"] = [(np.stack([blurred] * 3), np.stack([sharp] * 3), None)
                               for _, blurred, sharp in load_pairs()]  # fmt: skip
    return sets


def restore(model: VideoDeblurNet, blurred: np.ndarray, blur: np.ndarray | None) -> np.ndarray:
    """A whole video restored in one pass; ``blur`` the descriptors to feed (None: the
    network's own, blind estimates for a conditioned network)."""
    with torch.no_grad():
        told = None if blur is None else torch.from_numpy(blur)[None]
        restored, _ = model(to_tensor(blurred)[None], blur=told)
    return frames_from_tensor(restored[0])


def video_gains(job: tuple) -> dict[str, list[float]]:
    """Per test set, each video's gain (dB) of one arm's network (or the shipped one)."""
    args, arm, checkpoint = job
    torch.set_num_threads(1)
    model = load_video_deblur(checkpoint)
    told = arm in ARMS and ARMS[arm][1]
    return test_set_gains(args, lambda blurred, blur: restore(model, blurred,
                                                              blur if told else None))  # fmt: skip


def motion_wiener_gains(args: argparse.Namespace) -> dict[str, list[float]]:
    """Per test set, each video's gain (dB) of the motion arm's Wiener step alone."""
    return test_set_gains(args, lambda blurred, _: deblur_video_motion(blurred))


def test_set_gains(
    args: argparse.Namespace, restorer: Callable[[np.ndarray, np.ndarray | None], np.ndarray]
) -> dict[str, list[float]]:
    """Per test set, each video's gain (dB): the mean PSNR of ``restorer(blurred, blur)``
    minus the blurred frames' (the real pair's last frame alone)."""
    gains = {}
    for name, videos in test_sets(args.root, args.test_frames, args.photo_frames).items():
        last = slice(-1, None) if name == "real GoPro pair" else slice(None)
        gains[name] = []
        for blurred, sharp, blur in videos:
            output = restorer(blurred, blur)
            before = [psnr(s, b, 255.0) for b, s in zip(blurred[last], sharp[last], strict=True)]
            after = [psnr(s, o, 255.0) for o, s in zip(output[last], sharp[last], strict=True)]
            gains[name].append(float(np.mean(after) - np.mean(before)))
    return gains


def throughput(model: VideoDeblurNet, frames: int = 60) -> float:
    """Frames per second at 160x120 on 2 threads over a random video (blind estimates
    included), after a warm-up."""
    video = (np.random.default_rng(0).random((frames, 120, 160, 3)) * 255).astype(np.uint8)
    torch.set_num_threads(2)
    restore(model, video[:4], None)
    start = time.perf_counter()
    for chunk in range(0, frames, 20):
        restore(model, video[chunk : chunk + 20], None)
    return frames / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="a stand-in (its sharp renders and blur.csv)")
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    parser.add_argument("--steps", type=int, default=1200)
    parser.add_argument("--train-frames", type=int, default=200,
                        help="training frames per training sequence")  # fmt: skip
    parser.add_argument("--photo-videos", type=int, default=14)
    parser.add_argument("--test-frames", type=int, default=50)
    parser.add_argument("--photo-frames", type=int, default=8)
    parser.add_argument("--arms", nargs="+", choices=list(ARMS),
                        default=["plain", "estimated", "told"],
                        help="the arms to run (plain always)")  # fmt: skip
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default="build/conditioned", help="training runs")
    parser.add_argument("--stem", default="deblur_conditioned",
                        help="name of the tables written")  # fmt: skip
    add_out_dir_argument(parser)
    args = parser.parse_args()
    if len(args.seeds) < 2:
        parser.error("--seeds: at least two, for a paired interval")

    arms = [arm for arm in ARMS if arm == "plain" or arm in args.arms]
    jobs = [(args, arm, seed) for seed in args.seeds for arm in arms]
    started = time.perf_counter()
    checkpoints = dict(zip([(arm, seed) for _, arm, seed in jobs],
                           parallel_map(train_one, jobs, args.workers), strict=True))  # fmt: skip
    print(f"{time.perf_counter() - started:.0f} s of training")
    scoring = [(args, arm, checkpoints[(arm, seed)]) for arm in arms for seed in args.seeds]
    results = list(parallel_map(video_gains, scoring, args.workers))
    by_arm: dict[str, dict[str, dict[int, list[float]]]] = {}
    for (_, arm, checkpoint), gains in zip(scoring, results, strict=True):
        seed = int(checkpoint.parent.name.rsplit("seed", 1)[1])
        for name, values in gains.items():
            by_arm.setdefault(name, {}).setdefault(arm, {})[seed] = values
    if "motion" in arms:  # deterministic: the same gains stand beside every seed
        for name, values in motion_wiener_gains(args).items():
            by_arm[name][MOTION_WIENER] = {seed: values for seed in args.seeds}

    parameters = {arm: parameter_count(VideoDeblurNet(ARMS[arm][0])) for arm in arms}
    parameters[MOTION_WIENER] = 0
    gain_rows, versus_rows, video_rows, step_rows = [], [], [], []
    for name, scored in by_arm.items():
        means = {arm: {seed: float(np.mean(v)) for seed, v in seeds.items()}
                 for arm, seeds in scored.items()}  # fmt: skip
        for arm, seeds in scored.items():
            gain_rows += [{"test_set": name, "arm": arm, "seed": seed, "videos": len(values),
                           "gain_db": round(means[arm][seed], 3),
                           "worst_video_gain_db": round(min(values), 3)}
                          for seed, values in seeds.items()]  # fmt: skip
            per_video = np.mean([seeds[seed] for seed in args.seeds], axis=0)
            video_rows += [{"test_set": name, "arm": arm, "video": index, "gain_db": round(g, 3)}
                           for index, g in enumerate(per_video)]  # fmt: skip
        networks = {arm: seeds for arm, seeds in means.items() if arm != MOTION_WIENER}
        table = ablation_intervals(networks, parameters, reference="plain",
                                   below="gains less than plain",
                                   above="gains more than plain")  # fmt: skip
        versus_rows += [{"test_set": name, **_rounded(row)} for row in table]
        if MOTION_WIENER in means:
            steps = {arm: means[arm] for arm in (MOTION_WIENER, "motion")}
            table = ablation_intervals(steps, parameters, reference=MOTION_WIENER,
                                       below="the network loses to its Wiener step",
                                       above="the network adds to its Wiener step")  # fmt: skip
            step_rows += [{"test_set": name, **_rounded(row)} for row in table]
        print(name, versus_rows[-1], step_rows[-1:] if step_rows else "")

    network_rows = []
    for arm in [arm for arm in ("plain", "estimated", "wiener", "motion") if arm in arms]:
        model = load_video_deblur(checkpoints[(arm, args.seeds[0])])
        network_rows.append({"arm": arm, "parameters": parameter_count(model),
                             "frames_per_s_2_threads": round(throughput(model), 1)})  # fmt: skip
        print(network_rows[-1])
    notes = (f"Settings: root {args.root}, seeds {args.seeds}, {args.steps} steps per training "
             f"(one thread), {args.train_frames} line-blurred training frames per training "
             f"sequence and {args.photo_videos} noise-free photo training videos; first "
             f"{args.test_frames} frames of every test sequence, {args.photo_frames} frames per "
             "photo video. Gains: a video's mean per-frame PSNR minus its blurred frames', dB, "
             "averaged over the videos of a set; versus plain: paired by seed, 95 % t-interval. "
             "Throughput on a shared 2-core machine.")  # fmt: skip
    tables = {"gains": gain_rows, "versus plain": versus_rows, "videos": video_rows,
              "network": network_rows}  # fmt: skip
    if step_rows:
        tables["motion network versus its Wiener step"] = step_rows
    save_benchmark_tables(args.stem, tables, args.out_dir, notes=notes,
                          title="The video network told each frame's blur: blind estimate and "
                                "true line, beside the shipped settings")  # fmt: skip


def _rounded(row: dict) -> dict:
    """An interval row's columns (:data:`INTERVAL_COLUMNS`), floats to 3 decimals."""
    return {key: round(row[key], 3) if isinstance(row.get(key), float) else row.get(key, "")
            for key in INTERVAL_COLUMNS}  # fmt: skip


if __name__ == "__main__":
    main()
