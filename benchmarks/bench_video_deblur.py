"""CPU throughput of the recurrent video deblurring network at 160x120 (target >= 25 frames/s),
and its PSNR gain on camera blur made from real photographs.

    python benchmarks/bench_video_deblur.py [--frames 200] [--threads 2] [--checkpoint F]
        [--noise 0.01 0.005 0.0025 0] [--out-dir figures]

Runs the shipped checkpoint (or the one given) over a synthetic 160x120 video in chunks of 32
frames, as ``blurloc deblur-video`` does, and prints frames per second for the full network and
for the single-frame baseline of the same size. Then deblurs GoPro-style videos made from five
scikit-image photographs at three pan speeds
(:func:`blurloc.experiments.photo_video.photo_video`) and prints the PSNR of the input and of
the output against the sharp middle sub-frames, with the stand-in's sensor noise (sigma 0.01)
and then, summed up, with less (``--noise``): real footage averaged the GoPro way carries
little noise, and a network trained on noisy frames gains partly by denoising. Writes
``<out-dir>/bench_video_deblur.md``/``.csv`` (throughput), ``bench_video_deblur-photo_videos.csv``
(every photo video at the first noise level) and ``bench_video_deblur-by_noise.csv``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import torch

from blurloc.experiments.photo_video import PHOTO_VIDEO_SPEEDS, photo_video_gains
from blurloc.inference import DEFAULT_CHECKPOINT, load_video_deblur, restore_sequence
from blurloc.models.video_deblur import VideoDeblurConfig, VideoDeblurNet, parameter_count
from blurloc.tables import add_out_dir_argument, save_benchmark_tables


def frames_per_second(model: torch.nn.Module, video: np.ndarray) -> float:
    """Frames per second of :func:`restore_sequence` over ``video`` (after one warm-up run)."""
    restore_sequence(model, video[:8])
    start = time.perf_counter()
    restore_sequence(model, video)
    return len(video) / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=200)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--checkpoint", default=str(DEFAULT_CHECKPOINT))
    parser.add_argument(
        "--noise", nargs="+", type=float, default=[0.01, 0.005, 0.0025, 0.0],
        help="sensor noise sigmas of the photo videos (the first in detail)",
    )  # fmt: skip
    add_out_dir_argument(parser)
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    video = (np.random.default_rng(0).random((args.frames, 120, 160, 3)) * 255).astype(np.uint8)
    full = load_video_deblur(args.checkpoint)
    single = VideoDeblurNet(VideoDeblurConfig(aux_state=False, blending=False, recurrent=False))
    speed_rows, photo_rows, noise_rows = [], [], []
    for name, model in (("full network (checkpoint)", full), ("single-frame baseline", single)):
        fps = frames_per_second(model, video)
        speed_rows.append(
            {
                "network": name,
                "parameters": parameter_count(model),
                "frames_per_s": round(fps, 2),
                "threads": args.threads,
                "frames": args.frames,
            }
        )
        print(
            f"{name}: {parameter_count(model):,} parameters, {fps:.1f} frames/s at 160x120 "
            f"on {args.threads} threads (target >= 25)"
        )
    for noise in args.noise:
        rows = photo_video_gains(lambda blurred: restore_sequence(full, blurred), noise_sigma=noise)
        for row in rows if noise == args.noise[0] else []:
            photo_rows.append({"noise_sigma": noise, **row})
            print(
                f"photo video {row['photo']}, {row['step_px']} px per sub-frame: "
                f"{row['blurred_psnr_db']:.2f} dB -> {row['restored_psnr_db']:.2f} dB "
                f"({row['gain_db']:+.2f})"
            )
        gains = [row["gain_db"] for row in rows]
        by_speed = ", ".join(
            f"{np.mean([r['gain_db'] for r in rows if r['step_px'] == step]):+.2f}"
            for step in PHOTO_VIDEO_SPEEDS
        )
        print(
            f"photo videos, noise sigma {noise}: gain min {min(gains):+.2f} dB, mean "
            f"{np.mean(gains):+.2f} dB (must not be worse than the input); by pan speed "
            f"{PHOTO_VIDEO_SPEEDS} px per sub-frame: {by_speed}"
        )
        noise_rows.append(
            {
                "noise_sigma": noise,
                "videos": len(rows),
                "gain_min_db": round(min(gains), 3),
                "gain_mean_db": round(float(np.mean(gains)), 3),
                **{
                    f"gain_step_{step}px_db": round(
                        float(np.mean([r["gain_db"] for r in rows if r["step_px"] == step])), 3
                    )
                    for step in PHOTO_VIDEO_SPEEDS
                },
            }
        )
    saved = save_benchmark_tables(
        "bench_video_deblur",
        {"throughput": speed_rows, "photo videos": photo_rows, "by noise": noise_rows},
        args.out_dir,
        "Video deblurring network: CPU throughput at 160x120 and PSNR gain on photo videos",
    )
    print(f"wrote {saved.markdown}")


if __name__ == "__main__":
    main()
