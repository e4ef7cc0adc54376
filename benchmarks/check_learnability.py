"""Does the sharp-input pose regressor learn every stand-in scene, and what limits it?

    python benchmarks/check_learnability.py [--render-seeds 0 1] [--epochs 8 32] [--seeds 2]
                                            [--work /tmp/learnability] [--out-dir figures]

The stand-in is useful for the paper's question only if its regressor learns: on every scene the
LSTM trained on sharp frames should reach at most 0.5x the position error and 0.6x the orientation
error of predicting the mean training pose (published methods reach about 0.1-0.3x on real
7-Scenes). This check renders the full-size default stand-in at each ``--render-seeds`` seed (seed 0
is the one the notebooks use), trains the LSTM on sharp frames with ``train-pose``'s defaults except
the number of epochs, once per ``--epochs`` value (an epoch is 32 optimiser steps whatever the
scene's size), for ``--seeds`` training seeds, and prints per scene the mean-pose baseline, the
nearest-view oracle (the training pose nearest to each test pose: how near the test views lie to
views the training split holds) and the regressor's errors and ratios. Then the paired difference of
the position and orientation ratios between the last and the first ``--epochs`` value, per render
seed and scene, with a 95 % t-interval. Both tables are written to
``<out-dir>/check_learnability.md`` with one CSV each (``check_learnability.csv``,
``check_learnability-epochs.csv``). Renders (about 5 minutes each on 2 cores) and trainings are kept
under ``--work`` and not redone. Not part of ``make reproduce``; docs/results.md ("What reproduced,
in numbers", the row on whether the regressor learns) records the last run.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from blurloc.data.scenes import SCENE_NAMES
from blurloc.data.synth import synthesize
from blurloc.experiments.comparisons import comparison_table
from blurloc.experiments.pose import (
    learning_check,
    mean_pose_baseline,
    nearest_view_baseline,
    run_pose_matrix,
)
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import PoseTrainConfig


def _check(
    root: Path, models: Path, scenes: list[str], config: PoseTrainConfig, seeds: int
) -> list[dict]:
    """Train the sharp-input LSTM on every scene of ``root`` and add the oracle to each row."""
    summaries, _ = run_pose_matrix(
        {"sharp": root}, scenes, [("sharp", "lstm")], config, models,
        seeds=tuple(range(seeds)), workers=2,
    )  # fmt: skip
    baseline = {scene: mean_pose_baseline(root, scene) for scene in scenes}
    rows = learning_check(summaries, baseline)
    for row in rows:
        nearest = nearest_view_baseline(root, row["scene"])["position_m"]["median"]
        row["nearest_position_m"] = round(nearest, 3)
        row["nearest_ratio"] = round(nearest / row["baseline_position_m"], 2)
    return rows


def main() -> None:
    """Render, train and print the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--render-seeds", type=int, nargs="+", default=[0, 1])
    parser.add_argument("--epochs", type=int, nargs="+", default=[8, 32])
    parser.add_argument("--seeds", type=int, default=2, help="training seeds per scene")
    parser.add_argument("--scenes", nargs="+", default=list(SCENE_NAMES))
    parser.add_argument("--work", type=Path, default=Path("/tmp/learnability"))
    add_out_dir_argument(parser)
    args = parser.parse_args()
    results = {}
    for render_seed in args.render_seeds:
        start = time.perf_counter()
        root = synthesize(args.work / f"seed{render_seed}", scenes=args.scenes, seed=render_seed,
                          progress=False)  # fmt: skip
        print(f"render seed {render_seed}: ready in {time.perf_counter() - start:.0f} s")
        for epochs in args.epochs:
            start = time.perf_counter()
            config = PoseTrainConfig(device="cpu", epochs=epochs)
            models = args.work / "models" / f"seed{render_seed}" / f"epochs{epochs}"
            results[render_seed, epochs] = _check(root, models, args.scenes, config, args.seeds)
            print(f"  {epochs} epochs: trained and tested in {time.perf_counter() - start:.0f} s",
                  flush=True)  # fmt: skip

    rows = [
        {"render_seed": render_seed, "epochs": epochs, **row}
        for (render_seed, epochs), scene_rows in results.items()
        for row in scene_rows
    ]
    for (render_seed, epochs), scene_rows in results.items():
        met = sum(r["position_ratio"] <= 0.5 and r["orientation_ratio"] <= 0.6 for r in scene_rows)
        print(f"render seed {render_seed}, {epochs} epochs: {met} of {len(scene_rows)} scenes at "
              f"<= 0.5x position and <= 0.6x orientation")  # fmt: skip

    first, last = args.epochs[0], args.epochs[-1]
    paired = comparison_table(rows, [(first, last)], ("position_ratio", "orientation_ratio"),
                              factor="epochs", units=("render_seed", "scene"),
                              method="t")  # fmt: skip
    saved = save_benchmark_tables(
        "check_learnability",
        {"scenes": rows,
         "epochs": [{k: round(v, 3) if isinstance(v, float) else v for k, v in row.items()}
                    for row in paired]},
        args.out_dir,
        "Does the sharp-input pose regressor learn every stand-in scene?",
        notes=f"Scenes: sharp-input LSTM (mean over {args.seeds} training seeds) against the "
        f"mean-pose baseline and the nearest-view oracle. Epochs: {last} minus {first} epochs, "
        "paired by render seed and scene; the verdict is on the claim that longer training "
        "lowers the ratio.",
    )  # fmt: skip
    print("\n" + saved.markdown.read_text())


if __name__ == "__main__":
    main()
