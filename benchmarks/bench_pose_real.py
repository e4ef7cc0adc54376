"""Pose regression on real frames, beside image retrieval and the mean pose.

    python benchmarks/bench_pose_real.py [--data samples/real/recording] [--scene fr1_rpy]
        [--standin ROOT] [--standin-scene chess] [--seeds 3] [--variant fixed_crop=true ...]
        [--standin-variant resize=120,crop=104 ...]
        [--work /tmp/bench-pose-real] [--validation 2 6] [--out-dir figures]

On a real recording in the 7-Scenes layout (default: the committed TUM RGB-D ``freiburg1_rpy``
recording, ``samples/real/recording``, its test sequences lying between training ones) and on
one scene of the stand-in (``--standin``: a rendered root; skipped when not given), it scores
every test frame's median position and orientation error of

- the mean pose (the mean training position and rotation for every frame): what a regressor
  must beat to have learnt anything, and the unit of every ratio;
- image retrieval (:mod:`blurloc.experiments.retrieval`): the pose of the training frame with
  the nearest global descriptor, what a user would pick instead of a regressor;
- the nearest training view in pose (an oracle that reads the test poses: how close the
  training views come to the test views);
- ``train-pose`` with the package's defaults (:class:`blurloc.train.config.PoseTrainConfig`),
  ``--seeds`` seeds, each a run of its own (8 epochs of 512 windows, about 3 minutes on 2
  shared CPU cores);
- each ``--variant`` (settings of ``PoseTrainConfig`` changed from the defaults, e.g.
  ``fixed_crop=true``, ``resize=96,crop=84`` or ``model.dropout=0.2``) on the same seeds; on the
  stand-in the defaults and each ``--standin-variant``.

Ratios are to the mean pose's median errors; a regressor's row gives the mean over seeds and
the 95 % t-interval of that mean, and whether every seed meets the targets (position <= 0.5x,
orientation <= 0.7x). Paired rows give the per-seed difference of the ratios (variant minus
defaults, regressor minus retrieval) with its 95 % t-interval and the verdict it supports. The
position spread is also given as the angle the mean pose's median position error subtends at
the scene's median depth: a translation that small moves the image about as a turn of that
angle does. Runs are kept under ``--work`` and reused. Writes ``<out-dir>/bench_pose_real.md``
and ``.csv`` with the command and the date.

``--validation 2 6`` chooses settings without the test split: those training
sequences of the real recording become the split scored (held out of training), the test
sequences are not read at all, and every row is a validation score. Choose the variant there,
then score it on the test split in a run without the option.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np

from blurloc.data import DataError, load_split, validation_root
from blurloc.data.real import RECORDING_SCENE, posed_frame_table, recording_root
from blurloc.data.sevenscenes import read_depth
from blurloc.experiments.pose import mean_pose_baseline, nearest_view_baseline
from blurloc.experiments.retrieval import retrieval_baseline
from blurloc.inference import load_pose_model, predict_poses
from blurloc.intervals import paired_interval, verdict
from blurloc.metrics import pose_summary, position_errors
from blurloc.models.pose import PoseConfig
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.config import PoseTrainConfig
from blurloc.train.datasets import FrameCache
from blurloc.train.pose import train_pose

#: Targets of a regressor on real frames, as ratios to the mean pose (position, orientation).
TARGETS = (0.5, 0.7)
COLUMNS = ["dataset", "what", "seeds", "position_m", "orientation_deg", "position_ratio",
           "position_ratio_95ci", "orientation_ratio", "orientation_ratio_95ci", "verdict",
           "val_position_m", "train_s"]  # fmt: skip


def parse_variant(text: str) -> dict:
    """``name=value,...`` as ``PoseTrainConfig`` overrides: numbers and true/false parsed,
    other values kept as text (``model.encoder=efficientnet_lite0``), ``model.<name>`` settings
    of its ``PoseConfig`` gathered under ``model``."""
    overrides: dict = {}
    for item in text.split(","):
        name, _, value = item.partition("=")
        if value.lower() in ("true", "false"):
            parsed = value.lower() == "true"
        else:
            parsed = _number_or_text(value)
        if name.startswith("model."):
            overrides.setdefault("model", {})[name.removeprefix("model.")] = parsed
        else:
            overrides[name] = parsed
    variant_config(overrides, 0)  # refuses unknown names and bad values now, not after training
    return overrides


def _number_or_text(value: str) -> int | float | str:
    """``value`` as an int, else a float, else as it is."""
    for kind in (int, float):
        try:
            return kind(value)
        except ValueError:
            pass
    return value


def variant_config(overrides: dict, seed: int) -> PoseTrainConfig:
    """The package's defaults with ``overrides`` (:func:`parse_variant`) and ``seed``."""
    settings = dict(overrides)
    model = PoseConfig(**settings.pop("model", {}))
    return replace(PoseTrainConfig(seed=seed), **settings, model=model)


