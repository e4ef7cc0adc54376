"""Blind blur estimation on a stand-in split, against the blur recorded in ``blur.csv``.

    python benchmarks/bench_blur_estimation.py --root ROOT [--split test] [--every 1]

Prints the estimator's and the detector's measures beside their targets (Spearman of estimated
length vs recorded extent >= 0.8; median length error <= 1 px for extents >= 2 px; median angle
error <= 10° for extents >= 4 px; >= 90 % of frames with >= 3 px flagged, >= 90 % of frames under
1 px passed), the time per frame, and the rank correlation with the camera's image-plane motion
(from poses and depth) of the estimate and of the variance of the Laplacian. ROOT is a rendered
stand-in (``blurloc synth``); the length model was fitted on training splits only.
"""

from __future__ import annotations

import argparse
import time

from blurloc.experiments.blur_estimation import (
    estimation_rows,
    estimation_summary,
    motion_rank_correlation,
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="stand-in root with blur.csv files")
    parser.add_argument("--split", default="test")
    parser.add_argument("--every", type=int, default=1, help="use every n-th frame")
    args = parser.parse_args()

    start = time.perf_counter()
    rows = estimation_rows(args.root, args.split, args.every)
    per_frame_ms = (time.perf_counter() - start) / len(rows) * 1000
    print(f"{len(rows)} {args.split} frames of {args.root}, {per_frame_ms:.1f} ms per frame "
          f"(estimate + detector score)")  # fmt: skip
    for row in estimation_summary(rows):
        verdict = "met" if row["met"] else "NOT met"
        print(f"  {row['measure']:46s} {row['value']:8.3f}  target {row['target']:7s} "
              f"({row['frames']} frames) {verdict}")  # fmt: skip
    print("Spearman against the camera's image-plane motion (estimate / variance of Laplacian):")
    for row in motion_rank_correlation(args.root, args.split, args.every):
        print(f"  {row['scene']:10s} seq {row['sequence']:2d} ({row['frames']:4d} frames): "
              f"{row['estimate_spearman']:+.3f} / {row['laplacian_spearman']:+.3f}")  # fmt: skip


if __name__ == "__main__":
    main()
