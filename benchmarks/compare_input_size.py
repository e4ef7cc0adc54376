"""Does a larger input, where the median blur exceeds 2 px, change the pose verdicts?

    python benchmarks/compare_input_size.py [--resize 80] [--crop 64] [--seeds 5]
                                            [--data ROOT] [--work /tmp/input-size]
                                            [--out-dir figures]

At the pose network's default input (64 px short side, 56 px crops) the stand-in's median
blur is under 2 px, too little, perhaps, for deblurring to matter. This check repeats notebook 04's
main comparison at a larger input: the LSTM on blurred, network-deblurred (the shipped video
checkpoint) and sharp frames, every scene, ``--seeds`` seeds shared by the three inputs, and
prints the blur at both input sizes, the mean over seeds of the per-scene medians, and the
paired differences (network-deblurred - blurred, sharp - blurred) with 95 % bootstrap
intervals over the scene x seed pairs and the verdict each interval supports, as notebook 04
does at the default size (``figures/pose_paired_differences.md``); both tables are written to
``<out-dir>/compare_input_size-<resize>.md`` with one CSV each (``compare_input_size-<resize>.csv``,
``compare_input_size-<resize>-paired.csv``).
``--data`` is the full-size default stand-in (rendered under ``--work`` when not given, about
7 minutes on 2 cores); the deblurred copy (about 3 minutes) and the trainings (about 11
minutes) are kept under ``--work``. Not part of ``make reproduce``; docs/results.md ("What
reproduced, in numbers", the row on the main comparison at a larger input) records the last run.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

from blurloc.data import list_scenes
from blurloc.data.synth import synthesize
from blurloc.experiments.comparisons import comparison_table
from blurloc.experiments.pose import (
    blur_at_input,
    mean_pose_baseline,
    pose_overview,
    run_pose_matrix,
)
from blurloc.experiments.video import write_deblurred_root
from blurloc.inference import DEFAULT_CHECKPOINT, VideoRestorer
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import PoseTrainConfig

METRICS = ("position_m_median", "orientation_deg_median", "combined")


def main() -> None:
    """Deblur, train, and print the paired comparison."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resize", type=int, default=80)
    parser.add_argument("--crop", type=int, default=64)
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--data", type=Path, help="the default stand-in (rendered if not given)")
    parser.add_argument("--work", type=Path, default=Path("/tmp/input-size"))
    add_out_dir_argument(parser)
    args = parser.parse_args()
    start = time.perf_counter()
    data = args.data or synthesize(args.work / "standin", progress=False)
    rnn = args.work / "deblurred" / "rnn"
    if not (rnn / "done").is_file():
        write_deblurred_root(data, rnn, VideoRestorer(DEFAULT_CHECKPOINT), workers=2)
        (rnn / "done").touch()
    print(f"stand-in and deblurred copy ready in {time.perf_counter() - start:.0f} s", flush=True)

    default = PoseTrainConfig(device="cpu")
    config = replace(default, resize=args.resize, crop=args.crop)
    for name, settings in (("default", default), ("this run", config)):
        blur = blur_at_input(data, settings)
        print(
            f"blur at the {name} input ({settings.resize} px short side): median "
            f"{blur['input_median_px']} px, 90th percentile {blur['input_p90_px']} px"
        )

    roots = {"blurred": data, "rnn": rnn, "sharp": data}
    runs = [(condition, "lstm") for condition in roots]
    scenes = list_scenes(data)
    start = time.perf_counter()
    summaries, _ = run_pose_matrix(roots, scenes, runs, config,
                                   args.work / f"models-{args.resize}-{args.crop}",
                                   seeds=tuple(range(args.seeds)), workers=2)  # fmt: skip
    print(f"{len(summaries)} trainings in {(time.perf_counter() - start) / 60:.1f} min\n")

    baseline = {scene: mean_pose_baseline(data, scene) for scene in scenes}
    paired = comparison_table(summaries, [("blurred", "rnn"), ("blurred", "sharp")], METRICS,
                              where={"head": "lstm"})  # fmt: skip
    saved = save_benchmark_tables(
        f"compare_input_size-{args.resize}",
        {"overview": pose_overview(summaries, runs, baseline),
         "paired": [{k: round(v, 4) if isinstance(v, float) else v for k, v in row.items()}
                    for row in paired]},
        args.out_dir,
        f"Pose verdicts at a {args.resize} px input ({args.crop} px crops, {args.seeds} seeds)",
        notes="Overview: median errors, mean over scenes and seeds. Paired: mean paired "
        "difference over scene x seed pairs, 95 % bootstrap interval and the verdict on the "
        "claimed direction (lower).",
    )  # fmt: skip
    print("\n" + saved.markdown.read_text())


if __name__ == "__main__":
    main()
