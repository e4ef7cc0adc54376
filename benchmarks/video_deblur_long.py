"""``blurloc deblur-video``'s methods over long videos: is the gain the same at the end of a
600-frame video as at its start?

    blurloc synth --out data/standin-long-clean --scenes chess fire heads --frames 600
        --seed 9 --shot-noise 0 --read-noise 0 --noise 0
    python benchmarks/video_deblur_long.py --standin data/standin
        --clean-standin data/standin-long-clean [--frames 600] [--out-dir figures]

Methods: ``motion-network`` (the command's default, :class:`~blurloc.inference.
MotionNetworkRestorer`: each frame deconvolved by its own motion in the video, the exposure share
read from the video, then the recurrent network trained on deconvolved frames), ``network`` (the
paper's network alone, trained on blurred frames,
:class:`~blurloc.inference.VideoRestorer`) and ``motion`` (the deconvolution alone,
:func:`~blurloc.video_wiener.deblur_video_motion` with the share read). Videos: the first
``--frames`` frames of the first test sequence of every scene of ``--standin`` (as rendered,
with the camera model's noise) and of ``--clean-standin`` (a render without any noise), all of
a shorter sequence (stairs has half as many frames), scored against the sharp renders; and the first
``--frames`` frames of the real recording (TUM RGB-D ``fr1_rpy`` at 160x120, its sequences in
order as one video: real camera blur and noise, no sharp truth), where the mean absolute change
each method makes to the frames (0-255) is reported instead. Per video and method: PSNR gain
(restored minus blurred, eq. 6, mean over frames; a frame identical to its sharp render, from
a still camera without noise, has nothing to restore and is not scored) over the first 100 and
the last 100 frames, their difference (the stability target: within 0.3 dB) and the gain over
the whole video (frames per second: ``benchmarks/bench_video_motion_speed.py``); per set and
method the mean gain, the mean and the largest drift (last minus first) and the videos that are
stable. Writes
``<out-dir>/video_deblur_long.md``/``.csv`` (``-videos.csv``: every video).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from blurloc.data import list_scenes, load_split
from blurloc.data.frames import list_frames, read_frames
from blurloc.data.real import recording_root
from blurloc.inference import DEFAULT_CHECKPOINT, MotionNetworkRestorer, VideoRestorer
from blurloc.metrics import psnr
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.video_wiener import deblur_video_motion

#: Frames at each end of a video whose gains are compared (the stability target's 100).
END_FRAMES = 100
#: Largest difference between the last and the first END_FRAMES frames' gains (dB) that counts
#: as stable (the deblurring targets' 0.3 dB).
STABLE_DB = 0.3


def methods() -> dict:
    """The command's three methods, by the name ``--method`` gives them."""
    return {"motion-network": MotionNetworkRestorer(),
            "network": VideoRestorer(DEFAULT_CHECKPOINT),
            "motion": lambda video: deblur_video_motion(video, None)}  # fmt: skip


def standin_videos(root: Path, frames: int) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(label, blurred, sharp) for the first ``frames`` frames of the first test sequence of
    every scene under ``root`` (all of a shorter one: the stand-in's stairs has half as many)."""
    videos = []
    for scene in list_scenes(root):
        sequence = load_split(root, scene, "test")[0]
        ids = sequence.frame_ids[:frames]
        videos.append((f"{scene} {sequence.folder.name}", sequence.images("color", ids),
                       sequence.images("sharp", ids)))  # fmt: skip
    return videos


def frame_psnrs(video: np.ndarray, sharp: np.ndarray) -> np.ndarray:
    """PSNR (dB, eq. 6) of every frame of ``video`` against ``sharp`` (inf where identical)."""
    return np.array([psnr(truth, frame, 255.0) for frame, truth in zip(video, sharp, strict=True)])


def main() -> None:
    """Restore every long video with every method; write the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--standin", type=Path, required=True)
    parser.add_argument("--clean-standin", type=Path, required=True)
    parser.add_argument("--frames", type=int, default=600)
    add_out_dir_argument(parser)
    args = parser.parse_args()
    if args.frames < 2 * END_FRAMES:
        parser.error(f"--frames must be >= {2 * END_FRAMES}")
    restorers = methods()
    rows = []
    for set_name, root in (("stand-in as rendered (noisy)", args.standin),
                           ("stand-in without noise", args.clean_standin)):  # fmt: skip
        for label, blurred, sharp in standin_videos(root, args.frames):
            before = frame_psnrs(blurred, sharp)
            scored = np.isfinite(before)  # a still camera without noise: nothing to restore
            for name, restore in restorers.items():
                restored = restore(blurred)
                gains = np.where(scored, frame_psnrs(restored, sharp) - before, np.nan)
                first = np.nanmean(gains[:END_FRAMES])
                last = np.nanmean(gains[-END_FRAMES:])
                rows.append({"set": set_name, "video": label, "method": name,
                             "frames": len(blurred), "frames_scored": int(scored.sum()),
                             "gain_db": round(float(np.nanmean(gains)), 3),
                             "gain_first_100_db": round(float(first), 3),
                             "gain_last_100_db": round(float(last), 3),
                             "last_minus_first_db": round(float(last - first), 3),
                             "stable": bool(abs(last - first) <= STABLE_DB),
                             "change_first_100": "", "change_last_100": ""})  # fmt: skip
                print(rows[-1], flush=True)
    recording = [path for folder in sorted(recording_root().glob("*/seq-*"))
                 for path in list_frames(folder)][: args.frames]  # fmt: skip
    frames = np.stack(list(read_frames(recording)))
    for name, restore in restorers.items():
        restored = restore(frames)
        change = np.abs(restored.astype(float) - frames).mean(axis=(1, 2, 3))
        rows.append({"set": "real recording fr1_rpy (no truth)", "video": "seq-01 onwards",
                     "method": name, "frames": len(frames), "frames_scored": "", "gain_db": "",
                     "gain_first_100_db": "", "gain_last_100_db": "", "last_minus_first_db": "",
                     "stable": "", "change_first_100": round(float(change[:END_FRAMES].mean()), 3),
                     "change_last_100": round(float(change[-END_FRAMES:].mean()), 3)})  # fmt: skip
        print(rows[-1], flush=True)
    notes = (f"First {args.frames} frames of every video; gains: restored minus blurred PSNR "
             f"(eq. 6), dB, mean over frames; stable: the last {END_FRAMES} frames' gain within "
             f"{STABLE_DB} dB of the first {END_FRAMES}'s; change: mean absolute change of the "
             "real frames (0-255), which have no sharp truth.")  # fmt: skip
    summary = []
    for set_name in dict.fromkeys(row["set"] for row in rows if row["gain_db"] != ""):
        for name in restorers:
            chosen = [row for row in rows if row["set"] == set_name and row["method"] == name]
            drift = [row["last_minus_first_db"] for row in chosen]
            gains = [row["gain_db"] for row in chosen]
            summary.append({"set": set_name, "method": name, "videos": len(chosen),
                            "mean_gain_db": round(float(np.mean(gains)), 3),
                            "mean_last_minus_first_db": round(float(np.mean(drift)), 3),
                            "largest_drift_db": max(drift, key=abs),
                            "videos_stable": sum(row["stable"] for row in chosen)})  # fmt: skip
    saved = save_benchmark_tables("video_deblur_long", {"summary": summary, "videos": rows},
                                  args.out_dir, notes=notes)  # fmt: skip
    print(f"tables: {saved}")


if __name__ == "__main__":
    main()
