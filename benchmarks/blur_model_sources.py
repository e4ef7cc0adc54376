"""What each training source contributes to the blur length model, scored on real frames and
on the stand-in in one run.

    python benchmarks/blur_model_sources.py --fit-root data/s60 [ROOT ...]
        --test-root data/s60 [--budget 3000] [--test-budget 600] [--out-dir figures]

The length model (:func:`blurloc.blur.fit_length_model`) is fitted three times, from the same
examples: on the stand-in's training splits alone (``--fit-root``, about ``--budget`` frames of
each root, :func:`~blurloc.experiments.blur_estimation.length_training_set`), on blurred real
photographs alone (:func:`~blurloc.experiments.blur_estimation.photo_training_set`), and on
both (how the shipped model is fitted: ``benchmarks/bench_blur_estimation.py``'s docstring names
its renders). Each model's detector threshold is calibrated on its own
training examples (:func:`blurloc.blur.calibrate_blur_threshold`, blurred from 3 px against sharp
examples and those under 1.5 px). Every model is then scored, without refitting, on:

- real TUM RGB-D frames with poses (the development set's ``posed`` part, 640x480): Spearman
  rank correlation of the coarse length (:func:`blurloc.blur.analysis_length`) with the
  camera's image motion during the frame interval;
- real photographs: the share of sharp ones reported sharp and of blurred ones flagged, at the
  model's threshold (photographs a model was fitted on are counted apart);
- the stand-in's test split (``--test-root``): Spearman of the coarse length with the recorded
  extent, and the share of frames with >= 3 px flagged and of sharp renders passed.

The coarse length is what the model gives; the shipped estimator
(:func:`blurloc.blur.estimate_motion_blur`) refines long linear blur by the spectrum's sinc
zeros on top of it. Writes ``<out-dir>/blur_model_sources.md`` and ``.csv``.
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.stats import spearmanr

from blurloc.blur import (
    BLURRED_FROM_PX,
    SHARP_BELOW_PX,
    blur_features,
    calibrate_blur_threshold,
    fit_length_model,
)
from blurloc.data.real import load_photographs
from blurloc.experiments.blur_estimation import (
    TRAINING_PHOTOS,
    length_training_set,
    photo_training_set,
)
from blurloc.experiments.real_frames import SKIMAGE_NAMES, posed_frames_with_motion
from blurloc.tables import add_out_dir_argument, save_benchmark_tables


def predictions(model, features: np.ndarray) -> np.ndarray:
    """Coarse lengths (px at the analysis scale, >= 0) of feature rows."""
    return np.maximum(model.predict(features), 0.0)


def fitted_threshold(model, features: np.ndarray, extents: np.ndarray) -> float:
    """The detector threshold calibrated on a model's own training examples."""
    scores = predictions(model, features)
    blurred = extents >= BLURRED_FROM_PX
    keep = blurred | (extents < SHARP_BELOW_PX)
    return calibrate_blur_threshold(scores[keep], blurred[keep], sharp_groups=extents[keep] > 0)


def posed_features() -> tuple[np.ndarray, np.ndarray]:
    """Feature rows of the real posed frames and their camera image motion (px per interval)."""
    images, motion = posed_frames_with_motion()
    return np.stack([blur_features(image).values for image in images]), motion


def photograph_features() -> dict[str, dict[str, np.ndarray]]:
    """Feature rows of the real sharp and blurred photographs, by part and name."""
    return {part: {name: blur_features(image).values
                   for name, image in load_photographs(part).items()}
            for part in ("sharp", "blurred")}  # fmt: skip


def score(model, threshold: float, evaluation: dict) -> dict[str, float]:
    """One model's measures on the evaluation sets (see the module's docstring)."""
    posed, motion = evaluation["posed"]
    row = {"real TUM frames: Spearman(length, image motion)": spearmanr(
        predictions(model, posed), motion).statistic}  # fmt: skip
    for part, wanted in (("sharp", False), ("blurred", True)):
        photos = evaluation["photos"][part]
        unseen = [name for name in photos
                  if SKIMAGE_NAMES.get(name, name) not in TRAINING_PHOTOS]  # fmt: skip
        flagged = {name: predictions(model, values[None])[0] > threshold
                   for name, values in photos.items()}  # fmt: skip
        label = "reported sharp" if part == "sharp" else "flagged"
        row[f"real {part} photographs not fitted on: share {label}"] = np.mean(
            [flagged[name] == wanted for name in unseen])  # fmt: skip
    features, extents = evaluation["standin"]
    lengths = predictions(model, features)
    blurred = extents > 0
    row["stand-in test: Spearman(length, recorded extent)"] = spearmanr(
        lengths[blurred], extents[blurred]).statistic  # fmt: skip
    row["stand-in test: share flagged, extent >= 3 px"] = np.mean(
        lengths[extents >= BLURRED_FROM_PX] > threshold)  # fmt: skip
    row["stand-in test: share passed, sharp renders"] = np.mean(lengths[extents == 0] <= threshold)
    return {key: round(float(value), 3) for key, value in row.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fit-root", nargs="+", required=True, help="stand-in roots to fit on")
    parser.add_argument("--test-root", required=True, help="stand-in root scored (test split)")
    parser.add_argument("--budget", type=int, default=3000, help="training frames per fit root")
    parser.add_argument("--test-budget", type=int, default=600, help="test frames scored")
    add_out_dir_argument(parser)
    args = parser.parse_args()

    standin = [length_training_set(root, "train", budget=args.budget) for root in args.fit_root]
    sources = {
        "stand-in": (np.concatenate([f for f, _ in standin]),
                     np.concatenate([e for _, e in standin])),
        "photographs": photo_training_set(),
    }  # fmt: skip
    sources["both (shipped recipe)"] = tuple(
        np.concatenate([sources["stand-in"][i], sources["photographs"][i]]) for i in (0, 1)
    )
    evaluation = {
        "posed": posed_features(),
        "photos": photograph_features(),
        "standin": length_training_set(args.test_root, "test", budget=args.test_budget),
    }
    rows = []
    for name, (features, extents) in sources.items():
        model = fit_length_model(features, extents)
        threshold = fitted_threshold(model, features, extents)
        rows.append({"fitted on": name, "examples": len(extents),
                     "threshold (px)": round(threshold, 2),
                     **score(model, threshold, evaluation)})  # fmt: skip
    table = save_benchmark_tables(
        "blur_model_sources",
        {"sources": rows},
        args.out_dir,
        "The blur length model fitted on each source, scored on real frames and the stand-in",
    )
    print(table.markdown.read_text())


if __name__ == "__main__":
    main()
