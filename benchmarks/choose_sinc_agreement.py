"""How far from the coarse blur length the sinc refinement may go: the choice of SINC_AGREEMENT.

    python benchmarks/choose_sinc_agreement.py --root R640_S3 [--photos 8] [--out-dir figures]

For each candidate band (low, high), :func:`blurloc.blur.estimate_motion_blur` keeps the length
refined from the spectrum's sinc zeros only within low-high times the coarse length. Prints,
per band, on the training split of ROOT (a 640x480 stand-in render that the length model was
not fitted on: ``blurloc synth --out R640_S3 --width 640 --height 480 --frames 16 --seed 3``)
the rank correlation of the estimate with the recorded extent and the median length error
(extents >= 2 px), and on line-blurred photo crops (``estimation_trials``: L 7-27 px, σ 0,
0.005 and 0.01; crops of seed 13, not those notebook 01 measures) the median length and angle
errors. The shipped band (``blurloc.blur.SINC_AGREEMENT``) was chosen from this table, on
this render only (docs/results.md gives the reasons). The table goes to
``<out-dir>/choose_sinc_agreement.md``/``.csv``.
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.stats import spearmanr

from blurloc.blur import blur_features, estimate_motion_blur
from blurloc.data.sevenscenes import read_image
from blurloc.experiments.blur_estimation import recorded_frames
from blurloc.experiments.estimation import estimation_trials, photo_crops
from blurloc.tables import add_out_dir_argument, save_benchmark_tables

BANDS = ((0.5, 4.0), (0.5, 3.0), (0.5, 2.0), (0.5, 1.5), (0.6, 2.0), (0.67, 1.5), (0.67, 2.0),
         (0.75, 1.33), (0.75, 2.0), (0.75, 2.5), (0.8, 2.0))  # fmt: skip
PHOTO_LENGTHS_PX = (7.0, 12.0, 17.0, 22.0, 27.0)
PHOTO_SIGMAS = (0.0, 0.005, 0.01)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="640x480 stand-in render, not fitted on")
    parser.add_argument("--photos", type=int, default=8, help="photo crops (x 15 trials)")
    add_out_dir_argument(parser)
    args = parser.parse_args()

    frames = [(read_image(sequence.path(record["frame"], "color")), record["mean_px"])
              for record, sequence in recorded_frames(args.root, "train")]  # fmt: skip
    crops = photo_crops(args.photos, 256, seed=13)
    frame_features = [blur_features(image) for image, _ in frames]
    extents = np.array([extent for _, extent in frames])
    rows = []
    for band in BANDS:
        lengths = np.array(
            [
                estimate_motion_blur(image, features=found, agreement=band).length_px
                for (image, _), found in zip(frames, frame_features, strict=True)
            ]
        )
        trials = estimation_trials(
            crops, PHOTO_LENGTHS_PX, PHOTO_SIGMAS, seed=13, agreement=band
        )  # the same crops, blur and noise per band
        rows.append({
            "band": f"{band[0]:g}-{band[1]:g}",
            "render_spearman": round(float(spearmanr(lengths, extents).statistic), 3),
            "render_length_error_px": round(float(np.median(
                np.abs(lengths - extents)[extents >= 2])), 2),
            "photo_length_error_px": round(float(np.median(
                [t["length_error_px"] for t in trials])), 2),
            "photo_angle_error_deg": round(float(np.median(
                [t["angle_error_deg"] for t in trials])), 2),
        })  # fmt: skip
    saved = save_benchmark_tables(
        "choose_sinc_agreement",
        {"bands": rows},
        args.out_dir,
        "SINC_AGREEMENT candidates",
        notes=f"{len(frames)} training frames of {args.root} and {len(trials)} line-blurred "
        "photo crops.",
    )
    print(saved.markdown.read_text())


if __name__ == "__main__":
    main()
