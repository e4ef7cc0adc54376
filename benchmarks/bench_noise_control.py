"""Denoising is not deblurring: the video network's gain on blurred frames beside its gain on a
noise-only control, and the gain on blurred frames by how much blur they carry.

    python benchmarks/bench_noise_control.py [--root data/standin] [--frames 250]
        [--checkpoint PATH] [--out-dir figures]

The stand-in's sharp renders are noise-free, so part of any PSNR gain of a network fed the
blurred (and noisy) frames may be denoising. The control feeds it the sharp render plus the same
sensor noise (σ = 0.01 on gamma-encoded intensities, quantised to 8 bits, as the renderer does),
with no blur. Both are scored against the sharp render (eq. 6), on the first ``--frames`` frames
of every test sequence, with the shipped checkpoint (or ``--checkpoint``). Prints both gains side
by side, then the blurred frames' gain per bin of recorded blur extent (``blur.csv``'s mean_px):
where in the blur distribution the gain is made, and how much of the test split lies where little
can be gained. Last, where in the spectrum: the squared error split into radial frequency bands
(``metrics.band_squared_error``), for the blurred input, the control's noisy input (the noise
alone, so the rest of the blurred input's error in a band is the blur's) and what the network
removes of each band in both. Writes ``<out-dir>/bench_noise_control.md``/``.csv`` (the two
gains) with ``bench_noise_control-by_extent.csv`` and ``bench_noise_control-by_band.csv``.
"""

from __future__ import annotations

import argparse
import itertools

import numpy as np
import torch

from blurloc.data import list_scenes, load_split
from blurloc.data.stats import read_blur_metadata
from blurloc.data.synth import SynthConfig
from blurloc.images import srgb_to_linear, to_uint8
from blurloc.inference import DEFAULT_CHECKPOINT, load_video_deblur, restore_sequence
from blurloc.intervals import paired_interval
from blurloc.metrics import FREQUENCY_BAND_EDGES, band_squared_error, psnr
from blurloc.tables import add_out_dir_argument, save_benchmark_tables

EXTENT_BINS_PX = (0.0, 1.0, 2.0, 4.0, 8.0, np.inf)


def mse_removed(psnr_pairs: np.ndarray) -> np.ndarray:
    """Squared error (8-bit units^2) removed per frame, from (before, after) PSNR pairs (dB)."""
    mse = 255.0**2 * 10.0 ** (-psnr_pairs / 10.0)
    return mse[:, 0] - mse[:, 1]


