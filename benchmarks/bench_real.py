"""The stages measured on the real development set (``samples/real``, see its README) beside
the stand-in's test split, in one run.

    python benchmarks/bench_real.py [--out-dir figures] [--standin data/standin]
                                    [--budget 600]

Measures, with the package's current API and defaults:

- blur detection (:func:`blurloc.blur.detect_blur`): the share of real sharp photographs
  reported sharp and the share of real blurred photographs flagged, with every score;
- blind blur length on the 80 consecutive posed TUM RGB-D frames: Spearman rank correlation of
  :func:`blurloc.blur.estimate_motion_blur`'s length, of the detector's score and of the negated
  variance of the Laplacian with the camera's image motion, at 640x480 and at 320x240, over all
  frames and over the half with the slower motion, and the length's lead over the variance of
  the Laplacian with its 95 % moving-block bootstrap interval
  (:func:`~blurloc.experiments.real_frames.spearman_difference`); and the same rank
  correlation of each frame's exposure path length from the video's own motion
  (:func:`~blurloc.experiments.real_frames.video_motion_lengths`);
- blind Wiener deblurring (:func:`blurloc.deconv.deblur_blind`): PSNR against the sharp frame
  before and after, on the real blurred/sharp pairs;
- the TUM reader of ``pose-error`` (:func:`blurloc.trajectory.read_tum`) on the real TUM files;
- on the stand-in (rows marked "stand-in"): the estimator and detector against the blur it
  recorded, and the same rank correlations with the camera's image motion.

The camera's image motion of a frame is
:func:`~blurloc.experiments.blur_estimation.camera_motion_px`: the mean displacement of a grid
of pixels, placed at the frame's median depth, between the poses of the frames before and after
it, halved: px per frame interval. The motion during the exposure is that times exposure / frame
interval; the Kinect's exposure is not recorded, and a constant factor leaves rank correlations
unchanged.
Lens distortion is ignored. Writes ``<out-dir>/bench_real.md``, ``bench_real.csv`` (one row per
measure) and ``bench_real-photographs.csv`` (one row per photograph).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from blurloc.blur import BLUR_THRESHOLD
from blurloc.data.real import tum_files, verify
from blurloc.experiments.blur_estimation import (
    estimation_rows,
    estimation_summary,
    motion_rank_correlation,
)
from blurloc.experiments.real_frames import (
    blur_measures,
    motion_agreement,
    pair_restorations,
    photograph_verdicts,
    posed_frames_with_motion,
    spearman_difference,
    video_motion_lengths,
)
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.trajectory import read_tum


def detection_rows(rows: list[dict]) -> list[dict]:
    """Blur detection on real photographs; returns one row per photograph
    (:func:`~blurloc.experiments.real_frames.photograph_verdicts`). The share is given over all
    photographs and over those the length model was not fitted on."""
    photographs = photograph_verdicts()
    for part in ("sharp", "blurred"):
        measure = "share reported sharp" if part == "sharp" else "share flagged blurred"
        mine = [row for row in photographs if row["part"] == part]
        unseen = [row for row in mine if not row["fitted_on"]]
        for label, chosen in (("", mine), (", not fitted on", unseen)):
            share = round(float(np.mean([row["correct"] for row in chosen])), 3)
            rows.append({"stage": "detect_blur", "data": f"real {part} photographs{label}",
                         "n": len(chosen), "measure": measure, "value": share,
                         "target": ">= 0.9"})  # fmt: skip
    return photographs


def motion_rows(rows: list[dict]) -> None:
    """Rank correlations of blur measures with the camera's image motion on the posed frames,
    at 640x480 and 320x240, over all frames and over the half with the slower motion."""
    images, motion = posed_frames_with_motion()
    rows.append({"stage": "camera motion", "data": "real TUM fr1_rpy frames", "n": len(motion),
                 "measure": "image motion per frame interval, px (median; 5th-95th pct)",
                 "value": f"{np.median(motion):.1f} ({np.percentile(motion, 5):.1f}-"
                          f"{np.percentile(motion, 95):.1f})", "target": ""})  # fmt: skip
    slower = motion <= np.median(motion)
    for scale in (1, 2):
        size = f"{images.shape[2] // scale}x{images.shape[1] // scale}"
        measures = blur_measures(images, scale)
        for subset, chosen in (("", np.ones_like(slower)), (", slower half", slower)):
            picked = {name: values[chosen] for name, values in measures.items()}
            for row in motion_agreement(picked, motion[chosen]):
                rows.append({"stage": row["measure"],
                             "data": f"real TUM fr1_rpy frames, {size}{subset}",
                             "n": row["frames"], "measure": "Spearman with camera image motion",
                             "value": row["spearman"],
                             "target": ">= 0.5" if "length" in row["measure"] else ""})  # fmt: skip
        video = video_motion_lengths(images, scale)
        for subset, chosen in (("", np.ones_like(slower)), (", slower half", slower)):
            (row,) = motion_agreement({"video motion path (blur.video_motion_kernels)":
                                       video[chosen]}, motion[chosen])  # fmt: skip
            rows.append({"stage": row["measure"],
                         "data": f"real TUM fr1_rpy frames, {size}{subset}",
                         "n": row["frames"], "measure": "Spearman with camera image motion",
                         "value": row["spearman"], "target": ""})  # fmt: skip
        difference = spearman_difference(
            measures["blind length (px)"], measures["negated variance of the Laplacian"], motion
        )
        rows.append({"stage": "blind length minus variance of the Laplacian",
                     "data": f"real TUM fr1_rpy frames, {size}", "n": difference.pairs,
                     "measure": "difference of Spearman with camera image motion [95 % "
                                "moving-block bootstrap interval, blocks of 10 frames]",
                     "value": f"{difference.mean:+.3f} [{difference.low:+.3f}, "
                              f"{difference.high:+.3f}]", "target": "> 0"})  # fmt: skip
        flagged = np.mean(measures["detector score (px)"] > BLUR_THRESHOLD)
        rows.append({"stage": "detect_blur", "data": f"real TUM fr1_rpy frames, {size}",
                     "n": len(images), "measure": "share flagged blurred",
                     "value": round(float(flagged), 3), "target": ""})  # fmt: skip


def standin_rows(rows: list[dict], root: Path, budget: int) -> None:
    """The same stages on the stand-in's test split, beside the real rows: the estimator and
    detector against the recorded blur (``blur.csv``), and the rank correlation of the length and
    of the variance of the Laplacian with the camera's image motion."""
    data = f"stand-in test split ({root.name}, about {budget} frames)"
    for summary in estimation_summary(estimation_rows(root, "test", budget)):
        rows.append({"stage": "estimate_motion_blur / detect_blur", "data": data,
                     "n": summary["frames"], "measure": summary["measure"],
                     "value": summary["value"], "target": summary["target"]})  # fmt: skip
    overall = motion_rank_correlation(root, "test", budget)[-1]
    for stage, key in (("estimate_motion_blur length", "estimate_spearman"),
                       ("negated variance of the Laplacian", "laplacian_spearman")):  # fmt: skip
        rows.append({"stage": stage, "data": data, "n": overall["frames"],
                     "measure": "Spearman with camera image motion", "value": overall[key],
                     "target": ">= 0.5" if "length" in stage else ""})  # fmt: skip


