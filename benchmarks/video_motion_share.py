"""How much of ``blurloc deblur-video``'s shortfall on the stand-in is the exposure share it
reads? The default method with the share read from each video beside the same method told the
camera's own share, on the stand-in's test sequences.

    python benchmarks/video_motion_share.py --standin data/standin
        [--clean-standin data/standin-clean-s8] [--frames 50 250] [--out-dir figures]

The default (:class:`~blurloc.inference.MotionNetworkRestorer`: each frame deconvolved by its
own motion with the exposure share read from the video,
:func:`~blurloc.blur.video_motion.calibrate_exposure_share`, DEFAULT_EXPOSURE_SHARE where the
reading does not tell the shares apart; then the method's network) and the same restorer told
the render's exposure in frame intervals (its ``blur_strength``, a camera setting) restore the
first ``--frames`` frames (each cut; a cut longer than every sequence of a root is left out; a
shorter sequence gives all its frames) of every test sequence of ``--standin`` (as rendered,
with the camera model's noise) and of ``--clean-standin`` (a render without noise, ``blurloc
synth --out data/standin-clean-s8 --frames 60 --seed 8 --shot-noise 0 --read-noise 0 --noise
0``). Per set and cut:
the videos whose share was read (and its median), the mean PSNR gain of each arm over the
blurred input (eq. 6, mean over frames), and told minus read paired by video with a 95 %
t-interval, over all videos, over those whose share was read and over those that fell back to
the default. Writes ``<out-dir>/video_motion_share.md``/``.csv`` (``-videos.csv``: one row per
video). About 15 min on 2 cores.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from blurloc.blur.video_motion import calibrate_exposure_share, frame_shifts
from blurloc.data import list_scenes, load_split
from blurloc.data.manifest import render_settings
from blurloc.experiments.photo_video import restoration_psnr
from blurloc.inference import MotionNetworkRestorer
from blurloc.intervals import paired_interval
from blurloc.tables import add_out_dir_argument, save_benchmark_tables


def interval_text(differences: list[float]) -> str:
    """Mean and 95 % t-interval of paired differences, or why there is none."""
    if len(differences) < 2:
        return f"{differences[0]:+.3f} (one video)" if differences else "no videos"
    interval = paired_interval(np.array(differences), method="t")
    return f"{interval.mean:+.3f} [{interval.low:+.3f}, {interval.high:+.3f}]"


def _frame_range(rows: list[dict]) -> str:
    """The frames per video of a set's rows: one count, or the least and the most."""
    counts = sorted({row["frames"] for row in rows})
    return str(counts[0]) if len(counts) == 1 else f"{counts[0]}-{counts[-1]}"


def main() -> None:
    """Restore every test sequence with the share read and told; write the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--standin", type=Path, required=True)
    parser.add_argument("--clean-standin", type=Path)
    parser.add_argument("--frames", type=int, nargs="+", default=[50, 250])
    add_out_dir_argument(parser)
    args = parser.parse_args()
    started = time.time()
    read = MotionNetworkRestorer()
    roots = [("stand-in as rendered (noisy)", args.standin)]
    if args.clean_standin is not None:
        roots.append(("stand-in without noise", args.clean_standin))
    summary, videos = [], []
    for name, root in roots:
        camera_share = float(render_settings(root)["blur_strength"])
        told = MotionNetworkRestorer(exposure_share=camera_share)
        sequences = [sequence for scene in list_scenes(root)
                     for sequence in load_split(root, scene, "test")]  # fmt: skip
        longest = max(len(sequence.frame_ids) for sequence in sequences)
        for frames in args.frames:
            if frames > longest and frames != args.frames[0]:
                continue  # the sequences are shorter: the same videos as a shorter cut
            rows = []
            for sequence in sequences:
                ids = sequence.frame_ids[:frames]
                blurred, sharp = sequence.images("color", ids), sequence.images("sharp", ids)
                share = calibrate_exposure_share(blurred, frame_shifts(blurred))
                before, after_read = restoration_psnr(read, blurred, sharp)
                _, after_told = restoration_psnr(told, blurred, sharp)
                rows.append({"set": name, "frames": len(ids),
                             "video": f"{sequence.folder.parent.name} {sequence.folder.name}",
                             "share_read": "" if share is None else share,
                             "gain_read_db": round(after_read - before, 3),
                             "gain_told_db": round(after_told - before, 3)})  # fmt: skip
                print(rows[-1], flush=True)
            videos += rows
            difference = {"all": [r["gain_told_db"] - r["gain_read_db"] for r in rows]}
            difference["share read"] = [r["gain_told_db"] - r["gain_read_db"]
                                        for r in rows if r["share_read"] != ""]  # fmt: skip
            difference["not read (default)"] = [r["gain_told_db"] - r["gain_read_db"]
                                                for r in rows if r["share_read"] == ""]  # fmt: skip
            shares = [r["share_read"] for r in rows if r["share_read"] != ""]
            summary.append({
                "set": name, "frames": _frame_range(rows), "videos": len(rows),
                "camera_share": camera_share, "shares_read": len(shares),
                "median_share_read": round(float(np.median(shares)), 2) if shares else "",
                "gain_read_db": round(float(np.mean([r["gain_read_db"] for r in rows])), 3),
                "gain_told_db": round(float(np.mean([r["gain_told_db"] for r in rows])), 3),
                **{f"told_minus_read, {part}": interval_text(values)
                   for part, values in difference.items()},
            })  # fmt: skip
            print(summary[-1], flush=True)
    notes = ("Default: the share read from each video (the package's default share where it is "
             "not told apart); told: the render's exposure in frame intervals. Gains: PSNR of "
             "the restored frames minus the blurred ones' against the sharp renders (eq. 6, mean "
             "over frames), dB, mean over videos; told minus read per video, 95 % t-interval. "
             f"{time.time() - started:.0f} s on 2 CPU cores.")  # fmt: skip
    saved = save_benchmark_tables("video_motion_share", {"summary": summary, "videos": videos},
                                  args.out_dir, notes=notes)  # fmt: skip
    print(f"tables: {saved}")


if __name__ == "__main__":
    main()