def nearest_position_text(root: Path, scene: str) -> str:
    """Per test sequence, the median distance of its positions to the nearest training
    position: how far outside the training positions its views lie."""
    train = np.concatenate([s.poses()[:, :3, 3] for s in load_split(root, scene, "train")])
    parts = []
    for sequence in load_split(root, scene, "test"):
        positions = sequence.poses()[:, :3, 3]
        nearest = [np.linalg.norm(train - p, axis=1).min() for p in positions]
        parts.append(f"{sequence.folder.name} {np.median(nearest):.3f} m")
    return "test positions' median distance to the nearest training position: " + ", ".join(parts)


def median_depth(root: Path, scene: str) -> float | None:
    """Median depth of the scene's test frames (every 10th depth image), metres; for the
    committed recording, which holds no depth, the median depth of the development set's posed
    frames of the same recording; None when neither is known."""
    paths = [s.path(i, "depth") for s in load_split(root, scene, "test") for i in s.frame_ids]
    paths = [path for path in paths[::10] if path.is_file()]
    if paths:
        return float(np.median([np.median(d[d > 0]) for d in map(read_depth, paths)]))
    if root.resolve() == recording_root().resolve() and scene == RECORDING_SCENE:
        return float(np.median([float(r["depth_median_m"]) for r in posed_frame_table()]))
    return None


def run_seed(root: Path, scene: str, folder: Path, config: PoseTrainConfig,
             cache: FrameCache) -> dict:  # fmt: skip
    """Train (or reuse) one run and score its best checkpoint on the test split."""
    history = train_pose(root, scene, folder, config, progress=False, cache=cache)
    model, trained = load_pose_model(folder / "best.pt", scene=scene)
    test = load_split(root, scene, "test")
    pair = predict_poses(model, test, trained, cache=cache)
    summary = pose_summary(pair)
    ends = np.cumsum([len(s) for s in test])[:-1]
    per_sequence = [float(np.median(e)) for e in np.split(position_errors(pair), ends)]
    scores = np.add(history["val_position_m"], np.divide(history["val_orientation_deg"], 10))
    return {"position_m": summary["position_m"]["median"], "per_sequence": per_sequence,
            "orientation_deg": summary["orientation_deg"]["median"],
            "val_position_m": history["val_position_m"][int(np.argmin(scores))],
            "train_s": history["seconds"][-1]}  # fmt: skip


def interval_text(values: np.ndarray) -> str:
    """The 95 % t-interval of the mean of ``values``, as ``low to high``."""
    interval = paired_interval(values, method="t")
    return f"{interval.low:.2f} to {interval.high:.2f}"


def lower(interval) -> str:
    """Whether the first of a paired row is better, as its interval says."""
    return {"reproduced": "first lower", "contradicted": "first higher"}.get(
        verdict(interval), f"not resolved (±{interval.half_width:.2f})"
    )


