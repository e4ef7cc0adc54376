"""Choosing when a frame's grid kernels agree enough to restore it with one kernel.

    python benchmarks/choose_kernel_agreement.py [--out-dir figures]

:func:`blurloc.video_wiener.deblur_video_motion` measures each frame's kernel at the points of
a 3 x 3 grid and restores the frame tile by tile; where the kernels agree (a pan, which moves
the image alike everywhere) one restoration of the whole frame with the middle kernel does the
same work in a fraction of the time. This script chooses the largest disagreement
(:func:`~blurloc.video_wiener.kernel_disagreement`, CANDIDATES) at which that holds, on
GoPro-style videos of the photographs that the test videos do not show
(:func:`~blurloc.experiments.photo_video.photo_training_videos`, 12 videos of 12 frames per
set): pans without noise and with sigma = 0.01, and pans without noise with the camera also
turning about its optical axis by 0.1 and 0.3 degrees per sub-frame or moving towards the
photograph by 0.3 % per sub-frame, the motions of the test sets. Each video's motion is measured
once; every candidate restores it (``None``: every frame by its grid). Per set and candidate:
the mean gain over videos (PSNR of the restored video minus the blurred one's, eq. 6), the
worst video, the share of frames restored with one kernel, the restoration's seconds per frame
and the mean change of gain against the grid. Chosen: the largest candidate whose mean gain on
every set is at most MAX_LOSS_DB below the grid's (the package's AGREEMENT_L1 is this choice).
Writes ``<out-dir>/choose_kernel_agreement.md``/``.csv``. About 6 min on 2 cores.
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from blurloc.blur import DEFAULT_EXPOSURE_SHARE, LOCAL_GRID, local_motion_kernels
from blurloc.experiments.photo_video import photo_training_videos
from blurloc.metrics import mean_frame_psnr
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.video_wiener import AGREEMENT_L1, deblur_by_local_kernels, kernel_disagreement

#: Disagreements tried (None: every frame by its grid; 2: every frame with one kernel).
CANDIDATES = (None, 0.1, 0.2, 0.3, 0.5, 0.8, 2.0)
#: (label, noise sigma, turn in degrees and magnification per sub-frame) of the training sets.
SETS = (("pans", 0.0, 0.0, 0.0), ("pans, sigma 0.01", 0.01, 0.0, 0.0),
        ("turning 0.1 deg", 0.0, 0.1, 0.0), ("turning 0.3 deg", 0.0, 0.3, 0.0),
        ("moving forward 0.3 %", 0.0, 0.0, 0.003))  # fmt: skip
#: Largest loss of mean gain against the grid that a candidate may cost on any set, dB.
MAX_LOSS_DB = 0.05


def main() -> None:
    """Score every candidate on every training set; choose; write the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_out_dir_argument(parser)
    args = parser.parse_args()
    rows = []
    for label, noise, roll, zoom in SETS:
        videos = photo_training_videos(12, frames=12, seed=1, noise_sigma=noise, roll_deg=roll,
                                       zoom=zoom)  # fmt: skip
        gains = {candidate: [] for candidate in CANDIDATES}
        seconds = dict.fromkeys(CANDIDATES, 0.0)
        disagreements = []
        for blurred, sharp in videos:
            motion = local_motion_kernels(blurred, DEFAULT_EXPOSURE_SHARE, LOCAL_GRID)
            disagreements += [kernel_disagreement(kernels) for kernels in motion.kernels]
            before = mean_frame_psnr([(blurred, sharp)])
            for candidate in CANDIDATES:
                start = time.perf_counter()
                restored = deblur_by_local_kernels(blurred, motion.kernels, motion.lengths_px,
                                                   motion.grid, agreement_l1=candidate)  # fmt: skip
                seconds[candidate] += time.perf_counter() - start
                gains[candidate].append(mean_frame_psnr([(restored, sharp)]) - before)
        frames = len(disagreements)
        for candidate in CANDIDATES:
            one_kernel = np.mean([value <= candidate for value in disagreements]) if candidate \
                is not None else 0.0  # fmt: skip
            rows.append({
                "set": label, "agreement_l1": "grid" if candidate is None else candidate,
                "mean_gain_db": round(float(np.mean(gains[candidate])), 3),
                "worst_video_db": round(float(np.min(gains[candidate])), 3),
                "change_vs_grid_db": round(float(np.mean(gains[candidate])
                                                 - np.mean(gains[None])), 3),
                "frames_one_kernel": round(float(one_kernel), 2),
                "seconds_per_frame": round(seconds[candidate] / frames, 4),
            })  # fmt: skip
            print(rows[-1], flush=True)
    eligible = [candidate for candidate in CANDIDATES if candidate is not None and all(
        row["change_vs_grid_db"] >= -MAX_LOSS_DB for row in rows
        if row["agreement_l1"] == candidate)]  # fmt: skip
    chosen = max(eligible) if eligible else None
    print(f"chosen agreement_l1: {chosen} (package default {AGREEMENT_L1})")
    if chosen != AGREEMENT_L1:
        print("the choice differs from the package's AGREEMENT_L1: update it", file=sys.stderr)
    notes = (
        f"12 training photo videos of 12 frames per set (photographs the test videos do not "
        f"show); seconds per frame: the restoration alone, the motion measured once. "
        f"Chosen: {chosen}, the largest candidate whose mean gain on every set is at most "
        f"{MAX_LOSS_DB} dB below the grid's; the package's AGREEMENT_L1 is {AGREEMENT_L1}."
    )
    saved = save_benchmark_tables("choose_kernel_agreement", {"candidates": rows}, args.out_dir,
                                  notes=notes)  # fmt: skip
    print(f"tables: {saved}")


if __name__ == "__main__":
    main()
