"""Deblurring speed and quality on 640x480 frames.

    python benchmarks/bench_deblur.py [--images 6] [--kernels 5] [--repeats 15]
                                      [--quality-size 640 480] [--out-dir figures]

Measures, prints and writes to ``<out-dir>/bench_deblur.md``/``.csv`` (timings) and
``bench_deblur-quality.csv`` (quality): (1) the time of blind deblurring (detect -> estimate ->
Wiener, ``deblur_blind``) of a 640x480 RGB frame, its parts, and scikit-image's ``wiener`` on the
same frame and kernel for scale (target for blind deblurring: <= 30 ms on 2 cores; medians over the
repeats, with the machine's load average printed beside them), and (2) non-blind PSNR of this
package's Wiener filter (NSR estimated from the noise, not tuned per image) against scikit-image's
``wiener`` at its best ``balance`` (swept per trial) and ``unsupervised_wiener``: gray photographs
(scikit-image's bundled ones, resized to 640x480, or to ``--quality-size``: 255 255 is the size of
Levin et al.'s test images), each blurred by ``--kernels`` random line kernels and as many random
camera-shake kernels (:func:`blurloc.blur.shake_path`, shaped like Levin et al.'s recorded ones),
noise σ = 0.01; per kind, the mean gain over scikit-image with a 95 % bootstrap interval over the
trials (target: >= +1 dB), and over scikit-image given the same mirror padding
(:func:`blurloc.experiments.wiener_oracles.skimage_comparison`: then only the regulariser differs).
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable

import cv2
import numpy as np
import skimage.data
from skimage.restoration import wiener

from blurloc.blur import blur_image, detect_blur, estimate_motion_blur, motion_kernel
from blurloc.deconv import deblur_blind, wiener_deconvolve
from blurloc.experiments.wiener_oracles import KERNEL_KINDS, skimage_comparison
from blurloc.intervals import paired_interval
from blurloc.tables import add_out_dir_argument, save_benchmark_tables

PHOTOS = ("astronaut", "coffee", "chelsea", "rocket", "immunohistochemistry", "hubble_deep_field")


def frame(name: str, size: tuple[int, int] = (640, 480)) -> np.ndarray:
    """A bundled photograph as an RGB float image in [0, 1] of ``size`` (width, height)."""
    image = getattr(skimage.data, name)().astype(np.float64) / 255.0
    return cv2.resize(image, size, interpolation=cv2.INTER_AREA)


def median_ms(call: Callable[[], object], repeats: int) -> float:
    """Median wall time of ``call`` in ms over ``repeats`` runs, after one warm-up run."""
    call()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return float(np.median(times) * 1000)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--images", type=int, default=len(PHOTOS))
    parser.add_argument("--kernels", type=int, default=5, help="kernels of each kind per photo")
    parser.add_argument(
        "--quality-size",
        type=int,
        nargs=2,
        default=(640, 480),
        metavar=("WIDTH", "HEIGHT"),
        help="size of the photos in the quality part (255 255: Levin et al.'s)",
    )
    parser.add_argument("--repeats", type=int, default=15)
    add_out_dir_argument(parser)
    args = parser.parse_args()
    rng = np.random.default_rng(0)

    sample = blur_image(frame("astronaut"), motion_kernel(15, 30), 0.01, rng=rng)
    sample8 = np.round(np.clip(sample, 0, 1) * 255).astype(np.uint8)
    estimate = estimate_motion_blur(sample8)
    kernel = estimate.kernel()
    timings = {
        "detect (blur_score)": lambda: detect_blur(sample8),
        "estimate (length, angle)": lambda: estimate_motion_blur(sample8),
        "Wiener (eq. 4, 3 channels)": lambda: wiener_deconvolve(sample8, kernel),
        "blind deblurring, all three": lambda: deblur_blind(sample8),
        "skimage wiener (3 channels)": lambda: [
            wiener(sample8[..., c] / 255.0, kernel, 0.01) for c in range(3)
        ],
    }
    print(
        f"per 640x480 RGB frame (L = 15 px at 30°, estimated {estimate.length_px:.1f} px at "
        f"{estimate.angle_deg:.1f}°), median of {args.repeats}; load average "
        f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores:"
    )
    load = os.getloadavg()[0]
    timing_rows = []
    for label, call in timings.items():
        milliseconds = median_ms(call, args.repeats)
        print(f"  {label:30s} {milliseconds:6.1f} ms")
        timing_rows.append(
            {
                "step": label,
                "median_ms": round(milliseconds, 2),
                "repeats": args.repeats,
                "load_average": round(load, 2),
                "cores": os.cpu_count(),
            }
        )
    print("  (target for blind deblurring: <= 30 ms on 2 cores)")

    size = tuple(args.quality_size)
    print(
        f"non-blind, σ = 0.01, gray {size[0]}x{size[1]}, {args.images} photos x "
        f"{args.kernels} kernels of each kind; PSNR dB (mean) and blurloc minus "
        "scikit-image's best balance (mean, 95 % bootstrap interval over the trials):"
    )
    photos = [frame(name, size).mean(axis=2) for name in PHOTOS[: args.images]]
    quality_rows = []
    for kind, ((low, high), label) in KERNEL_KINDS.items():
        rows = skimage_comparison(photos, [kind], args.kernels, rng, unsupervised=True)
        mean = {key: np.mean([r[key] for r in rows]) for key in rows[0] if key.endswith("_db")}
        gain, padded = (paired_interval(np.array([r["ours_db"] - r[key] for r in rows]))
                        for key in ("skimage_best_balance_db", "skimage_padded_db"))  # fmt: skip
        ahead = np.mean([r["ours_db"] > r["skimage_best_balance_db"] for r in rows])
        print(
            f"  {label}, {low:.0f}-{high:.0f} px: blurred {mean['blurred_db']:.2f}, blurloc "
            f"{mean['ours_db']:.2f}, skimage best balance {mean['skimage_best_balance_db']:.2f} "
            f"(mirror-padded like blurloc: {mean['skimage_padded_db']:.2f}), unsupervised "
            f"{mean['unsupervised_db']:.2f}; gain {gain.mean:+.2f} dB [{gain.low:+.2f}, "
            f"{gain.high:+.2f}], {ahead:.0%} of trials ahead (target: >= +1 dB); over the "
            f"mirror-padded skimage {padded.mean:+.2f} dB [{padded.low:+.2f}, "
            f"{padded.high:+.2f}]"
        )
        quality_rows.append(
            {
                "kernels": label,
                "length_px": f"{low:.0f}-{high:.0f}",
                "trials": len(rows),
                **{key: round(float(value), 3) for key, value in mean.items()},
                "gain_db": round(gain.mean, 3),
                "gain_low": round(gain.low, 3),
                "gain_high": round(gain.high, 3),
                "share_ahead": round(float(ahead), 3),
                "gain_over_padded_db": round(padded.mean, 3),
                "padded_low": round(padded.low, 3),
                "padded_high": round(padded.high, 3),
            }
        )
    saved = save_benchmark_tables(
        "bench_deblur",
        {"timings": timing_rows, "quality": quality_rows},
        args.out_dir,
        "Deblurring speed (640x480 RGB) and non-blind quality against scikit-image",
        notes=f"Timings: median of {args.repeats} runs after one warm-up, ms per frame. Quality: "
        f"gray {size[0]}x{size[1]} photos, noise sigma 0.01, PSNR dB means; gains are blurloc "
        "minus scikit-image's best balance (and minus scikit-image mirror-padded), mean and "
        "95 % bootstrap interval over the trials.",
    )
    print(f"wrote {saved.markdown}")


if __name__ == "__main__":
    main()
