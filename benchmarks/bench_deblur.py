"""Deblurring speed and quality on 640x480 RGB frames.

    python benchmarks/bench_deblur.py [--images 6] [--repeats 5]

Prints (1) the time of blind deblurring (detect -> estimate -> Wiener, ``deblur_blind``) of a
640x480 RGB frame, its parts, and scikit-image's ``wiener`` on the same frame and kernel for
scale (target for blind deblurring: <= 30 ms on 2 cores; medians over the repeats, with the
machine's load average printed beside them), and (2) non-blind PSNR/SSIM of this
package's Wiener filter (NSR estimated from the noise, not tuned per image) against
scikit-image's ``wiener`` at its best ``balance`` (swept per image) and ``unsupervised_wiener``,
same images, same linear motion kernels, noise σ = 0.01 (target: >= +1 dB over ``wiener``).
Images: scikit-image's bundled photographs, resized to 640x480.
"""

from __future__ import annotations

import argparse
import os
import time
from collections.abc import Callable

import cv2
import numpy as np
import skimage.data
from skimage.restoration import unsupervised_wiener, wiener

from blurloc.blur import blur_image, detect_blur, estimate_motion_blur, motion_kernel
from blurloc.deconv import deblur_blind, wiener_deconvolve
from blurloc.metrics import psnr, ssim

PHOTOS = ("astronaut", "coffee", "chelsea", "rocket", "immunohistochemistry", "hubble_deep_field")
BALANCES = (1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0)


def frame(name: str) -> np.ndarray:
    """A bundled photograph as a 640x480 RGB float image in [0, 1]."""
    image = getattr(skimage.data, name)().astype(np.float64) / 255.0
    return cv2.resize(image, (640, 480), interpolation=cv2.INTER_AREA)


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
    parser.add_argument("--repeats", type=int, default=15)
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
    print(f"per 640x480 RGB frame (L = 15 px at 30°, estimated {estimate.length_px:.1f} px at "
          f"{estimate.angle_deg:.1f}°), median of {args.repeats}; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores:")
    for label, call in timings.items():
        print(f"  {label:30s} {median_ms(call, args.repeats):6.1f} ms")
    print("  (target for blind deblurring: <= 30 ms on 2 cores)")

    rows = []
    for name in PHOTOS[: args.images]:
        sharp = frame(name).mean(axis=2)
        kernel = motion_kernel(rng.uniform(7, 27), rng.uniform(0, 180))
        blurred = blur_image(sharp, kernel, 0.01, rng=rng)
        ours = np.clip(wiener_deconvolve(blurred, kernel), 0, 1)
        swept = [np.clip(wiener(blurred, kernel, b, clip=False), 0, 1) for b in BALANCES]
        best = max(swept, key=lambda image: psnr(sharp, image, 1.0))
        unsupervised = np.clip(
            unsupervised_wiener(blurred, kernel, clip=False, rng=np.random.default_rng(0))[0], 0, 1
        )
        rows.append(
            [
                f(sharp, image, 1.0)
                for image in (np.clip(blurred, 0, 1), ours, best, unsupervised)
                for f in (psnr, ssim)
            ]
        )
    mean = np.mean(rows, axis=0)
    print(f"non-blind, σ = 0.01, {len(rows)} images (gray 640x480), PSNR dB / SSIM:")
    for index, label in enumerate(
        (
            "blurred input",
            "blurloc Wiener (estimated NSR)",
            "skimage wiener (best balance)",
            "skimage unsupervised_wiener",
        )
    ):
        print(f"  {label:32s} {mean[2 * index]:6.2f} / {mean[2 * index + 1]:.3f}")
    print(f"  gain over skimage wiener: {mean[2] - mean[4]:+.2f} dB (target >= +1 dB)")


if __name__ == "__main__":
    main()
