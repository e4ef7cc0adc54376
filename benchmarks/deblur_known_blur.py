"""What does the video network lack on the stand-in's blur? The network trained and scored on
the stand-in's sharp frames under four blurs, from the render's own camera blur to one line for
every frame, all without sensor noise.

    blurloc synth --out data/standin-noise0 --frames 200 --noise 0
    python benchmarks/deblur_known_blur.py --root data/standin-noise0 [--seeds 0 1 2 3]
        [--steps 1200] [--frames 100] [--out build/known_blur] [--workers 2]
        [--blurs rendered warped "recorded lines" "one line"] [--versus OTHER_OUT]
        [--out-dir figures]

On a stand-in rendered without noise (see ``train_without_noise.py``), the full network of
notebook 03 gains about as much as one linear filter for all frames, while a filter fitted to
each frame's own blur gains far more. Four blurs of the same sharp frames, each one step
simpler than the one before, tell apart what the network lacks:

- ``rendered``: the render's blurred frames, the task the network fails at. Each is the
  average of a few renders along the camera's path over the exposure (:func:`~blurloc.data.
  synth.render_exposure`): every render rasterises the scene's edges and picks its texture
  detail anew, and surfaces hidden at mid-exposure may show;
- ``warped``: the same camera blur made from the sharp frame alone (:func:`warped_blur`): it
  varies across the frame with depth and position as the render's does, but it is a linear
  function of the sharp frame's pixels;
- ``recorded lines``: each sharp frame convolved with a straight line of its frame's recorded
  blur (``blur.csv``: the mean path length and the dominant direction), uniform over the frame:
  the frame-to-frame changes of length and direction remain;
- ``one line``: every sharp frame convolved with one horizontal line of the median recorded
  length of the training frames (horizontal: the trainer's mirror flips leave it unchanged), a
  blur the network never has to find.

The line blurs are applied to the 8-bit sharp frames (eq. 1 without noise, mirrored borders)
and rounded back to 8 bits. Every arm trains the same network (``VideoTrainConfig`` with
``--steps`` steps, validated every 100 on the last 15 % of one training sequence per scene,
in ``--workers`` one-thread processes) once per seed, and is scored on the first ``--frames``
frames of every test sequence under its own blur (mean of the per-scene means; frames that
equal their sharp frame under any blur are left out of all). Printed: each arm's gain per
seed, the paired difference of each arm to the one before with its 95 % t-interval, and for
every blur the gains of two 9 x 9 linear filters (one learned on the arm's training frames,
one fitted to each test frame's own top half: see ``linear_deblur_bounds.py``).

The tables go to ``<out-dir>/deblur_known_blur.md`` with one CSV each: ``deblur_known_blur.csv``
(gain per arm and seed), ``deblur_known_blur-steps.csv`` (each arm minus the one before),
``deblur_known_blur-linear_filters.csv`` and, with ``--versus``, ``deblur_known_blur-versus.csv``.
Each arm's gain per seed is also written to ``--out``/``gains.csv``. ``--versus`` names another
run's ``--out`` (on another render of the same scenes and camera paths, e.g. one made with ``blurloc
synth --supersample 3``): every arm that both runs hold, and every step from one such arm to the
next, is then compared across the two renders, paired by seed, with its 95 % t-interval.

Finished trainings in ``--out`` are reused (``train_without_noise.py``'s ``clean-seed<n>``
runs are the ``rendered`` arm's: copy them to ``rendered-seed<n>``); one made with other
settings is refused.
"""

from __future__ import annotations

import argparse
import csv
import functools
import itertools
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
from linear_deblur_bounds import filter_gains, fit_global_filter, print_gains
from scipy.ndimage import map_coordinates

from blurloc.blur import blur_image, motion_kernel
from blurloc.config import write_rows
from blurloc.data import SequenceFrames, list_scenes, load_split
from blurloc.data.render import Scene
from blurloc.data.sevenscenes import read_depth
from blurloc.data.stats import read_blur_metadata
from blurloc.data.synth import HandheldTrajectory, SynthConfig, exposure_tracks, sequence_trajectory
from blurloc.experiments.deblurring import per_scene_means
from blurloc.experiments.video_ablation import INTERVAL_COLUMNS, ablation_intervals
from blurloc.experiments.wiener_oracles import standin_settings
from blurloc.geometry import intrinsics
from blurloc.images import as_float_image, linear_to_srgb, srgb_to_linear
from blurloc.inference import DEFAULT_CHECKPOINT, VideoRestorer
from blurloc.metrics import psnr
from blurloc.models.video_deblur import VideoDeblurNet, parameter_count
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import VideoTrainConfig
from blurloc.train.loop import parallel_map, validation_cut
from blurloc.train.video import Video, train_video_deblur

