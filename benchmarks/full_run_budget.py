"""How long a full ``make reproduce`` takes on this machine: its heavy units timed here, times
how many the run makes, beside the stage times of the last full run.

    python benchmarks/full_run_budget.py [--data data/standin] [--out build/full_run_budget]
        [--out-dir figures]

Each unit is timed with the notebooks' own functions and settings, two one-thread worker
processes at once, as the run does (about 7 minutes on 2 cores):

1. rendering: the heads scene of the stand-in (2,000 frames) rendered again, frames/s;
2. video-network ablation trainings: two of notebook 03's trainings (400 steps, validated at
   200 and 400), side by side;
3. scoring a trained network on the first 100 frames of every test sequence (notebook 03);
4. network-deblurred and blind-Wiener copies of the heads scene, frames/s;
5. pose trainings: four of notebook 04's (chess, LSTM and single-frame heads, 2 seeds each).

Units 2-5 include starting their processes and reading their frames, which the run does once
per worker and group rather than per unit, so the projection errs long. Stages not timed here
(notebooks 00-02 and 05, notebook 03's evaluation and figures) are taken at their last full
run's times. The projection is given for the run as the notebooks define it and for the
smallest run the method's comparisons need (3 seeds per video ablation, the minimum for a
t-interval; 3 seeds per blur strength in the dose-response; the pose matrix unchanged: 7
scenes x 5 seeds x 5 inputs and heads). Target: 150 minutes on 2 cores.

Writes ``<out-dir>/full_run_budget.md``/``.csv`` (seconds per stage: the last full run's, the
projection here, the smallest run's) and ``full_run_budget-units.csv`` (the timed units).
"""

from __future__ import annotations

import argparse
import shutil
import time
from collections.abc import Callable
from pathlib import Path

from blurloc.data.synth import SynthConfig, synthesize
from blurloc.experiments import video_ablation
from blurloc.experiments.pose import run_pose_matrix
from blurloc.experiments.video import wiener_sequence, write_deblurred_root
from blurloc.inference import DEFAULT_CHECKPOINT, VideoRestorer
from blurloc.models.video_deblur import VideoDeblurConfig
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import PoseTrainConfig, VideoTrainConfig

#: Stage times (s) of the last full run (docs/reproduction.md, "Full reproduction: time per
#: notebook"; 2 cores): the render; from notebook 03's printed lines and cell durations, its
#: ablation trainings, their scoring, the two copies and the rest (2,290 s in all); notebooks
#: 04 and 06; notebooks 00-02 and 05.
REFERENCE = {"render": 703, "ablation trainings": 1470, "ablation scoring": 170,
             "Wiener copy": 80, "network copy": 350, "notebook 03, the rest": 220,
             "pose matrix (notebook 04)": 1197, "dose-response (notebook 06)": 839,
             "notebooks 00-02 and 05": 302}  # fmt: skip
STANDIN_FRAMES = 43_000
DOSE_FRAMES = 4 * 3_000  # chess at four exposures, 500 frames per sequence, rendered and copied
POSE_TRAININGS = 7 * 5 * 5  # notebook 04: scenes x seeds x (4 inputs + the single-frame head)
#: (video ablation trainings, dose-response pose trainings): as the notebooks run them (4
#: variants x 3 seeds; 4 strengths x 2 inputs x 5 seeds), and with 3 seeds each.
AS_RUN, SMALLEST = (12, 40), (12, 24)


def timed(action: Callable[[], object]) -> tuple[float, object]:
    """Wall-clock seconds of ``action()``, and what it returned."""
    started = time.perf_counter()
    result = action()
    return time.perf_counter() - started, result


