"""Where the video network's gain lies: variants of it trained with one budget over several
seeds, scored on the stand-in's test sequences, with the paired difference to the first variant.

    python benchmarks/ablate_video_deblur.py --root data/standin [--variants full half_resolution]
        [--seeds 0 1 2] [--steps 400 [1600]] [--frames 100] [--out build/video_ablation]
        [--workers 2] [--out-dir figures]

Each variant is trained like notebook 03's ablations (``VideoTrainConfig`` with
``--steps`` optimiser steps, on the first 250 frames of every training sequence, validated
every 100 steps on the end of one whole training sequence per scene, in ``--workers``
one-thread processes), once per seed and per training length (labelled
``<variant>@<steps>``), and scored on the first ``--frames`` frames of every test sequence (PSNR
against the sharp renders; mean of the per-scene means). Printed: each variant's gain over the
blurred input per seed, and a table of its parameter count, its mean and spread over seeds and
its paired difference to the reference (the first variant at the first training length; same
seeds) with a 95 % t-interval; last, per run, the step whose network was scored (``best.pt``:
the best validation) and how far the recurrent state of the network at the end of training
(``last.pt``) grows over the longest test sequence. Finished trainings in ``--out`` are reused;
one made with other settings is refused (runs from before bounded recurrent states became the
package's default among them: the old ``full`` runs are this script's ``unbounded``; delete or
move them).
Variants: notebook 03's four at equal parameter count (``full``, ``no_aux``, ``no_blending``,
``single_frame``; with the package's default, bounded states, as in notebook 03),
``half_resolution`` (features at half instead of quarter resolution) and ``wide`` (48 channels,
hidden state 32), which change the capacity on purpose, and ``aligned`` (the full network whose
recurrent states follow the image: moved by the frame-to-frame translation,
``VideoDeblurConfig(align=True)``; no extra parameters) and ``unbounded`` (the full network
without the tanh on its hidden and auxiliary states, ``VideoDeblurConfig(bounded_state=False)``:
the default until the shipped checkpoint was trained with bounded states; no extra parameters).
Trainings are kept in ``--out``; the tables go to ``<out-dir>/ablate_video_deblur.md`` with one CSV
each: ``ablate_video_deblur.csv`` (the intervals), ``ablate_video_deblur-per_seed.csv`` and
``ablate_video_deblur-runs.csv`` (best step, largest state).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch

from blurloc.data import list_scenes, load_split
from blurloc.experiments.video_ablation import (
    INTERVAL_COLUMNS,
    ablation_gains,
    ablation_intervals,
    equal_parameter_variants,
    train_ablations,
)
from blurloc.inference import load_video_deblur, to_tensor
from blurloc.models.video_deblur import (
    VideoDeblurConfig,
    VideoDeblurNet,
    frame_translation,
    parameter_count,
)
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import VideoTrainConfig

VARIANTS = {
    **equal_parameter_variants(),
    "half_resolution": VideoDeblurConfig(feature_stride=2),
    "wide": VideoDeblurConfig(channels=48, hidden=32),
    "aligned": VideoDeblurConfig(align=True),
    "unbounded": VideoDeblurConfig(bounded_state=False),
}


def frame_shifts(root: str, frames: int) -> np.ndarray:
    """Frame-to-frame image translation (px, :func:`frame_translation`) over the first
    ``frames`` frames of every test sequence: how far an ``aligned`` network moves its states
    (in feature pixels: divided by the feature stride)."""
    shifts = []
    for scene in list_scenes(root):
        for sequence in load_split(root, scene, "test"):
            part = sequence.first(frames)
            video = to_tensor(part.images())
            shifts.append(frame_translation(video[:-1], video[1:]).norm(dim=1).numpy())
    return np.concatenate(shifts)


def largest_state(checkpoint: Path, video: torch.Tensor) -> float:
    """Largest magnitude of the hidden state of eq. 8 while a network restores ``video``
    ((T, 3, H, W) in [-1, 1]) frame by frame; ``inf`` once it overflows or turns NaN."""
    model = load_video_deblur(checkpoint)
    state, largest = None, 0.0
    with torch.inference_mode():
        for frame in video:
            _, state = model(frame[None, None], state)
            largest = max(largest, float(torch.nan_to_num(state[0], nan=np.inf).abs().max()))
    return largest


def longest_test_video(root: str, frames: int) -> torch.Tensor:
    """The first ``frames`` frames of the stand-in's longest test sequence, as a tensor."""
    sequence = max((s for scene in list_scenes(root) for s in load_split(root, scene, "test")),
                   key=len).first(frames)  # fmt: skip
    return to_tensor(sequence.images())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="stand-in root (needs sharp frames)")
    parser.add_argument("--variants", nargs="+", default=["full", "half_resolution"],
                        choices=sorted(VARIANTS))  # fmt: skip
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    parser.add_argument("--steps", nargs="+", type=int, default=[400],
                        help="training lengths; every variant is trained with each")  # fmt: skip
    parser.add_argument("--frames", type=int, default=100, help="test frames per sequence")
    parser.add_argument("--out", default="build/video_ablation")
    parser.add_argument("--workers", type=int, default=2, help="processes that train at once")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    if len(args.seeds) < 2:
        parser.error("--seeds: at least two, for a paired interval")

    variants = {name: VARIANTS[name] for name in args.variants}
    started, runs, parameters = time.perf_counter(), [], {}
    for steps in args.steps:
        budget = VideoTrainConfig(steps=steps, validate_every=100)
        trained = train_ablations(args.root, variants, args.seeds, budget,
                                  f"{args.out}/steps{steps}", frames_per_sequence=250,
                                  workers=args.workers, validation_per_scene=1)  # fmt: skip
        for run in trained:  # variants labelled with their training length
            label = f"{run.variant}@{steps}"
            runs.append(replace(run, variant=label))
            parameters[label] = parameter_count(VideoDeblurNet(variants[run.variant]))
    seconds = time.perf_counter() - started
    gains, _ = ablation_gains(args.root, runs, frames_per_sequence=args.frames,
                              workers=args.workers)  # fmt: skip
    for name, by_seed in gains.items():
        print(f"{name:20s} " + ", ".join(f"seed {s}: {g:+.2f} dB" for s, g in by_seed.items()))
    intervals = ablation_intervals(
        gains,
        parameters,
        reference=runs[0].variant,
        below="below the reference",
        above="above the reference",
    )
    rows = [{key: round(row[key], 3) if isinstance(row.get(key), float) else row.get(key, "")
             for key in INTERVAL_COLUMNS} for row in intervals]  # fmt: skip
    print(f"\nsteps {args.steps}, seeds {args.seeds}, first {args.frames} frames of every test "
          f"sequence ({seconds:.0f} s of training); gains over the blurred input, dB:")  # fmt: skip
    tables = {
        "variants": rows,
        "per seed": [{"variant": name, "seed": seed, "gain_db": round(gain, 3)}
                     for name, by_seed in gains.items() for seed, gain in by_seed.items()],
        "runs": [],
    }  # fmt: skip
    video = longest_test_video(args.root, args.frames)
    print(
        f"per run: the step of the scored network (best validation) and the largest |hidden "
        f"state| of the network at the end of training over {len(video)} test frames:"
    )
    for run in runs:
        best_step = run.history["step"][int(np.argmax(run.history["val_psnr"]))]
        state = largest_state(run.folder / "last.pt", video)
        print(
            f"  {run.variant:20s} seed {run.seed}: best at step {best_step}, largest state "
            f"{state:.3g}"
        )
        tables["runs"].append({"variant": run.variant, "seed": run.seed, "best_step": best_step,
                               "largest_state": float(f"{state:.4g}")})  # fmt: skip
    if "aligned" in variants:
        shifts = frame_shifts(args.root, args.frames)
        print(
            f"frame-to-frame translation on the scored test frames ({shifts.size} pairs): "
            f"median {np.median(shifts):.2f} px, 90th percentile "
            f"{np.percentile(shifts, 90):.2f} px; the recurrent states move by these divided by "
            f"the feature stride ({VARIANTS['aligned'].feature_stride})"
        )
    saved = save_benchmark_tables(
        "ablate_video_deblur",
        tables,
        args.out_dir,
        "Video network variants: gains over the blurred input and paired differences",
        notes=f"Steps {args.steps}, seeds {args.seeds}, first {args.frames} frames of every test "
        f"sequence of {args.root} ({seconds:.0f} s of training); dB; 95 % t-intervals paired by "
        f"seed against {runs[0].variant}.",
    )
    print(saved.markdown.read_text())


if __name__ == "__main__":
    main()