def main() -> None:
    """Measure, print and write the two gains, the gain by blur extent and by band."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default="data/standin", help="stand-in root (full render)")
    parser.add_argument("--frames", type=int, default=250, help="frames per test sequence")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--checkpoint", default=DEFAULT_CHECKPOINT, help="video network")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    torch.set_num_threads(2)
    network = load_video_deblur(args.checkpoint)
    rng = np.random.default_rng(args.seed)
    sigma = SynthConfig().noise_sigma
    extents = {(r["scene"], r["sequence"], r["frame"]): r["mean_px"]
               for r in read_blur_metadata(args.root) if r["split"] == "test"}  # fmt: skip
    blurred_frames = []  # per frame: (extent px, input PSNR, restored PSNR) against the render
    control_frames = []  # per frame: (input PSNR, restored PSNR) of the noise-only control
    bands = np.zeros((4, len(FREQUENCY_BAND_EDGES) - 1))  # (blurred, control) x (input, output)
    for scene in list_scenes(args.root):
        for sequence in load_split(args.root, scene, "test"):
            part = sequence.first(args.frames)
            blurred = part.images()
            sharp = part.images("sharp")
            linear = srgb_to_linear(sharp.astype(np.float64) / 255.0)
            noisy = to_uint8(linear, rng.normal(0.0, sigma, linear.shape))
            scores = {}
            for name, video in (("blurred", blurred), ("control", noisy)):
                restored = restore_sequence(network, video)
                row = 0 if name == "blurred" else 2
                bands[row] += band_squared_error(sharp, video)
                bands[row + 1] += band_squared_error(sharp, restored)
                scores[name] = [(psnr(truth, before, 255.0), psnr(truth, after, 255.0))
                                for before, after, truth in zip(video, restored, sharp,
                                                                strict=True)]  # fmt: skip
            blurred_frames += [(extents[scene, sequence.number, frame], *pair) for frame, pair
                               in zip(part.frame_ids, scores["blurred"], strict=True)]  # fmt: skip
            control_frames += scores["control"]
    table, control = np.array(blurred_frames), np.array(control_frames)
    print(f"shipped network, {len(table)} test frames, mean PSNR (dB) against the sharp renders:")
    for name, values in (
        ("blurred", table[:, 1]),
        ("blurred, restored", table[:, 2]),
        ("noisy sharp", control[:, 0]),
        ("noisy sharp, restored", control[:, 1]),
    ):
        print(f"  {name:<24} {values.mean():6.2f}")
    gains = [
        {
            "input": name,
            "frames": len(pairs),
            "input_psnr_db": round(pairs[:, 0].mean(), 3),
            "restored_psnr_db": round(pairs[:, 1].mean(), 3),
            "gain_db": round((pairs[:, 1] - pairs[:, 0]).mean(), 3),
            "mse_removed": round(mse_removed(pairs).mean(), 3),
        }
        for name, pairs in (("blurred", table[:, 1:]), ("noisy sharp (control)", control))
    ]
    extent_rows = []
    print(f"  gain on blurred frames     {(table[:, 2] - table[:, 1]).mean():+.2f} dB")
    print(f"  gain on noise only         {(control[:, 1] - control[:, 0]).mean():+.2f} dB")
    removed = mse_removed(control)
    print(
        "\nblurred frames by recorded blur extent (mean px over the exposure, blur.csv): share "
        "of the frames, mean PSNR (dB) blurred -> restored, mean gain with a 95 % bootstrap "
        "interval over the frames (frames of one sequence are not independent: a lower bound "
        "on the width), and the squared error removed (8-bit units^2, mean over the frames)"
    )
    for low, high in itertools.pairwise(EXTENT_BINS_PX):
        inside = table[(table[:, 0] >= low) & (table[:, 0] < high)]
        if len(inside) < 2:
            print(f"  {low:4.0f}-{high:<4.0f} px  {len(inside)} frames: left out")
            continue
        gain = paired_interval(inside[:, 2] - inside[:, 1])
        extent_rows.append(
            {
                "extent_px": f"{low:.0f}-{high:.0f}",
                "frames": len(inside),
                "share": round(len(inside) / len(table), 4),
                "blurred_psnr_db": round(inside[:, 1].mean(), 3),
                "restored_psnr_db": round(inside[:, 2].mean(), 3),
                "gain_db": round(gain.mean, 3),
                "gain_low": round(gain.low, 3),
                "gain_high": round(gain.high, 3),
                "mse_removed": round(mse_removed(inside[:, 1:]).mean(), 3),
            }
        )
        print(
            f"  {low:4.0f}-{high:<4.0f} px  {len(inside) / len(table):6.1%}  "
            f"{inside[:, 1].mean():6.2f} -> {inside[:, 2].mean():6.2f}  "
            f"{gain.mean:+.2f} dB [{gain.low:+.2f}, {gain.high:+.2f}]  "
            f"MSE removed {mse_removed(inside[:, 1:]).mean():6.2f}"
        )
    print(
        f"  noise-only control: MSE removed {removed.mean():6.2f} (what denoising alone "
        "removes; a blur bin removing more is also deblurring)"
    )
    saved = save_benchmark_tables(
        "bench_noise_control",
        {"gains": gains, "by extent": extent_rows, "by band": print_bands(bands)},
        args.out_dir,
        f"Video network: gain on blurred frames and on a noise-only control ({args.root}, "
        f"first {args.frames} frames of every test sequence)",
        notes="PSNR against the sharp renders; gain intervals: 95 % bootstrap over the frames "
        "(frames of one sequence are not independent: a lower bound on the width); "
        "mse_removed in 8-bit units^2, mean over the frames; bands: shares of the squared error.",
    )
    print(f"wrote {saved.markdown}")


def print_bands(bands: np.ndarray) -> list[dict]:
    """Print and return the squared error by frequency band: (4, K) sums of the blurred input,
    its restoration, the control's input and its restoration (rows of ``bands``)."""
    blurred_in, blurred_out, control_in, control_out = bands
    print(
        "\nsquared error by spatial frequency (cycles per pixel; all frames and channels, "
        "Parseval): the blurred input's share per band, the part of it that the noise alone "
        "makes (the control's input error over the blurred input's), and the share of each "
        "band's error the network removes, on blurred frames and on the noise-only control"
    )
    print("  band            share   noise part   removed (blurred)   removed (noise only)")
    rows = []
    for k, (low, high) in enumerate(itertools.pairwise(FREQUENCY_BAND_EDGES)):
        label = f"{low:.3f}-{high:.3f}" if np.isfinite(high) else f">= {low:.3f}"
        rows.append(
            {
                "band_cycles_per_px": label,
                "share": round(blurred_in[k] / blurred_in.sum(), 4),
                "noise_part": round(control_in[k] / blurred_in[k], 4),
                "removed_blurred": round(1 - blurred_out[k] / blurred_in[k], 4),
                "removed_noise_only": round(1 - control_out[k] / control_in[k], 4),
            }
        )
        print(
            f"  {label:<14} {blurred_in[k] / blurred_in.sum():6.1%}   "
            f"{control_in[k] / blurred_in[k]:9.1%}   {1 - blurred_out[k] / blurred_in[k]:16.1%}"
            f"   {1 - control_out[k] / control_in[k]:19.1%}"
        )
    for name, before, after in (
        ("blurred", blurred_in, blurred_out),
        ("noise only", control_in, control_out),
    ):
        print(
            f"  all bands, {name}: {10 * np.log10(before.sum() / after.sum()):+.2f} dB (MSE of "
            "all frames together)"
        )
    return rows


if __name__ == "__main__":
    main()