def deblur_rows(rows: list[dict]) -> None:
    """PSNR of blind Wiener deblurring against the sharp frame on the real pairs."""
    for pair in pair_restorations():
        before, after = pair["blurred_psnr_db"], pair["deblurred_psnr_db"]
        rows.append({"stage": "deblur_blind", "data": f"real pair {pair['pair']}", "n": 1,
                     "measure": "PSNR dB: blurred -> deblurred (change)",
                     "value": f"{before:.2f} -> {after:.2f} ({pair['change_db']:+.2f})",
                     "target": "> 0 change"})  # fmt: skip


def tum_rows(rows: list[dict]) -> None:
    """Whether the TUM reader of ``pose-error`` accepts each real ground-truth file."""
    for path in tum_files():
        try:
            stamps, _, _ = read_tum(path)
            value = f"read {len(stamps)} poses"
        except ValueError as error:
            value = f"refused: {error}"
        rows.append({"stage": "read_tum (pose-error)", "data": path.name, "n": 1,
                     "measure": "accepts the real file", "value": value,
                     "target": "accepted"})  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_out_dir_argument(parser)
    parser.add_argument(
        "--standin",
        default="data/standin",
        help="stand-in root measured beside the real data (blurloc synth)",
    )
    parser.add_argument("--budget", type=int, default=600,
                        help="about how many stand-in test frames to read")  # fmt: skip
    args = parser.parse_args()
    if not (Path(args.standin) / "standin.json").is_file():
        parser.error(f"--standin {args.standin}: no stand-in there (make one with blurloc synth)")
    verify()
    rows: list[dict] = []
    detection = detection_rows(rows)
    motion_rows(rows)
    deblur_rows(rows)
    tum_rows(rows)
    standin_rows(rows, Path(args.standin), args.budget)
    for row in rows:
        print(" | ".join(str(v) for v in row.values()))
    save_benchmark_tables(
        "bench_real",
        {"measures": rows, "photographs": detection},
        args.out_dir,
        "The stages on the real development set beside the stand-in",
        notes="Photographs: `detect_blur` at its default threshold, one row each.",
    )


if __name__ == "__main__":
    main()
