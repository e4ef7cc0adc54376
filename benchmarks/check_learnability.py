"""Does the sharp-input pose regressor learn every stand-in scene, with and without shared routes?

    python benchmarks/check_learnability.py [--share 0.8] [--render-seeds 0 1] [--seeds 2]
                                            [--epochs N] [--work /tmp/learnability]

The stand-in is useful for the paper's question only if its regressor learns: on every scene
the LSTM trained on sharp frames should reach at most 0.5x the position error and 0.6x the
orientation error of predicting the mean training pose (published methods reach about 0.1-0.3x
on real 7-Scenes). This check renders the full-size stand-in at each ``--render-seeds`` seed
twice, with independent sequences (``route_share`` 0, the default) and with sequences that
follow a shared route in part (``--share``, :func:`blurloc.data.synth.scene_route`); trains the
LSTM on sharp frames with ``train-pose``'s defaults (``--epochs`` overrides the epoch count)
for ``--seeds`` training seeds; and prints per scene the mean-pose baseline, the nearest-view
oracle (the training pose nearest to each test pose) and the regressor's errors and ratios.
Then the paired difference (shared minus independent, per render seed and scene) of the
position ratio and of the oracle's ratio, with a 95 % t-interval. Renders (about 5 minutes per
stand-in on 2 cores) and trainings are kept under ``--work`` and not redone. Not part of
``make reproduce``; the README records the last run.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from blurloc.data.scenes import SCENE_NAMES
from blurloc.data.synth import SynthConfig, synthesize
from blurloc.experiments.pose import (
    learning_check,
    mean_pose_baseline,
    nearest_view_baseline,
    run_pose_matrix,
)
from blurloc.intervals import paired_interval
from blurloc.train.config import PoseTrainConfig


def _check(root: Path, models: Path, scenes: list[str], config: PoseTrainConfig,
           seeds: int) -> list[dict]:  # fmt: skip
    """Train the sharp-input LSTM on every scene of ``root`` and add the oracle to each row."""
    summaries, _ = run_pose_matrix({"sharp": root}, scenes, [("sharp", "lstm")], config, models,
                                   seeds=tuple(range(seeds)), workers=2)  # fmt: skip
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
    parser.add_argument("--share", type=float, default=0.8)
    parser.add_argument("--render-seeds", type=int, nargs="+", default=[0, 1])
    parser.add_argument("--seeds", type=int, default=2, help="training seeds per scene")
    parser.add_argument("--epochs", type=int, help="epochs (default: train-pose's)")
    parser.add_argument("--scenes", nargs="+", default=list(SCENE_NAMES))
    parser.add_argument("--work", type=Path, default=Path("/tmp/learnability"))
    args = parser.parse_args()
    config = PoseTrainConfig(device="cpu")
    if args.epochs is not None:
        config = replace(config, epochs=args.epochs)
    results = {}
    for render_seed in args.render_seeds:
        for share in (0.0, args.share):
            name = f"seed{render_seed}-share{share:g}"
            start = time.perf_counter()
            root = synthesize(args.work / name, scenes=args.scenes, seed=render_seed,
                              config=SynthConfig(route_share=share), progress=False)  # fmt: skip
            rendered = time.perf_counter() - start
            models = args.work / "models" / name / f"epochs{config.epochs}"
            results[render_seed, share] = _check(root, models, args.scenes, config, args.seeds)
            print(f"{name}: rendered in {rendered:.0f} s, trained and tested in "
                  f"{time.perf_counter() - start - rendered:.0f} s", flush=True)  # fmt: skip

    print(f"\nSharp-input LSTM, {config.epochs} epochs, mean over {args.seeds} training seeds\n")
    print(
        "| render seed | route share | scene | mean pose (m / °) | nearest view (m, ratio) "
        "| LSTM (m / °) | ratio position | ratio orientation |\n"
        "|---|---|---|---|---|---|---|---|"
    )
    for (render_seed, share), rows in results.items():
        for r in rows:
            print(f"| {render_seed} | {share:g} | {r['scene']} | {r['baseline_position_m']:.3f} / "
                  f"{r['baseline_orientation_deg']:.1f} | {r['nearest_position_m']:.3f}, "
                  f"{r['nearest_ratio']:.2f} | {r['position_m']:.3f} / {r['orientation_deg']:.2f} "
                  f"| {r['position_ratio']:.2f} | {r['orientation_ratio']:.2f} |")  # fmt: skip
    for (render_seed, share), rows in results.items():
        met = sum(r["position_ratio"] <= 0.5 and r["orientation_ratio"] <= 0.6 for r in rows)
        print(f"render seed {render_seed}, share {share:g}: {met} of {len(rows)} scenes at "
              f"<= 0.5x position and <= 0.6x orientation")  # fmt: skip

    print("\nShared minus independent routes, paired by render seed and scene (95 % t-interval):")
    for key in ("position_ratio", "orientation_ratio", "nearest_ratio", "baseline_position_m",
                "baseline_orientation_deg"):  # fmt: skip
        differences = [
            shared[key] - alone[key]
            for render_seed in args.render_seeds
            for alone, shared in zip(
                results[render_seed, 0.0], results[render_seed, args.share], strict=True
            )
        ]
        if len(differences) < 2:
            break
        interval = paired_interval(np.array(differences), method="t")
        print(f"  {key}: {interval.mean:+.3f} [{interval.low:+.3f}, {interval.high:+.3f}] "
              f"({interval.pairs} pairs)")  # fmt: skip


if __name__ == "__main__":
    main()