def dataset_rows(label: str, root: Path, scene: str, seeds: int, variants: dict[str, dict],
                 work: Path) -> list[dict]:  # fmt: skip
    """Every row of one dataset: baselines, regressors per seed and over seeds, paired rows."""
    mean = mean_pose_baseline(root, scene)
    unit = np.array([mean["position_m"]["median"], mean["orientation_deg"]["median"]])
    depth = median_depth(root, scene)
    spread = "" if depth is None else (
        f"position spread = {np.degrees(np.arctan(unit[0] / depth)):.1f} deg of view at the "
        f"median depth {depth:.2f} m")  # fmt: skip
    rows = []

    def baseline(what: str, summary: dict, note: str = "") -> np.ndarray:
        errors = np.array([summary["position_m"]["median"], summary["orientation_deg"]["median"]])
        ratios = errors / unit
        rows.append({"dataset": label, "what": what, "seeds": "", "position_m": f"{errors[0]:.4f}",
                     "orientation_deg": f"{errors[1]:.2f}", "position_ratio": f"{ratios[0]:.2f}",
                     "orientation_ratio": f"{ratios[1]:.2f}", "verdict": note})  # fmt: skip
        return ratios

    baseline(
        f"mean pose ({mean['frames']} test frames)",
        mean,
        "; ".join(filter(None, [spread, nearest_position_text(root, scene)])),
    )
    retrieved = baseline("image retrieval (nearest training frame, 16x12 gray descriptor)",
                         retrieval_baseline(root, scene))  # fmt: skip
    baseline("nearest training view in pose (oracle)", nearest_view_baseline(root, scene))
    cache = FrameCache()
    ratios = {}
    for name, overrides in {"train-pose defaults": {}, **variants}.items():
        per_seed = []
        for seed in range(seeds):
            config = variant_config(overrides, seed)
            kind = name.replace(",", "_") if overrides else "defaults"
            folder = work / label.replace(" ", "-") / kind / f"seed-{seed}"
            result = run_seed(root, scene, folder, config, cache)
            per_seed.append(result)
            print(label, name, seed, result, flush=True)
        errors = np.array([[r["position_m"], r["orientation_deg"]] for r in per_seed])
        ratios[name] = errors / unit
        met = np.all(ratios[name] <= np.array(TARGETS), axis=0)
        rows.append({"dataset": label, "what": name if not overrides else f"variant {name}",
                     "seeds": seeds, "position_m": f"{errors[:, 0].mean():.4f}",
                     "orientation_deg": f"{errors[:, 1].mean():.2f}",
                     "position_ratio": f"{ratios[name][:, 0].mean():.2f}",
                     "position_ratio_95ci": interval_text(ratios[name][:, 0]),
                     "orientation_ratio": f"{ratios[name][:, 1].mean():.2f}",
                     "orientation_ratio_95ci": interval_text(ratios[name][:, 1]),
                     "verdict": f"every seed within <= {TARGETS[0]}x position: "
                                f"{'yes' if met[0] else 'no'}; <= {TARGETS[1]}x orientation: "
                                f"{'yes' if met[1] else 'no'} (per seed "
                                + ", ".join(f"{a:.2f}/{b:.2f}" for a, b in ratios[name])
                                + "); median position error per test sequence, seed mean: "
                                + ", ".join(f"{s.folder.name} {e:.3f} m" for s, e in zip(
                                    load_split(root, scene, "test"),
                                    np.mean([r["per_sequence"] for r in per_seed], axis=0),
                                    strict=True)),
                     "val_position_m": f"{np.mean([r['val_position_m'] for r in per_seed]):.4f}",
                     "train_s": round(np.mean([r["train_s"] for r in per_seed]))})  # fmt: skip
    pairs = [(f"{name} - defaults", ratios[name] - ratios["train-pose defaults"])
             for name in variants]  # fmt: skip
    pairs += [(f"{name} - image retrieval", ratios[name] - retrieved) for name in ratios]
    for what, differences in pairs:
        found = [paired_interval(differences[:, k], method="t") for k in range(2)]
        rows.append({"dataset": label, "what": f"paired: {what} (ratio difference)",
                     "seeds": seeds, "position_ratio": f"{found[0].mean:+.2f}",
                     "position_ratio_95ci": f"{found[0].low:+.2f} to {found[0].high:+.2f}",
                     "orientation_ratio": f"{found[1].mean:+.2f}",
                     "orientation_ratio_95ci": f"{found[1].low:+.2f} to {found[1].high:+.2f}",
                     "verdict": f"position: {lower(found[0])}; orientation: "
                                f"{lower(found[1])}"})  # fmt: skip
    return rows


