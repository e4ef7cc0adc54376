"""The video network on 640x480 frames (7-Scenes' size), restored at their own size and
downscaled to the 160x120 it was trained at.

    blurloc synth --out data/standin-640 --scenes chess heads office --frames 30 --width 640 \
        --height 480 --seed 2
    python benchmarks/video_deblur_scales.py --root data/standin-640 [--checkpoint F]
        [--widths 640 320 160] [--threads 2] [--out-dir figures]

The stand-in the network trains on is rendered at 160x120 with an exposure chosen so that its
blur is, relative to the frame, as strong as in heavily blurred 7-Scenes frames at 640x480; a
640x480 render of the same exposure carries four times the blur in pixels, with the same
sensor noise per pixel. Downscaling by area averages that noise down too (by 4 at 160x120).
For every test sequence of ``--root`` and every width of ``--widths`` (height three quarters of
it; frames and sharp renders resized by area), the mean PSNR of the blurred frames and of the
restored ones against the sharp renders, and the median blur (px at that width, from the
stand-in's blur records); then the mean gain per width over the sequences. Writes
``<out-dir>/video_deblur_scales.md``/``.csv`` (per width) and
``video_deblur_scales-per_sequence.csv``.
"""

from __future__ import annotations

import argparse

import numpy as np
import torch

from blurloc.data import list_scenes, load_split
from blurloc.data.stats import read_blur_metadata
from blurloc.experiments.photo_video import restoration_psnr
from blurloc.inference import DEFAULT_CHECKPOINT, load_video_deblur, restore_sequence
from blurloc.tables import add_out_dir_argument, save_benchmark_tables
from blurloc.train.datasets import resize_short_side


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="a stand-in rendered at 640x480")
    parser.add_argument("--checkpoint", default=str(DEFAULT_CHECKPOINT))
    parser.add_argument("--widths", nargs="+", type=int, default=[640, 320, 160])
    parser.add_argument("--threads", type=int, default=2)
    add_out_dir_argument(parser)
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    model = load_video_deblur(args.checkpoint)
    gains: dict[int, list[float]] = {width: [] for width in args.widths}
    sequence_rows = []
    blur_px: dict[tuple[str, int], list[float]] = {}  # recorded blur extent per test sequence
    for row in read_blur_metadata(args.root):
        if row["split"] == "test":
            blur_px.setdefault((row["scene"], row["sequence"]), []).append(row["mean_px"])
    for scene in list_scenes(args.root):
        for sequence in load_split(args.root, scene, "test"):
            blurred, sharp = sequence.images(), sequence.images("sharp")
            blur = np.median(blur_px[scene, sequence.number]) / blurred.shape[2]
            for width in args.widths:
                small_blurred, small_sharp = (
                    np.stack([resize_short_side(frame, 3 * width // 4) for frame in video])
                    for video in (blurred, sharp)
                )  # by area, as the pose network's input
                before, after = restoration_psnr(
                    lambda video: restore_sequence(model, video), small_blurred, small_sharp
                )
                gains[width].append(after - before)
                sequence_rows.append(
                    {
                        "scene": scene,
                        "sequence": sequence.number,
                        "width": width,
                        "median_blur_px": round(blur * width, 2),
                        "blurred_psnr_db": round(before, 3),
                        "restored_psnr_db": round(after, 3),
                        "gain_db": round(after - before, 3),
                    }
                )
                print(f"{scene} sequence {sequence.number}, {width}x{3 * width // 4}: median blur "
                      f"{blur * width:.1f} px, {before:.2f} -> {after:.2f} dB "
                      f"({after - before:+.2f})")  # fmt: skip
    width_rows = []
    for width, values in gains.items():
        width_rows.append(
            {
                "width": width,
                "height": 3 * width // 4,
                "sequences": len(values),
                "gain_mean_db": round(float(np.mean(values)), 3),
                "gain_min_db": round(min(values), 3),
                "gain_max_db": round(max(values), 3),
            }
        )
        print(
            f"{width}x{3 * width // 4}: gain mean {np.mean(values):+.2f} dB, min "
            f"{min(values):+.2f}, max {max(values):+.2f} over {len(values)} sequences"
        )
    saved = save_benchmark_tables(
        "video_deblur_scales",
        {"per width": width_rows, "per sequence": sequence_rows},
        args.out_dir,
        f"Video network on {args.root}'s test sequences at several widths",
    )
    print(f"wrote {saved.markdown}")


if __name__ == "__main__":
    main()
