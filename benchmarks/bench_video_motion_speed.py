"""Time per frame of deblurring by the video's own motion, at 160x120 and 640x480, by grid and
boundary, beside the mirror-boundary, one-kernel variant as the reference.

    python benchmarks/bench_video_motion_speed.py [--frames 6] [--out-dir figures]

Times :func:`blurloc.video_wiener.deblur_video_motion` on a noise-free GoPro-style video of
scikit-image's ``coffee`` (:func:`~blurloc.experiments.photo_video.photo_video`, a pan of 9 px
per frame at 160x120 and 36 px at 640x480) with a 3 x 3 grid of kernels and with one kernel per
frame (``grid``), each with the image beyond the frame unknown (the default, 10
conjugate-gradient steps) and with mirror boundaries (``boundary``), and reports seconds per
frame (measurement of the motion included) and the time over the one-kernel, mirror-boundary
run at the same size, in one process. Writes
``<out-dir>/bench_video_motion_speed.md``/``.csv``. About 2 min on 2 cores.
"""

from __future__ import annotations

import argparse
import time

import skimage.data

from blurloc.experiments.photo_video import photo_video
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.video_wiener import deblur_video_motion

#: (width, height) of the frames timed, and the pan per sub-frame (px) at each.
SIZES = (((160, 120), 1.0), ((640, 480), 4.0))
VARIANTS = ((3, "unknown"), (3, "mirror"), (1, "unknown"), (1, "mirror"))
REFERENCE = (1, "mirror")


def main() -> None:
    """Time every size, grid and boundary; write the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=6)
    add_out_dir_argument(parser)
    args = parser.parse_args()
    rows = []
    for size, step in SIZES:
        blurred, _ = photo_video(skimage.data.coffee(), frames=args.frames, step_px=step,
                                 angle_deg=20.0, size=size, noise_sigma=0.0, seed=1)  # fmt: skip
        seconds = {}
        for grid, boundary in VARIANTS:
            start = time.perf_counter()
            deblur_video_motion(blurred, grid=grid, boundary=boundary)
            seconds[grid, boundary] = (time.perf_counter() - start) / len(blurred)
        for (grid, boundary), value in seconds.items():
            rows.append({"size": f"{size[0]}x{size[1]}", "grid": grid, "boundary": boundary,
                         "seconds_per_frame": round(value, 3),
                         "frames_per_second": round(1.0 / value, 2),
                         "times_reference": round(value / seconds[REFERENCE], 1)})  # fmt: skip
            print(rows[-1], flush=True)
    notes = (f"{args.frames} frames per video; seconds per frame include measuring the motion "
             "between frames; times_reference: over grid 1 with mirror boundaries at the same "
             "size.")  # fmt: skip
    saved = save_benchmark_tables("bench_video_motion_speed", {"speed": rows}, args.out_dir,
                                  notes=notes)  # fmt: skip
    print(f"tables: {saved}")


if __name__ == "__main__":
    main()
