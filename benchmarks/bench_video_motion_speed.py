"""Time per frame of deblurring by the video's own motion, at 160x120 and 640x480, panning and
turning, by grid and boundary, beside the mirror-boundary, one-kernel variant as the reference.

    python benchmarks/bench_video_motion_speed.py [--frames 20] [--out-dir figures]

Times :func:`blurloc.video_wiener.deblur_video_motion` on noise-free GoPro-style videos of
scikit-image's ``coffee`` (:func:`~blurloc.experiments.photo_video.photo_video`, a pan of 9 px
per frame at 160x120 and 36 px at 640x480; ``turning``: the same pan with the camera also
turning about its optical axis by 0.3 degrees per sub-frame) with a 3 x 3 grid of kernels
(``grid``; as shipped, a frame whose kernels agree restored once with one of them,
``agreement``: ``AGREEMENT_L1``, with the image beyond the frame unknown, the default with 10
conjugate-gradient steps, and with mirror boundaries, ``boundary``; ``off``: every frame by its
grid, unknown boundaries only) and with one kernel per frame (both boundaries), every one with
THREADS frames restored at once (the shipped defaults also with one, ``threads``), and reports
seconds per frame (measurement of the motion included, after one untimed call on two frames)
and the time over the one-kernel, mirror-boundary run of the same video, in one process. The
``methods`` table times ``blurloc deblur-video``'s three methods with their defaults on the same
videos: ``motion-network`` (:class:`~blurloc.inference.MotionNetworkRestorer`: the share read
from the video, the deconvolution, then the network), ``motion`` (the deconvolution with the
share read) and ``network`` (the shipped network alone), with the time of reading the share once
per video (:func:`~blurloc.blur.video_motion.calibrate_exposure_share`, ``share_reading_s``) and
the frames per second without it (``frames_per_second_once_read``: the rate of a video long
enough that the one reading does not count). Writes
``<out-dir>/bench_video_motion_speed.md``/``.csv`` (``-methods.csv``). About 6 min on 2 cores.
"""

from __future__ import annotations

import argparse
import itertools
import time

import skimage.data

from blurloc.blur.video_motion import calibrate_exposure_share, frame_shifts
from blurloc.experiments.photo_video import photo_video
from blurloc.inference import DEFAULT_CHECKPOINT, MotionNetworkRestorer, VideoRestorer
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.video_wiener import AGREEMENT_L1, THREADS, deblur_video_motion

#: (width, height) of the frames timed, and the pan per sub-frame (px) at each.
SIZES = (((160, 120), 1.0), ((640, 480), 4.0))
#: (label, the camera's turn about its optical axis per sub-frame in degrees).
MOTIONS = (("pan", 0.0), ("turning", 0.3))
#: (grid, boundary, agreement tolerance, threads) timed.
VARIANTS = ((3, "unknown", AGREEMENT_L1, THREADS), (3, "unknown", AGREEMENT_L1, 1),
            (3, "unknown", None, THREADS), (3, "mirror", AGREEMENT_L1, THREADS),
            (1, "unknown", None, THREADS), (1, "mirror", None, THREADS))  # fmt: skip
REFERENCE = (1, "mirror", None, THREADS)


def main() -> None:
    """Time every size, grid and boundary; write the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=20)
    add_out_dir_argument(parser)
    args = parser.parse_args()
    rows, method_rows = [], []
    methods = {"motion-network": MotionNetworkRestorer(),
               "motion": lambda video: deblur_video_motion(video, None),
               "network": VideoRestorer(DEFAULT_CHECKPOINT)}  # fmt: skip
    for (size, step), (motion, roll) in itertools.product(SIZES, MOTIONS):
        blurred, _ = photo_video(skimage.data.coffee(), frames=args.frames, step_px=step,
                                 angle_deg=20.0, size=size, noise_sigma=0.0, seed=1,
                                 roll_deg=roll)  # fmt: skip
        deblur_video_motion(blurred[:2])  # first calls set up OpenCV and FFT plans: untimed
        seconds = {}
        for grid, boundary, agreement, threads in VARIANTS:
            start = time.perf_counter()
            deblur_video_motion(blurred, grid=grid, boundary=boundary, agreement_l1=agreement,
                                threads=threads)  # fmt: skip
            seconds[grid, boundary, agreement, threads] = ((time.perf_counter() - start)
                                                           / len(blurred))  # fmt: skip
        for (grid, boundary, agreement, threads), value in seconds.items():
            rows.append({"size": f"{size[0]}x{size[1]}", "motion": motion, "grid": grid,
                         "boundary": boundary,
                         "agreement": "off" if agreement is None else agreement,
                         "threads": threads,
                         "seconds_per_frame": round(value, 3),
                         "frames_per_second": round(1.0 / value, 2),
                         "times_reference": round(value / seconds[REFERENCE], 1)})  # fmt: skip
            print(rows[-1], flush=True)
        for method in methods.values():
            method(blurred[:2])  # loads the networks (each method's own): untimed
        shifts = frame_shifts(blurred)
        start = time.perf_counter()
        calibrate_exposure_share(blurred, shifts)
        share_seconds = time.perf_counter() - start
        for name, method in methods.items():
            start = time.perf_counter()
            method(blurred)
            value = (time.perf_counter() - start) / len(blurred)
            ratio = value / seconds[REFERENCE]
            reads_share = name != "network"
            after_share = value - share_seconds / len(blurred) if reads_share else value
            method_rows.append({"size": f"{size[0]}x{size[1]}", "motion": motion,
                                "method": name, "seconds_per_frame": round(value, 3),
                                "frames_per_second": round(1.0 / value, 2),
                                "times_reference": round(ratio, 1),
                                "share_reading_s": round(share_seconds, 2) if reads_share else "",
                                "frames_per_second_once_read":
                                    round(1.0 / after_share, 2) if after_share > 0 else "",
                                })  # fmt: skip
            print(method_rows[-1], flush=True)
    notes = (f"{args.frames} frames per video; seconds per frame include measuring the motion "
             "between frames; agreement: the largest disagreement of a frame's grid kernels at "
             "which it is restored with one kernel (off: by its grid); threads: frames restored "
             "at once; times_reference: over grid 1 with mirror boundaries on the same "
             "video.")  # fmt: skip
    saved = save_benchmark_tables("bench_video_motion_speed",
                                  {"speed": rows, "methods": method_rows}, args.out_dir,
                                  notes=notes)  # fmt: skip
    print(f"tables: {saved}")


if __name__ == "__main__":
    main()
