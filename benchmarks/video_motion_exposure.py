"""Deblurring by the video's own motion when the camera's exposure share is not known: the
default share, the share calibrated on the video, and the true one.

    python benchmarks/video_motion_exposure.py [--standin data/standin]
        [--clean-standin data/standin-clean-s8] [--frames 50] [--out-dir figures]

:func:`blurloc.video_wiener.deblur_video_motion` builds each frame's kernel from the image's
path during the exposure, a share of the frame interval that is a setting of the camera. This
script restores, with the package's defaults otherwise:

- the 15 noise-free GoPro-style photo videos of
  :func:`~blurloc.experiments.photo_video.photo_video_gains` (8 frames) with each frame
  averaging 5, 9 or 17 of every 9 sub-frames (exposure shares 0.56, 1 and 1.89), and the same
  with sigma = 0.01 noise;
- when given, the first ``--frames`` frames of every test sequence of ``--standin`` and
  ``--clean-standin`` (exposure: the render's blur strength, 2.2 frame intervals by default),

each with the fixed DEFAULT_EXPOSURE_SHARE (``default``), with the share read from the video
(``calibrated``: ``exposure_share=None``, :func:`~blurloc.blur.calibrate_exposure_share`, the
default where it tells no share apart) and with the true share (``true``). Per set: the shares
calibrated (median, range, videos where none was told apart), the mean gain over videos (PSNR
of the restored video minus the blurred one's, eq. 6), the worst video, and calibrated minus
default paired by video with a 95 % t-interval. Writes ``<out-dir>/video_motion_exposure.md``/
``.csv`` (``-videos.csv``: one row per video and method). About 10 min on 2 cores.
"""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from blurloc.blur import DEFAULT_EXPOSURE_SHARE, calibrate_exposure_share, frame_shifts
from blurloc.data import list_scenes, load_split
from blurloc.data.manifest import render_settings
from blurloc.experiments.photo_video import photo_video_set, restoration_psnr
from blurloc.intervals import paired_interval
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.video_wiener import deblur_video_motion

#: Sub-frames averaged into each photo-video frame, of every 9 (exposure share: this over 9).
EXPOSURES = (5, 9, 17)
#: Noise sigmas of the photo videos.
NOISES = (0.0, 0.01)


def photo_sets() -> Iterator[tuple[str, float, list[tuple[str, np.ndarray, np.ndarray]]]]:
    """(label, true share, videos) of the photo videos at every exposure and noise."""
    for noise in NOISES:
        for exposure in EXPOSURES:
            videos = [
                (f"{video.photo} {video.step_px} px", video.blurred, video.sharp)
                for video in photo_video_set(8, noise, exposure_subframes=exposure)
            ]
            yield (f"photo videos, exposure {exposure}/9, sigma {noise}", exposure / 9,
                   videos)  # fmt: skip


def standin_set(root: Path, frames: int) -> tuple[float, list[tuple[str, np.ndarray, np.ndarray]]]:
    """(the render's exposure share, videos) of a stand-in's test sequences."""
    share = float(render_settings(root)["blur_strength"])
    videos = [(f"{scene} {sequence.folder.name}", sequence.images("color", ids),
               sequence.images("sharp", ids))
              for scene in list_scenes(root) for sequence in load_split(root, scene, "test")
              for ids in [sequence.frame_ids[:frames]]]  # fmt: skip
    return share, videos


def main() -> None:
    """Restore every set with the default, calibrated and true share; write the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--standin", type=Path)
    parser.add_argument("--clean-standin", type=Path)
    parser.add_argument("--frames", type=int, default=50)
    add_out_dir_argument(parser)
    args = parser.parse_args()
    sets = list(photo_sets())
    for label, root in (("stand-in as rendered (noisy)", args.standin),
                        ("stand-in without noise", args.clean_standin)):  # fmt: skip
        if root is not None:
            sets.append((label, *standin_set(root, args.frames)))
    rows, video_rows = [], []
    for label, true_share, videos in sets:
        gains = {"default": [], "calibrated": [], "true": []}
        read = []
        for name, blurred, sharp in videos:
            share = calibrate_exposure_share(blurred, frame_shifts(blurred))
            read.append(np.nan if share is None else share)
            shares = {
                "default": DEFAULT_EXPOSURE_SHARE,
                "calibrated": share or DEFAULT_EXPOSURE_SHARE,
                "true": true_share,
            }
            for method, value in shares.items():
                before, after = restoration_psnr(lambda v, s=value: deblur_video_motion(v, s),
                                                 blurred, sharp)  # fmt: skip
                gains[method].append(after - before)
                video_rows.append({"set": label, "video": name, "method": method,
                                   "exposure_share": round(value, 3),
                                   "gain_db": round(after - before, 3)})  # fmt: skip
        told = np.array(read)[np.isfinite(read)]
        interval = paired_interval(np.subtract(gains["calibrated"], gains["default"]), method="t")
        rows.append({
            "set": label, "videos": len(videos), "true_share": round(true_share, 2),
            "calibrated_median": round(float(np.median(told)), 2) if len(told) else "",
            "calibrated_range": f"{told.min():.2f}-{told.max():.2f}" if len(told) else "",
            "none_told_apart": int(len(read) - len(told)),
            **{f"{method}_mean_gain_db": round(float(np.mean(values)), 3)
               for method, values in gains.items()},
            **{f"{method}_worst_video_db": round(float(np.min(values)), 3)
               for method, values in gains.items()},
            "calibrated_minus_default_db": round(interval.mean, 3),
            "ci_low": round(interval.low, 3), "ci_high": round(interval.high, 3),
            "verdict": ("calibrated higher" if interval.low > 0 else "calibrated lower"
                        if interval.high < 0 else f"not resolved (±{interval.half_width:.2f} dB)"),
        })  # fmt: skip
        print(rows[-1], flush=True)
    notes = ("deblur_video_motion with its defaults but for the exposure share: default "
             f"{DEFAULT_EXPOSURE_SHARE}; calibrated: read from each video by "
             "blur.calibrate_exposure_share (the default where it tells no share apart: "
             "none_told_apart); true: the share the video was made with. Photo videos: 8 frames, "
             "each averaging 5, 9 or 17 of every 9 sub-frames; stand-in: first "
             f"{args.frames} frames of every test sequence, exposure its render's blur "
             "strength. Interval: 95 % t over the videos.")  # fmt: skip
    saved = save_benchmark_tables("video_motion_exposure",
                                  {"exposure": rows, "videos": video_rows}, args.out_dir,
                                  notes=notes)  # fmt: skip
    print(f"tables: {saved}")


if __name__ == "__main__":
    main()