BLURS = ("rendered", "warped", "recorded lines", "one line")


def blur_maker(root: str, blur: str) -> Callable[[str, SequenceFrames, tuple[int, ...]], Video]:
    """A function of (scene, sequence, frame ids) giving those frames' (blurred, sharp) uint8
    video under one of :data:`BLURS`."""
    records = {(r["scene"], r["sequence"], r["frame"]): r for r in read_blur_metadata(root)}
    config, seed = standin_settings(root)
    one_line = motion_kernel(float(np.median([r["mean_px"] for r in records.values()
                                              if r["split"] == "train"])), 0.0)  # fmt: skip

    def video(scene: str, sequence: SequenceFrames, frames: tuple[int, ...]) -> Video:
        sharp = sequence.images("sharp", frames)
        if blur == "rendered":
            return sequence.images("color", frames), sharp
        if blur == "warped":
            world, trajectory = sequence_trajectory(scene, sequence.number, config, seed)
            blurred = [warped_blur(image, read_depth(sequence.path(frame, "depth")), world,
                                   trajectory, frame / config.fps, config,
                                   records[(scene, sequence.number, frame)]["samples"])
                       for frame, image in zip(frames, sharp, strict=True)]  # fmt: skip
            return np.stack(blurred), sharp
        kernels = [one_line if blur == "one line" else
                   motion_kernel(records[(scene, sequence.number, frame)]["mean_px"],
                                 records[(scene, sequence.number, frame)]["angle_deg"])
                   for frame in frames]  # fmt: skip
        blurred = [np.clip(np.rint(255 * blur_image(image, kernel)), 0, 255)
                   for image, kernel in zip(sharp, kernels, strict=True)]  # fmt: skip
        return np.stack(blurred).astype(np.uint8), sharp

    return video


@functools.cache
def training_videos(root: str, blur: str) -> dict[str, list[Video]]:
    """The stand-in's training videos under one of :data:`BLURS`, split as the video trainer
    splits them: ``train`` (each training sequence before its validation part) and
    ``validation`` (the validation part of the first training sequence of each scene). Read
    once per process."""
    video = blur_maker(root, blur)
    splits: dict[str, list[Video]] = {"train": [], "validation": []}
    for scene in list_scenes(root):
        for number, sequence in enumerate(load_split(root, scene, "train")):
            frames = sequence.frame_ids
            cut = len(frames) - validation_cut(len(frames))
            splits["train"].append(video(scene, sequence, frames[:cut]))
            if number == 0:
                splits["validation"].append(video(scene, sequence, frames[cut:]))
    return splits


@functools.cache
def test_videos(root: str, blur: str, frames: int) -> list[tuple[str, Video]]:
    """(scene, (blurred, sharp)) for the first ``frames`` frames of every test sequence under one
    of :data:`BLURS`. Read once per process."""
    video = blur_maker(root, blur)
    return [(scene, video(scene, sequence, sequence.frame_ids[:frames]))
            for scene in list_scenes(root)
            for sequence in load_split(root, scene, "test")]  # fmt: skip


