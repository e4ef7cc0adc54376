"""What limits the blur length model on the stand-in's test split: the look, the camera model,
the number of training renders and the blend with photographs, each changed alone.

    python benchmarks/length_model_cause.py --look previous=data/s60-prev
        no-camera=data/s60-nocam new=data/s60 --more data/s60-seed1 data/s60-seed2
        [--seeds 3] [--out-dir figures]

The ``--look`` roots are renders of the same poses in different looks (``blurloc synth --out
data/s60 --frames 60``; the same with ``--previous-look``; the same with ``--optics-blur 0
--shot-noise 0 --read-noise 0``: the new scenes without the camera model); the one named ``new``
is the reference. ``--more`` roots are further renders of the new look (other seeds). Each
configuration fits :func:`blurloc.blur.fit_length_model` (its defaults) with ``--seeds`` initial
seeds on the training examples of :func:`~blurloc.experiments.blur_estimation.length_training_set`
(training splits only), optionally with the blurred photographs of
:func:`~blurloc.experiments.blur_estimation.photo_training_set`, and is scored on the test split
of the root of its look: Spearman of the coarse length with the recorded extent over all blurred
test frames (the mean over seeds), over those with >= 1 px, and within each scene. Each
configuration is compared with the reference by the paired differences of the within-scene
Spearman (scene x seed pairs, the same poses and frames), with a percentile-bootstrap 95 %
interval (:func:`blurloc.intervals.paired_interval`). The spread of the recorded extents of each
split is listed beside them: a rank correlation is lower where the extents span less.
Writes ``<out-dir>/length_model_cause.md`` and ``.csv`` files.
"""

from __future__ import annotations

import argparse

import numpy as np
import torch
from scipy.stats import spearmanr

from blurloc.blur import blur_features, fit_length_model
from blurloc.data.sevenscenes import read_image
from blurloc.experiments.blur_estimation import (
    length_training_set,
    photo_training_set,
    recorded_frames,
)
from blurloc.intervals import paired_interval
from blurloc.tables import add_out_dir_argument, save_benchmark_tables


def test_frames(root: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Feature rows, recorded extents (px at the analysis scale) and scenes of a test split's
    blurred frames."""
    rows, extents, scenes = [], [], []
    for record, sequence in recorded_frames(root, "test"):
        found = blur_features(read_image(sequence.path(record["frame"], "color")))
        rows.append(found.values)
        extents.append(record["mean_px"] / found.scale)
        scenes.append(record["scene"])
    return np.array(rows), np.array(extents), np.array(scenes)


def scores(model, test: tuple[np.ndarray, np.ndarray, np.ndarray]) -> dict:
    """Spearman of a model's coarse lengths with the recorded extents: all blurred frames,
    those >= 1 px, and each scene's."""
    features, extents, scenes = test
    lengths = np.maximum(model.predict(features), 0.0)
    long = extents >= 1.0
    return {
        "all": spearmanr(lengths, extents).statistic,
        ">= 1 px": spearmanr(lengths[long], extents[long]).statistic,
        "scenes": {scene: spearmanr(lengths[scenes == scene], extents[scenes == scene]).statistic
                   for scene in np.unique(scenes)},
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--look", nargs="+", required=True, metavar="NAME=ROOT",
                        help="renders of the same poses; one named 'new'")  # fmt: skip
    parser.add_argument("--more", nargs="*", default=[], help="more renders of the new look")
    parser.add_argument("--seeds", type=int, default=3, help="initial seeds per configuration")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    looks = dict(item.split("=", 1) for item in args.look)
    if "new" not in looks:
        parser.error("--look needs a root named 'new'")
    torch.set_num_threads(1)

    train = {name: length_training_set(root) for name, root in looks.items()}
    tests = {name: test_frames(root) for name, root in looks.items()}
    photos = photo_training_set()
    more = [length_training_set(root) for root in args.more]
    configurations = {f"{name} look": (name, [train[name]]) for name in looks}
    configurations["new look + photographs"] = ("new", [train["new"], photos])
    if more:
        configurations["new look + more renders"] = ("new", [train["new"], *more])
        configurations["new look + more renders + photographs"] = (
            "new", [train["new"], *more, photos])  # fmt: skip

    results, rows = {}, []
    for label, (look, parts) in configurations.items():
        features = np.concatenate([part[0] for part in parts])
        extents = np.concatenate([part[1] for part in parts])
        results[label] = [scores(fit_length_model(features, extents, seed=10 * seed), tests[look])
                          for seed in range(args.seeds)]  # fmt: skip
        test_extents = tests[look][1]
        rows.append({
            "fitted on": label, "examples": len(extents), "tested on": f"{look} look test split",
            "Spearman (all blurred)": round(np.mean([r["all"] for r in results[label]]), 3),
            "Spearman (extent >= 1 px)": round(np.mean([r[">= 1 px"] for r in results[label]]), 3),
            "test extents: sd (px)": round(float(test_extents.std()), 2),
            "test extents: share < 1 px": round(float(np.mean(test_extents < 1)), 3),
        })  # fmt: skip
        print(rows[-1], flush=True)
    reference = results["new look"]
    comparisons = []
    for label, found in results.items():
        if label == "new look":
            continue
        differences = [result["scenes"][scene] - base["scenes"][scene]
                       for result, base in zip(found, reference, strict=True)
                       for scene in base["scenes"]]  # fmt: skip
        interval = paired_interval(np.array(differences))
        word = ("higher" if interval.low > 0 else "lower" if interval.high < 0
                else "no difference resolved")  # fmt: skip
        comparisons.append({
            "configuration": label, "vs": "new look",
            "within-scene Spearman difference": round(interval.mean, 3),
            "95 % interval": f"[{interval.low:.3f}, {interval.high:.3f}]",
            "pairs (scene x seed)": interval.pairs, "verdict": word,
        })  # fmt: skip
    training_sd = {name: round(float(extents[extents > 0].std()), 2)
                   for name, (_, extents) in train.items()}  # fmt: skip
    saved = save_benchmark_tables(
        "length_model_cause",
        {"configurations": rows, "paired comparisons": comparisons},
        args.out_dir,
        "What limits the blur length model on the stand-in's test split",
        notes=f"Length model: fit_length_model's defaults, seeds 0, 10, ... ({args.seeds} per "
        f"configuration); Spearman over blurred test frames, mean over seeds. Spread (sd, px) of "
        f"the recorded extents of the training splits' blurred frames: {training_sd}.",
    )
    print(saved.markdown.read_text())


if __name__ == "__main__":
    main()
