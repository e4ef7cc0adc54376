"""What limits deblurring by the video's own motion: the same Wiener step told the true motion.

    python benchmarks/motion_wiener_bounds.py [--border 16] [--out-dir figures]

On the 15 GoPro-style photo videos of
:func:`~blurloc.experiments.photo_video.photo_video_gains` (8 frames each, without noise and
with sigma = 0.01), whose camera path is known exactly
(:func:`~blurloc.experiments.photo_video.photo_video_motion`), every frame is deconvolved by
the restoration step of :func:`blurloc.video_wiener.deblur_video_motion`
(:func:`~blurloc.video_wiener.deblur_by_kernels`: the gradient regulariser, its weight
WEIGHT_PER_NOISE times the frame's estimated noise with a floor) with the kernel of one of
three paths:

- ``measured motion``: the method with one kernel per frame (``deblur_video_motion(...,
  grid=1)``; these pans move the whole image as one), the 3-point path through the positions
  measured between the blurred frames (:func:`~blurloc.blur.frame_shifts`), moved from the
  blurs' centroids to mid-exposure (:func:`~blurloc.blur.mid_exposure_shifts`);
- ``true positions, 3-point path``: the same path model through the true frame positions, so
  that only the measurement of the motion is removed;
- ``true exposure path``: the path the pan took during each exposure (its wobble included),
  so that the kernel is the one that made the blur: what a Wiener step can gain at best with
  that floor.

Without noise each at the weight floors WEIGHTS (the shipped one, MIN_WEIGHT, among them; the
others are not chosen on anything, so the best of them on these videos is an oracle); with
noise at the shipped floor only (the noise's weight, WEIGHT_PER_NOISE sigma, lies above it).
Each with mirror boundaries and with the image beyond the frame unknown
(:func:`~blurloc.deconv.wiener_deconvolve`'s BOUNDARIES; the shipped one: BOUNDARY), and, for
the measured motion without noise, with ITERATIONS conjugate-gradient steps of the unknown
boundary's solve.
Scored on the whole frame and on the frame without a ``--border`` px margin (where the pan
brings in content the frame does not hold). Gains: PSNR of the restored video minus the blurred
one's (eq. 6, mean over frames), dB; paired rows: each path and floor minus the method at the
shipped floor, in the same region, per video, 95 % t-interval. The shift table gives the
distance between the measured and the true motion (of the middle sub-frames) from each frame to
the next, as measured between the blurred frames and once moved to mid-exposure. Writes
``<out-dir>/motion_wiener_bounds.md``/``.csv`` (``-iterations.csv``; ``-shifts.csv``;
``-videos.csv``: one row per video). About 2 min on 2 cores.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from video_motion_deblur import lead

from blurloc.blur import exposure_paths, frame_shifts, mid_exposure_shifts, trajectory_kernel
from blurloc.blur.video_motion import path_length
from blurloc.deconv import BOUNDARIES, BOUNDARY_ITERATIONS
from blurloc.experiments.photo_video import photo_video_motion, photo_video_set
from blurloc.intervals import paired_interval
from blurloc.metrics import mean_frame_psnr
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.video_wiener import BOUNDARY, MIN_WEIGHT, deblur_by_kernels

WEIGHTS = tuple(sorted({0.02, 0.05, 0.1, 0.2, MIN_WEIGHT}))
FRAMES = 8
SUBFRAMES = 9
#: Sets: noise sigma and the floors run (with noise the noise's weight, WEIGHT_PER_NOISE sigma,
#: lies above the shipped floor, which alone is run).
SETS = {"photo videos, no noise": (0.0, WEIGHTS), "photo videos, sigma 0.01": (0.01, (MIN_WEIGHT,))}
METHOD = "measured motion"
#: Conjugate-gradient steps of the unknown-boundary solve tried (the iterations table).
ITERATIONS = (0, 3, 5, BOUNDARY_ITERATIONS, 20, 40)


def test_videos(noise_sigma: float):
    """The photo-video set (:func:`~blurloc.experiments.photo_video.photo_video_set`):
    (label, blurred, sharp, content positions) per video."""
    for video in photo_video_set(FRAMES, noise_sigma):
        yield (f"{video.photo} {video.step_px} px", video.blurred, video.sharp,
               photo_video_motion(FRAMES, SUBFRAMES, video.step_px, video.angle_deg))  # fmt: skip


def path_sets(blurred: np.ndarray, positions: np.ndarray) -> tuple[dict, dict]:
    """The three paths per frame (name -> list of (N, 2) paths) and the measured shifts' errors
    against the true ones (px, one per frame pair), as measured and moved to mid-exposure."""
    middle = positions[:, SUBFRAMES // 2]
    true_shifts = np.diff(middle, axis=0)
    measured = frame_shifts(blurred)
    moved = mid_exposure_shifts(measured, 1.0)
    paths = {
        METHOD: exposure_paths(moved, 1.0),
        "true positions, 3-point path": exposure_paths(true_shifts, 1.0),
        "true exposure path": list(positions - middle[:, None, :]),
    }
    errors = {
        "between the blurred frames": np.linalg.norm(measured - true_shifts, axis=1),
        "moved to mid-exposure": np.linalg.norm(moved - true_shifts, axis=1),
    }
    return paths, errors


def video_gain(restored: np.ndarray, blurred: np.ndarray, sharp: np.ndarray, border: int) -> float:
    """PSNR gain (dB, mean over frames) of ``restored`` over ``blurred`` without ``border`` px."""
    inner = np.s_[:, border : sharp.shape[1] - border, border : sharp.shape[2] - border]
    return mean_frame_psnr([(restored[inner], sharp[inner])]) - mean_frame_psnr(
        [(blurred[inner], sharp[inner])]
    )


def main() -> None:
    """Restore every test photo video by every path, floor and boundary, write the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--border", type=int, default=16, help="margin left out, px")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    start = time.perf_counter()
    regions = {"whole frame": 0, f"without a {args.border} px border": args.border}
    video_rows, shift_rows, gains, iteration_rows = [], [], {}, {}
    for set_name, (noise, weights) in SETS.items():
        errors = {}
        for label, blurred, sharp, positions in test_videos(noise):
            paths, shift_errors = path_sets(blurred, positions)
            for measurement, values in shift_errors.items():
                errors.setdefault(measurement, []).append(values)
            for path_name, frame_paths in paths.items():
                kernels = [trajectory_kernel(path, origin=np.zeros(2)) for path in frame_paths]
                lengths = np.array([path_length(path) for path in frame_paths])
                for weight in weights:
                    for boundary in BOUNDARIES:
                        restored = deblur_by_kernels(blurred, kernels, lengths, weight, boundary)
                        for region, border in regions.items():
                            value = video_gain(restored, blurred, sharp, border)
                            key = (set_name, path_name, weight, boundary, region)
                            gains.setdefault(key, []).append(value)
                            video_rows.append({"set": set_name, "path": path_name,
                                               "min_weight": weight, "boundary": boundary,
                                               "region": region, "video": label,
                                               "gain_db": round(value, 3)})  # fmt: skip
            if noise == 0.0:
                kernels = [trajectory_kernel(path, origin=np.zeros(2)) for path in paths[METHOD]]
                lengths = np.array([path_length(path) for path in paths[METHOD]])
                for iterations in ITERATIONS:
                    restored = deblur_by_kernels(blurred, kernels, lengths, MIN_WEIGHT, "unknown",
                                                 iterations)  # fmt: skip
                    value = video_gain(restored, blurred, sharp, 0)
                    iteration_rows.setdefault(iterations, []).append(value)
        for measurement, values in errors.items():
            values = np.concatenate(values)
            shift_rows.append({"set": set_name, "shifts": measurement,
                               "frame_pairs": len(values),
                               "mean_error_px": round(float(values.mean()), 3),
                               "median_error_px": round(float(np.median(values)), 3),
                               "max_error_px": round(float(values.max()), 3)})  # fmt: skip
    summary = []
    for (set_name, path_name, weight, boundary, region), values in gains.items():
        row = {"set": set_name, "path": path_name, "min_weight": weight, "boundary": boundary,
               "region": region, "videos": len(values),
               "mean_gain_db": round(float(np.mean(values)), 3),
               "worst_video_db": round(float(np.min(values)), 3),
               "videos_above_0": int(np.sum(np.array(values) > 0)),
               "minus_method_db": "", "ci_low": "", "ci_high": "", "verdict": ""}  # fmt: skip
        reference = gains[(set_name, METHOD, MIN_WEIGHT, BOUNDARY, region)]
        if (path_name, weight, boundary) != (METHOD, MIN_WEIGHT, BOUNDARY):
            interval = paired_interval(np.array(values) - reference, method="t")
            row.update({"minus_method_db": round(interval.mean, 3),
                        "ci_low": round(interval.low, 3), "ci_high": round(interval.high, 3),
                        "verdict": lead(interval, "the path")})  # fmt: skip
        summary.append(row)
    most = iteration_rows[max(ITERATIONS)]
    iterations_table = []
    for iterations, values in iteration_rows.items():
        interval = paired_interval(np.array(values) - most, method="t")
        iterations_table.append({"iterations": iterations, "videos": len(values),
                                 "mean_gain_db": round(float(np.mean(values)), 3),
                                 "worst_video_db": round(float(np.min(values)), 3),
                                 "minus_most_db": round(interval.mean, 3),
                                 "ci_low": round(interval.low, 3),
                                 "ci_high": round(interval.high, 3)})  # fmt: skip
    notes = (f"The 15 photo videos of photo_video_gains ({FRAMES} frames, {SUBFRAMES} sub-frames "
             "each), every frame deconvolved by deblur_by_kernels (the restoration step of "
             "deblur_video_motion) with the kernel of each path, at each floor of the "
             f"regulariser's weight (shipped: {MIN_WEIGHT}), with mirror boundaries and with the "
             f"image beyond the frame unknown (shipped: {BOUNDARY}). Gains: PSNR of the restored "
             "video minus the blurred one's (eq. 6, mean over frames), dB, over the 15 videos; "
             f"minus_method: the path, floor and boundary minus '{METHOD}' at {MIN_WEIGHT} with "
             f"{BOUNDARY} boundaries, in the same region, per video, 95 % t-interval. Floors "
             "other than the shipped one are not chosen on anything: the best of them on these "
             "videos is an oracle. Iterations: the conjugate-gradient steps of the unknown "
             f"boundary's solve (shipped: {BOUNDARY_ITERATIONS}; 0: the mirror result it starts "
             f"from), '{METHOD}' without noise at the shipped floor, whole frame; minus_most: "
             f"minus {max(ITERATIONS)} steps, per video, 95 % t-interval. "
             f"{time.perf_counter() - start:.0f} s on 2 CPU cores.")  # fmt: skip
    saved = save_benchmark_tables(
        "motion_wiener_bounds",
        {
            "results": summary,
            "iterations": iterations_table,
            "shifts": shift_rows,
            "videos": video_rows,
        },
        args.out_dir,
        notes=notes,
    )
    print(f"tables: {saved}")


if __name__ == "__main__":
    main()