def measure_units(data: Path, out: Path) -> dict[str, float]:
    """Seconds per unit: a rendered or copied frame, an ablation training, a network scored, a
    pose training (the last three two at a time, as in the run)."""
    heads = out / "heads-root"
    heads.mkdir(parents=True, exist_ok=True)
    if not (heads / "heads").exists():
        (heads / "heads").symlink_to((data / "heads").resolve())
    heads_frames = sum(1 for _ in (data / "heads").glob("seq-*/*.color.png"))
    seconds, _ = timed(lambda: synthesize(out / "render", scenes=["heads"], progress=False,
                                          config=SynthConfig(), overwrite=True))  # fmt: skip
    units = {"render": seconds / heads_frames}
    print(f"render: {1 / units['render']:.1f} frames/s")
    variants = video_ablation.equal_parameter_variants(VideoDeblurConfig(bounded_state=True))
    pair = {name: variants[name] for name in ("full", "single_frame")}
    budget = VideoTrainConfig(steps=400, validate_every=200, device="cpu")  # notebook 03's
    seconds, runs = timed(
        lambda: video_ablation.train_ablations(
            data, pair, [0], budget, out / "ablations", 250, workers=2, validation_per_scene=1
        )
    )
    units["ablation training"] = seconds / 2
    print(f"ablation training: {units['ablation training']:.0f} s (two at a time)")
    seconds, _ = timed(lambda: video_ablation.ablation_gains(data, runs, "cpu", 100, workers=2))
    units["ablation scoring"] = seconds / 2
    print(f"scoring one network: {units['ablation scoring']:.0f} s")
    for name, method in (("network copy", VideoRestorer(DEFAULT_CHECKPOINT, "cpu")),
                         ("Wiener copy", wiener_sequence)):  # fmt: skip
        copy = out / name.replace(" ", "-")
        seconds, _ = timed(lambda m=method, c=copy: write_deblurred_root(heads, c, m, workers=2))
        units[name] = seconds / heads_frames
        print(f"{name}: {1 / units[name]:.1f} frames/s")
    trainings = [("blurred", "lstm"), ("blurred", "none")]
    seconds, _ = timed(lambda: run_pose_matrix(
        {"blurred": data}, ["chess"], trainings, PoseTrainConfig(device="cpu"), out / "pose",
        (0, 1), workers=2))  # fmt: skip
    units["pose training"] = seconds / 4
    print(f"pose training: {units['pose training']:.1f} s (two at a time)")
    return units


def project(units: dict[str, float], ablations: int, dose_trainings: int) -> dict[str, float]:
    """Seconds of every stage of a run with ``ablations`` video trainings and
    ``dose_trainings`` pose trainings in the dose-response."""
    return {
        "render": units["render"] * STANDIN_FRAMES,
        "ablation trainings": units["ablation training"] * ablations,
        "ablation scoring": units["ablation scoring"] * ablations,
        "Wiener copy": units["Wiener copy"] * STANDIN_FRAMES,
        "network copy": units["network copy"] * STANDIN_FRAMES,
        "notebook 03, the rest": REFERENCE["notebook 03, the rest"],
        "pose matrix (notebook 04)": units["pose training"] * POSE_TRAININGS,
        "dose-response (notebook 06)": units["pose training"] * dose_trainings
        + (units["render"] + units["network copy"]) * DOSE_FRAMES,
        "notebooks 00-02 and 05": REFERENCE["notebooks 00-02 and 05"],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=Path("data/standin"),
                        help="the rendered stand-in (blurloc synth --out DIR)")  # fmt: skip
    parser.add_argument("--out", type=Path, default=Path("build/full_run_budget"),
                        help="scratch folder (emptied first)")  # fmt: skip
    add_out_dir_argument(parser)
    args = parser.parse_args()
    if not (args.data / "heads").is_dir() or not (args.data / "chess").is_dir():
        raise SystemExit(f"{args.data}: not a rendered stand-in (run blurloc synth --out DIR)")
    shutil.rmtree(args.out, ignore_errors=True)
    units = measure_units(args.data, args.out)
    as_run, smallest = project(units, *AS_RUN), project(units, *SMALLEST)
    print(f"\n{'stage':30s} {'last full run':>14s} {'projected here':>15s} {'smallest run':>13s}")
    for stage, reference in REFERENCE.items():
        print(f"{stage:30s} {reference:14.0f} {as_run[stage]:15.0f} {smallest[stage]:13.0f}")
    totals = [sum(REFERENCE.values()), sum(as_run.values()), sum(smallest.values())]
    print(f"{'total, minutes':30s} {totals[0] / 60:14.1f} {totals[1] / 60:15.1f} "
          f"{totals[2] / 60:13.1f}   (target 150)")  # fmt: skip
    stages = [
        {
            "stage": stage,
            "last_full_run_s": round(reference),
            "projected_here_s": round(as_run[stage]),
            "smallest_run_s": round(smallest[stage]),
        }
        for stage, reference in REFERENCE.items()
    ]
    stages.append(
        {
            "stage": "total, minutes (target 150)",
            "last_full_run_s": round(totals[0] / 60, 1),
            "projected_here_s": round(totals[1] / 60, 1),
            "smallest_run_s": round(totals[2] / 60, 1),
        }
    )
    saved = save_benchmark_tables(
        "full_run_budget",
        {
            "stages": stages,
            "units": [{"unit": unit, "seconds": round(value, 4)} for unit, value in units.items()],
        },
        args.out_dir,
        "Projected time of a full make reproduce on this machine",
        notes="Seconds per stage (the last row in minutes); units: seconds per rendered or copied "
        "frame, per ablation training, per network scored, per pose training.",
    )
    print(f"wrote {saved.markdown}")


if __name__ == "__main__":
    main()