def warped_blur(
    sharp: np.ndarray,
    depth: np.ndarray,
    world: Scene,
    trajectory: HandheldTrajectory,
    time_s: float,
    config: SynthConfig,
    samples: int,
) -> np.ndarray:
    """The camera's blur of one frame made from its sharp render alone: the sharp frame moved
    by each pixel's own image motion at the render's ``samples`` instants of the exposure
    (:func:`~blurloc.data.synth.render_exposure`'s midpoint rule) and averaged in linear light.

    The motion is that of the scene points seen on a grid at mid-exposure
    (:func:`~blurloc.data.synth.exposure_tracks`, from the frame's depth and the camera's
    path), interpolated to every pixel; the frame seen at an instant is the sharp frame
    sampled (bilinearly, mirrored at the borders) where each pixel's point was at mid-exposure.
    So the blur varies over the frame with depth and position as the render's does, at the
    same instants, but it is a linear function of the sharp frame's pixels: nothing is seen
    that the sharp frame does not show (no surface uncovered, no edge rasterised anew, no
    texture detail chosen anew).
    """
    height, width = depth.shape
    surface = np.where(depth > 0, depth, np.median(depth[depth > 0]))
    camera = intrinsics(config.width, config.height)
    step = max(1, min(width, height) // 16)  # a grid point every 7 px at 160x120
    # the midpoint rule's instants: evenly spaced over (samples - 1) / samples of the exposure
    span = replace(config, blur_strength=config.blur_strength * (samples - 1) / samples)
    tracks = exposure_tracks(world, trajectory, time_s, span, camera, surface, grid_step=step,
                             samples=samples)  # fmt: skip
    rows, columns = len(range(step // 2, height, step)), len(range(step // 2, width, step))
    motion = (tracks - tracks[samples // 2]).reshape(samples, rows, columns, 2)
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    grid = [(y - step // 2) / step, (x - step // 2) / step]
    light = srgb_to_linear(as_float_image(sharp)).astype(np.float32)
    total = np.zeros_like(light)
    for moved in motion:
        dx, dy = (map_coordinates(moved[..., axis], grid, order=1, mode="nearest")
                  for axis in (0, 1))  # fmt: skip
        total += cv2.remap(light, (x - dx).astype(np.float32), (y - dy).astype(np.float32),
                           cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT_101)  # fmt: skip
    return np.clip(np.rint(255 * linear_to_srgb(total / samples)), 0, 255).astype(np.uint8)


def train_one(job: tuple) -> Path:
    """Train (or reuse) one arm's network for one seed; returns its ``best.pt``."""
    root, blur, config, folder = job
    train_video_deblur(training_videos(root, blur), folder, config, progress=False)
    return folder / "best.pt"


def score_one(job: tuple) -> list[dict]:
    """Per-frame PSNR rows of one network (or of the blurred input, ``checkpoint`` None) on one
    arm's test videos."""
    root, blur, frames, method, checkpoint = job
    restore = np.asarray if checkpoint is None else VideoRestorer(checkpoint)
    rows = []
    for scene, (blurred, sharp) in test_videos(root, blur, frames):
        restored = restore(blurred)
        rows += [{"blur": blur, "method": method, "scene": scene, "index": len(rows) + k,
                  "psnr_db": psnr(truth, frame, 255.0)}
                 for k, (frame, truth) in enumerate(zip(restored, sharp, strict=True))]  # fmt: skip
    return rows


def compare_runs(
    gains: dict[str, dict[int, float]], versus: str, root: str, parameters: int
) -> list[dict]:
    """Print and return, for each arm both runs hold and for each step from one such arm to the next
    (e.g. ``warped - rendered``), its value in this run minus that in the run whose ``--out``
    is ``versus``, paired by seed, with its 95 % t-interval."""
    other: dict[str, dict[int, float]] = {}
    with open(Path(versus) / "gains.csv", newline="") as handle:
        for row in csv.DictReader(handle):
            other.setdefault(row["blur"], {})[int(row["seed"])] = float(row["gain_db"])
    arms = [blur for blur in BLURS if blur in gains and blur in other]
    runs = {versus: other, root: gains}
    quantities = {name: {run: by_blur[name] for run, by_blur in runs.items()} for name in arms}
    for first, second in itertools.pairwise(arms):
        quantities[f"{second} - {first}"] = {
            run: {seed: by_blur[second][seed] - by_blur[first][seed]
                  for seed in by_blur[first] if seed in by_blur[second]}
            for run, by_blur in runs.items()}  # fmt: skip
    compared = []
    for name, by_run in quantities.items():
        seeds = sorted(set(by_run[versus]) & set(by_run[root]))
        pair = {run: {seed: values[seed] for seed in seeds} for run, values in by_run.items()}
        table = ablation_intervals(pair, dict.fromkeys(pair, parameters), reference=versus,
                                   below=f"less on {root}", above=f"more on {root}")  # fmt: skip
        print(f"\n{name}, {root} minus {versus} (dB, paired by seed):")
        for row in table:
            rounded = {key: round(value, 3) if isinstance(value, float) else value
                       for key, value in row.items()}  # fmt: skip
            print(rounded)
            compared.append({"quantity": name, **rounded})
    return compared


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="a stand-in rendered with --noise 0")
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2, 3])
    parser.add_argument("--steps", type=int, default=1200)
    parser.add_argument("--frames", type=int, default=100, help="test frames per sequence")
    parser.add_argument("--out", default="build/known_blur")
    parser.add_argument("--workers", type=int, default=2, help="processes that work at once")
    parser.add_argument("--blurs", nargs="+", choices=BLURS, default=list(BLURS),
                        help="the arms to run (default: all four)")  # fmt: skip
    parser.add_argument("--versus", help="another run's --out, compared arm by arm and seed")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    blurs = [blur for blur in BLURS if blur in args.blurs]
    if len(args.seeds) < 2:
        parser.error("--seeds: at least two, for a paired interval")
    if args.versus and not (Path(args.versus) / "gains.csv").is_file():
        parser.error(f"--versus: {args.versus} holds no gains.csv (run this script there first)")

    budget = VideoTrainConfig(steps=args.steps, validate_every=100, threads=1)
    jobs = [(args.root, blur, replace(budget, seed=seed),
             Path(args.out) / f"{blur.replace(' ', '_')}-seed{seed}")
            for blur in blurs for seed in args.seeds]  # fmt: skip
    started = time.perf_counter()
    checkpoints = list(parallel_map(train_one, jobs, args.workers))
    seconds = time.perf_counter() - started
    scoring = [(args.root, blur, args.frames, "blurred", None) for blur in blurs]
    scoring += [(args.root, blur, args.frames, "shipped", DEFAULT_CHECKPOINT) for blur in blurs]
    scoring += [(args.root, job[1], args.frames, f"seed{job[2].seed}", checkpoint)
                for job, checkpoint in zip(jobs, checkpoints, strict=True)]  # fmt: skip
    rows = [row for rows in parallel_map(score_one, scoring, args.workers) for row in rows]
    unblurred = {row["index"] for row in rows
                 if row["method"] == "blurred" and np.isinf(row["psnr_db"])}  # fmt: skip
    print(f"{len(unblurred)} test frames left out: under some blur they equal their sharp frame")
    gains: dict[str, dict[int, float]] = {}
    for blur in blurs:
        means = {method: value["mean"] for method, value in per_scene_means(
            [row for row in rows if row["blur"] == blur and row["index"] not in unblurred],
            "psnr_db").items()}  # fmt: skip
        gains[blur] = {seed: means[f"seed{seed}"] - means["blurred"] for seed in args.seeds}
        print(f"\n{blur}: blurred input {means['blurred']:.2f} dB; shipped checkpoint "
              f"{means['shipped'] - means['blurred']:+.2f} dB; trained "
              + ", ".join(f"seed {s}: {g:+.2f} dB" for s, g in gains[blur].items()))  # fmt: skip
    write_rows([{"blur": blur, "seed": seed, "gain_db": gain} for blur, by_seed in gains.items()
                for seed, gain in by_seed.items()], Path(args.out) / "gains.csv")  # fmt: skip
    parameters = dict.fromkeys(blurs, parameter_count(VideoDeblurNet()))
    tables = {
        "per seed": [{"blur": blur, "seed": seed, "gain_db": round(gain, 3)}
                     for blur, by_seed in gains.items() for seed, gain in by_seed.items()],
        "steps": [],
        "linear filters": [],
    }  # fmt: skip
    if args.versus:
        tables["versus"] = compare_runs(gains, args.versus, args.root, parameters[blurs[0]])
    for reference, other in itertools.pairwise(blurs):  # each arm to the one before
        intervals = ablation_intervals({name: gains[name] for name in (reference, other)},
                                       parameters, reference=reference,
                                       below=f"gains less than under {reference}",
                                       above=f"gains more than under {reference}")  # fmt: skip
        table = [{key: round(row[key], 3) if isinstance(row.get(key), float) else row.get(key, "")
                  for key in INTERVAL_COLUMNS} for row in intervals]  # fmt: skip
        tables["steps"] += [{"step": f"{other} vs {reference}", **row} for row in table]
        for row in table:
            print(f"{other} vs {reference}: {row}")
    print(f"({seconds:.0f} s of training; steps {args.steps}, seeds {args.seeds}, first "
          f"{args.frames} frames of every test sequence)")  # fmt: skip
    for blur in blurs:
        training = (
            (blurred / 255, sharp / 255)
            for pair in training_videos(args.root, blur)["train"]
            for blurred, sharp in zip(*(part[:170:10] for part in pair), strict=True)
        )
        test = (
            (blurred / 255, sharp / 255)
            for _, pair in test_videos(args.root, blur, args.frames)
            for blurred, sharp in zip(*(part[::5] for part in pair), strict=True)
        )
        gains_linear = filter_gains(test, fit_global_filter(training, 9), 9)
        print(f"{blur}: 9 x 9 linear filters, bottom halves of {len(gains_linear['global'])} "
              f"test frames:")  # fmt: skip
        tables["linear filters"] += [{"blur": blur, **row} for row in print_gains(gains_linear)]
    if not tables["steps"]:
        del tables["steps"]  # one arm only: nothing to pair
    saved = save_benchmark_tables(
        "deblur_known_blur",
        tables,
        args.out_dir,
        "Video network trained and scored under four blurs of the same sharp frames",
        notes=f"{seconds:.0f} s of training; steps {args.steps}, seeds {args.seeds}, first "
        f"{args.frames} frames of every test sequence of {args.root}; {len(unblurred)} frames "
        "left out (equal to their sharp frame under some blur). Gains in dB over each blur's "
        "input; 95 % t-intervals paired by seed. Linear filters: 9 x 9, scored on the bottom "
        "halves of every fifth test frame.",
    )
    print(f"wrote {saved.markdown}")


if __name__ == "__main__":
    main()