def main() -> None:
    """Score the baselines and the regressors; write the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=None, help="real 7-Scenes-layout root "
                        "(default: the committed recording)")  # fmt: skip
    parser.add_argument("--scene", default=RECORDING_SCENE)
    parser.add_argument("--standin", type=Path, help="stand-in root (skipped when not given)")
    parser.add_argument("--standin-scene", default="chess")
    parser.add_argument("--standin-variant", action="append", default=[],
                        help="a variant trained on the stand-in too (default: none)")  # fmt: skip
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--variant", action="append", default=[],
                        help="PoseTrainConfig settings, name=value[,name=value]")  # fmt: skip
    parser.add_argument("--work", type=Path, default=Path("/tmp/bench-pose-real"))
    parser.add_argument("--stem", default="bench_pose_real",
                        help="name of the written tables (default: %(default)s)")  # fmt: skip
    parser.add_argument("--validation", type=int, nargs="+", default=None,
                        help="training sequences held out and scored instead of the test split, "
                        "e.g. 2 6 (choosing settings without the test split)")  # fmt: skip
    add_out_dir_argument(parser)
    args = parser.parse_args()
    if args.seeds < 2:
        parser.error(f"--seeds {args.seeds}: at least 2 (each regressor's interval is over seeds)")
    variants = {text: parse_variant(text) for text in args.variant}
    data = args.data or recording_root()
    label = f"real {args.scene}"
    scored = "test"
    if args.validation:
        try:
            data = validation_root(data, args.scene, args.validation, args.work / "validation-root")
        except DataError as error:
            parser.error(f"--validation {' '.join(map(str, args.validation))}: {error}")
        label, scored = f"real {args.scene} validation", "validation"
    rows = dataset_rows(label, data, args.scene, args.seeds, variants,
                        args.work)  # fmt: skip
    if args.standin is not None:
        rows += dataset_rows(f"stand-in {args.standin_scene}", args.standin, args.standin_scene,
                             args.seeds, {t: parse_variant(t) for t in args.standin_variant},
                             args.work)  # fmt: skip
    notes = (
        f"Median {scored} errors; ratios to the mean pose's; regressor rows: mean over seeds, "
        "95 % t-interval of the mean; paired rows: per-seed differences of ratios "
        "(negative: the first is better). Targets on real frames: position <= "
        f"{TARGETS[0]}x, orientation <= {TARGETS[1]}x. Real: {data} (scene {args.scene}); "
        "stand-in: "
        + (f"{args.standin} (scene {args.standin_scene})" if args.standin else "not run")
        + f". {args.seeds} seeds per regressor; each run trains the package's defaults "
        "(8 epochs of 512 windows of 4 frames: 256 steps) or a variant of them, train_s "
        "seconds on 2 shared CPU cores; val_position_m is the median position error on the "
        "validation frames (the end of every training sequence) at the kept epoch."
    )
    table = [{column: row.get(column, "") for column in COLUMNS} for row in rows]
    saved = save_benchmark_tables(
        args.stem,
        {"results": table},
        args.out_dir,
        "Pose regression on real frames beside image retrieval and the mean pose",
        notes=notes,
    )
    print(f"wrote {saved.markdown}")


if __name__ == "__main__":
    main()
