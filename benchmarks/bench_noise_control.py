"""Denoising is not deblurring: the video network's gain on blurred frames beside its gain on a
noise-only control.

    python benchmarks/bench_noise_control.py [--root data/standin] [--frames 250]

The stand-in's sharp renders are noise-free, so part of any PSNR gain of a network fed the
blurred (and noisy) frames may be denoising. The control feeds it the sharp render plus the same
sensor noise (σ = 0.01 on gamma-encoded intensities, quantised to 8 bits, as the renderer does),
with no blur. Both are scored against the sharp render (eq. 6), on the first ``--frames`` frames
of every test sequence, with the shipped checkpoint. Prints both gains side by side.
"""

from __future__ import annotations

import argparse

import numpy as np
import torch

from blurloc.data import list_scenes, load_split, read_image
from blurloc.data.synth import SynthConfig
from blurloc.images import srgb_to_linear, to_uint8
from blurloc.inference import DEFAULT_CHECKPOINT, load_video_deblur, restore_sequence
from blurloc.metrics import mean_frame_psnr


def main() -> None:
    """Measure and print the two gains."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default="data/standin", help="stand-in root (full render)")
    parser.add_argument("--frames", type=int, default=250, help="frames per test sequence")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    torch.set_num_threads(2)
    network = load_video_deblur(DEFAULT_CHECKPOINT)
    rng = np.random.default_rng(args.seed)
    sigma = SynthConfig().noise_sigma
    pairs: dict[str, list] = {"blurred": [], "blurred, restored": [], "noisy sharp": [],
                              "noisy sharp, restored": []}  # fmt: skip
    for scene in list_scenes(args.root):
        for sequence in load_split(args.root, scene, "test"):
            part = sequence.first(args.frames)
            blurred = np.stack([read_image(part.path(f)) for f in part.frame_ids])
            sharp = np.stack([read_image(part.path(f, "sharp")) for f in part.frame_ids])
            linear = srgb_to_linear(sharp.astype(np.float64) / 255.0)
            noisy = to_uint8(linear, rng.normal(0.0, sigma, linear.shape))
            for name, video in (("blurred", blurred), ("noisy sharp", noisy)):
                pairs[name].append((video, sharp))
                pairs[f"{name}, restored"].append((restore_sequence(network, video), sharp))
    psnr = {name: mean_frame_psnr(videos) for name, videos in pairs.items()}
    frames = sum(len(video) for video, _ in pairs["blurred"])
    print(f"shipped network, {frames} test frames, PSNR (dB) against the sharp renders:")
    for name, value in psnr.items():
        print(f"  {name:<24} {value:6.2f}")
    print(f"  gain on blurred frames     {psnr['blurred, restored'] - psnr['blurred']:+.2f} dB")
    print(f"  gain on noise only         {psnr['noisy sharp, restored'] - psnr['noisy sharp']:+.2f}"
          " dB")


if __name__ == "__main__":
    main()
