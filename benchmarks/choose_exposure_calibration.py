"""Choosing how the exposure share is read from a video: the weight of the one-kernel comparison
and the least depth at which a share is told apart.

    python benchmarks/choose_exposure_calibration.py [--out-dir figures]

:func:`blurloc.blur.fit_exposure_share` finds the exposure share under which a video's blurred
frames explain one another, subtracting the same comparison with one kernel on both sides with
weight w (WEIGHTS), and how clearly (its depth); :func:`~blurloc.blur.calibrate_exposure_share`
returns that share where the depth is above a least depth (DEPTHS), else None (the default
share). This script fits every GoPro-style video of the training photographs
(:func:`~blurloc.experiments.photo_video.photo_training_videos`: photographs the test videos do
not show, 12 videos of 12 frames per set) averaging 5, 9 or 17 of every 9 sub-frames (exposure
shares 0.56, 1 and 1.89) without noise and with sigma = 0.01, once per weight, and reports per
weight and least depth: the share of videos told apart, and among them the median and the worst
relative error of the share read (read over true, less 1). Chosen: among the settings whose worst
relative error is at most MAX_RELATIVE_ERROR, the one that tells the most videos apart, then
the smallest median error, then the largest least depth (the package's CALIBRATION_ALIKE_WEIGHT
and CALIBRATION_MIN_DEPTH are this choice). Writes
``<out-dir>/choose_exposure_calibration.md``/``.csv``. About 5 min on 2 cores.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from blurloc.blur import fit_exposure_share, frame_shifts
from blurloc.blur.video_motion import CALIBRATION_ALIKE_WEIGHT, CALIBRATION_MIN_DEPTH
from blurloc.experiments.photo_video import photo_training_videos
from blurloc.tables import add_out_dir_argument, save_benchmark_tables

#: Weights of the one-kernel comparison tried.
WEIGHTS = (0.5, 0.75, 1.0)
#: Least depths tried.
DEPTHS = (0.01, 0.003, 0.001, 0.0003)
#: Sub-frames averaged into each frame, of every 9.
EXPOSURES = (5, 9, 17)
#: Noise sigmas of the training videos.
NOISES = (0.0, 0.01)
#: Largest relative error of a share read that a chosen setting may make on any video.
MAX_RELATIVE_ERROR = 0.2


def main() -> None:
    """Fit every training video under every weight; score every least depth; choose."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_out_dir_argument(parser)
    args = parser.parse_args()
    videos = [(exposure / 9, blurred, frame_shifts(blurred))
              for exposure in EXPOSURES for noise in NOISES
              for blurred, _ in photo_training_videos(12, frames=12, seed=1, noise_sigma=noise,
                                                      exposure_subframes=exposure)]  # fmt: skip
    rows = []
    for weight in WEIGHTS:
        fits = [(truth, fit_exposure_share(blurred, shifts, weight))
                for truth, blurred, shifts in videos]  # fmt: skip
        for depth in DEPTHS:
            errors = [abs(fit.share / truth - 1) for truth, fit in fits
                      if fit is not None and fit.depth > depth]  # fmt: skip
            rows.append({"alike_weight": weight, "min_depth": depth, "videos": len(fits),
                         "told_apart": round(len(errors) / len(fits), 3),
                         "median_relative_error": round(float(np.median(errors)), 3)
                         if errors else "",
                         "worst_relative_error": round(float(np.max(errors)), 3)
                         if errors else ""})  # fmt: skip
            print(rows[-1], flush=True)
    allowed = [row for row in rows if row["worst_relative_error"] != ""
               and row["worst_relative_error"] <= MAX_RELATIVE_ERROR]  # fmt: skip
    best = max(allowed, key=lambda row: (row["told_apart"], -row["median_relative_error"],
                                         row["min_depth"]))  # fmt: skip
    for row in rows:
        row["chosen"] = "yes" if row is best else ""
    chosen = (best["alike_weight"], best["min_depth"])
    if chosen != (CALIBRATION_ALIKE_WEIGHT, CALIBRATION_MIN_DEPTH):
        print(f"the choice {chosen} differs from the package's "
              f"{(CALIBRATION_ALIKE_WEIGHT, CALIBRATION_MIN_DEPTH)}: update them",
              file=sys.stderr)  # fmt: skip
    notes = ("Training photo videos (12 per exposure and noise, 12 frames each) averaging 5, 9 "
             "or 17 of every 9 sub-frames, sigma 0 and 0.01; told_apart: share of the "
             f"{len(videos)} videos whose depth is above min_depth; errors: |read / true - 1| "
             f"over those. Chosen: worst error <= {MAX_RELATIVE_ERROR}, then most told apart, "
             "smallest median error, largest min_depth.")  # fmt: skip
    saved = save_benchmark_tables("choose_exposure_calibration", {"choice": rows}, args.out_dir,
                                  notes=notes)  # fmt: skip
    print(f"chosen: alike weight {chosen[0]}, least depth {chosen[1]}; tables: {saved}")


if __name__ == "__main__":
    main()
