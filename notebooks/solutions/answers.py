"""Reference answers to the "Try it" exercises of the notebooks.

Each function runs one exercise in seconds (on scikit-image's camera photograph or a tiny
stand-in) and returns
what the exercise's check tests; tests/test_exercises.py runs them and asserts the checks.
"""

from __future__ import annotations

import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import skimage.data
from skimage.transform import rescale

from blurloc.blur import (
    BLUR_THRESHOLD,
    blur_image,
    detect_blur,
    estimate_motion_blur,
    log_power_spectrum,
    motion_kernel,
    to_gray,
)
from blurloc.data.synth import SynthConfig, render_exposure, sequence_trajectory, synthesize
from blurloc.deconv import wiener_deconvolve
from blurloc.experiments.pose import baseline_beside_real
from blurloc.geometry import intrinsics
from blurloc.images import linear_to_srgb, srgb_to_linear
from blurloc.metrics import psnr


def camera() -> np.ndarray:
    """The camera photograph, grey, float in [0, 1]."""
    return to_gray(skimage.data.camera()).astype(np.float64)


def nb01_length_and_angle(lengths=(8.0, 20.0), angle_deg: float = 30.0, seed: int = 0) -> dict:
    """01, item 1: the estimated length and angle of line blur of each length."""
    rng = np.random.default_rng(seed)
    found = {}
    for length in lengths:
        estimate = estimate_motion_blur(
            blur_image(camera(), motion_kernel(length, angle_deg), 0.005, rng=rng)
        )
        found[length] = (estimate.length_px, estimate.angle_deg)
    return found


def nb01_noise_floor(sigmas=(0.005, 0.02), seed: int = 0) -> dict:
    """01, item 2: the darkest log power (the sinc zeros) of the blurred image at each noise."""
    rng = np.random.default_rng(seed)
    kernel = motion_kernel(16, 30)
    return {s: float(log_power_spectrum(blur_image(camera(), kernel, s, rng=rng)).min())
            for s in sigmas}  # fmt: skip


def nb01_threshold(lengths=(2.0, 2.5, 3.0, 3.5, 4.0, 5.0), seed: int = 0) -> dict:
    """01, item 3: the blur score of lightly blurred photographs and the verdict at two thresholds.

    Returns ``{threshold: number of the blurred photographs flagged}`` and the scores.
    """
    rng = np.random.default_rng(seed)
    frames = [blur_image(camera(), motion_kernel(length, 30), 0.005, rng=rng) for length in lengths]
    verdicts = {
        t: [detect_blur(frame, threshold=t) for frame in frames] for t in (BLUR_THRESHOLD, 3.0)
    }
    flagged = {t: sum(flag for flag, _ in v) for t, v in verdicts.items()}
    return flagged, [round(score, 2) for _, score in verdicts[BLUR_THRESHOLD]]


def nb01_frame_size(length_px: float = 16.0, factor: int = 4, seed: int = 0) -> tuple:
    """01, item 4: the estimated length at full size and after shrinking the frame ``factor``x."""
    rng = np.random.default_rng(seed)
    blurred = blur_image(camera(), motion_kernel(length_px, 30), 0.005, rng=rng)
    small = rescale(blurred, 1 / factor, anti_aliasing=True)
    return estimate_motion_blur(blurred).length_px, estimate_motion_blur(small).length_px


def nb02_nsr(nsrs=(1e-4, 1e-2, 1.0), seed: int = 0) -> dict:
    """02, item 1: PSNR of the Wiener restoration (true kernel) at each NSR."""
    rng = np.random.default_rng(seed)
    kernel = motion_kernel(15, 30)
    blurred = blur_image(camera(), kernel, 0.01, rng=rng)
    return {n: psnr(camera(), wiener_deconvolve(blurred, kernel, nsr=n).clip(0, 1), 1.0)
            for n in nsrs}  # fmt: skip


def nb02_linear_light(seed: int = 0) -> dict:
    """02, item 2: PSNR of deconvolving gamma-encoded values and of deconvolving linear light.

    The blur is applied in linear light (as a camera's exposure averages light), then encoded.
    """
    rng = np.random.default_rng(seed)
    kernel = motion_kernel(15, 30)
    sharp = camera()
    blurred = linear_to_srgb(blur_image(srgb_to_linear(sharp), kernel, 0.002, rng=rng).clip(0, 1))
    direct = wiener_deconvolve(blurred, kernel, nsr=1e-3)
    linear = linear_to_srgb(wiener_deconvolve(srgb_to_linear(blurred), kernel, nsr=1e-3).clip(0, 1))
    return {"gamma": psnr(sharp, direct.clip(0, 1), 1.0),
            "linear": psnr(sharp, linear.clip(0, 1), 1.0)}  # fmt: skip


def nb02_boundaries(seed: int = 0) -> dict:
    """02, item 3: PSNR of Wiener after blurring with periodic (wrap) or mirror borders.

    ``wiener_deconvolve`` extends the image by mirror reflection before its DFT, which matches
    mirror borders and not periodic ones.
    """
    rng = np.random.default_rng(seed)
    kernel = motion_kernel(15, 30)
    found = {}
    for boundary in ("wrap", "reflect"):
        blurred = blur_image(camera(), kernel, 0.0, boundary=boundary, rng=rng)
        found[boundary] = psnr(camera(), wiener_deconvolve(blurred, kernel, 1e-3).clip(0, 1), 1.0)
    return found


def nb02_kernel_zeros(lengths=(1.5, 10.0), size: int = 64) -> dict:
    """02, item 4: the smallest |C(f)| of a line kernel of each length (no zero: no undoing)."""
    return {length: float(np.abs(np.fft.fft2(motion_kernel(length, 0), (size, size))).min())
            for length in lengths}  # fmt: skip


def nb00_exposure(strengths=(1.1, 2.2, 4.4), size=(160, 120), seed: int = 0) -> dict:
    """00, items 1 and 3: the mean blur extent (px) of one stand-in frame at each exposure.

    The frame is the first of the heads scene's first test sequence, rendered at ``size``.
    """
    config = SynthConfig.quick(width=size[0], height=size[1])
    scene, trajectory = sequence_trajectory("heads", 1, config, seed)
    camera_matrix = intrinsics(*size)
    return {s: render_exposure(scene, trajectory, 1.0, replace(config, blur_strength=s),
                               camera_matrix)[3].mean_px
            for s in strengths}  # fmt: skip


def nb00_baseline(route_share: float = 0.0, seed: int = 0) -> list[dict]:
    """00, items 4 and 5: the mean-pose baseline of a quick heads stand-in with other settings."""
    root = Path(tempfile.mkdtemp(prefix="standin-try-"))
    config = SynthConfig.quick(route_share=route_share)
    synthesize(root, scenes=["heads"], config=config, seed=seed, progress=False)
    return baseline_beside_real(root)
