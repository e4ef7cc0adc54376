"""Does ``blurloc deblur-video`` remove the blur of real camera frames? Real frames have no sharp
truth, so the blur left in each restored frame is measured blind and ranked against the
camera's own motion during the frame.

    BLURLOC_REAL_DATA=/path/to/real python benchmarks/video_real_blur.py [--out-dir figures]

Frames: the 80 consecutive real posed TUM RGB-D ``fr1_rpy`` frames of the development set (a
hand-held camera turned about its three axes; ``python samples/real/fetch.py --parts posed``
writes them), as one video, area-averaged to 160x120 and to 320x240. The camera's image motion of
each frame is :func:`~blurloc.experiments.real_frames.posed_frames_with_motion`'s (recorded poses
and depth alone). Methods: the frames as recorded, ``deblur-video``'s three methods
(``motion-network``, the default: :class:`~blurloc.inference.MotionNetworkRestorer`;
``motion``: :func:`~blurloc.video_wiener.deblur_video_motion` with the share read from the
video; ``network``: the paper's network alone, :class:`~blurloc.inference.VideoRestorer`).

Per method, the blur measures of :func:`~blurloc.experiments.real_frames.blur_measures` on its
frames (the blind length, the detector's score, the negated variance of the Laplacian) and the
Spearman correlation of each with the camera's motion: on the recorded frames the blind length
follows the motion (its blur is the camera's); a method that removes that blur leaves frames
whose remaining blur follows the motion less, and whose blind length is shorter where the
camera moved fast. Each method's blind-length correlation minus the recorded frames' comes with
a 95 % moving-block bootstrap interval (blocks of 10 frames,
:func:`~blurloc.experiments.real_frames.spearman_difference`); the median blind length over the
faster and the slower half of the frames (by the camera's motion) and the mean absolute change
of the frames (0-255) are reported beside it. These are proxies, not a restoration score: the
blind estimator was fitted on the stand-in and on blurred photographs, not on deconvolved frames
(ringing or amplified noise can read as shorter or longer blur), and the variance of the
Laplacian rises with amplified noise as well as with sharpness. Writes
``<out-dir>/video_real_blur.md``/``.csv``. About 1 min on 2 cores.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from blurloc.experiments.real_frames import (
    blur_measures,
    motion_agreement,
    posed_frames_with_motion,
    resized_frames,
    spearman_difference,
)
from blurloc.inference import DEFAULT_CHECKPOINT, MotionNetworkRestorer, VideoRestorer
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.video_wiener import deblur_video_motion

#: Area-averaging factors of the 640x480 frames (4: 160x120, the networks' training size).
SCALES = (4, 2)
LENGTH = "blind length (px)"


def methods() -> dict:
    """The recorded frames and ``deblur-video``'s three methods, by name."""
    return {"as recorded": lambda video: video,
            "motion-network": MotionNetworkRestorer(),
            "motion": lambda video: deblur_video_motion(video, None),
            "network": VideoRestorer(DEFAULT_CHECKPOINT)}  # fmt: skip


def main() -> None:
    """Restore the real frames with every method, measure their blur, write the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_out_dir_argument(parser)
    args = parser.parse_args()
    started = time.time()
    images, motion = posed_frames_with_motion()
    faster = motion > np.median(motion)
    rows = []
    for scale in SCALES:
        video = np.stack(resized_frames(images, scale))
        size = f"{video.shape[2]}x{video.shape[1]}"
        recorded = None
        for name, method in methods().items():
            restored = method(video)
            measures = blur_measures(restored)
            if recorded is None:
                recorded = measures
            row = {"size": size, "method": name, "frames": len(video)}
            for agreement in motion_agreement(measures, motion):
                row[f"spearman {agreement['measure']}"] = agreement["spearman"]
            if name != "as recorded":
                difference = spearman_difference(measures[LENGTH], recorded[LENGTH], motion)
                row["blind length spearman minus recorded [95 %]"] = (
                    f"{difference.mean:+.3f} [{difference.low:+.3f}, {difference.high:+.3f}]"
                )
            else:
                row["blind length spearman minus recorded [95 %]"] = ""
            row["median blind length, faster half (px)"] = round(
                float(np.median(measures[LENGTH][faster])), 2
            )
            row["median blind length, slower half (px)"] = round(
                float(np.median(measures[LENGTH][~faster])), 2
            )
            row["mean absolute change (0-255)"] = round(
                float(np.mean(np.abs(restored.astype(float) - video.astype(float)))), 2
            )
            rows.append(row)
            print(row, flush=True)
    notes = (f"80 real TUM RGB-D fr1_rpy frames (one video), camera image motion per frame "
             f"interval median {np.median(motion):.1f} px at 640x480; Spearman of each blur "
             "measure (larger = more blur) with it; the faster half: frames above the median "
             "motion. No sharp truth: proxies only (see the benchmark's docstring). "
             f"{time.time() - started:.0f} s on 2 CPU cores.")  # fmt: skip
    saved = save_benchmark_tables("video_real_blur", {"measures": rows}, args.out_dir,
                                  notes=notes)  # fmt: skip
    print(f"tables: {saved}")


if __name__ == "__main__":
    main()
