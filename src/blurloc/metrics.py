"""Image-quality metrics: PSNR (eq. 5-6) and SSIM (eq. 7)."""

from __future__ import annotations

import numpy as np
from skimage.metrics import structural_similarity

from .images import check_image


def _pair(reference: np.ndarray, estimate: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    reference, estimate = check_image(reference), check_image(estimate)
    if reference.shape != estimate.shape:
        raise ValueError(f"images differ in shape: {reference.shape} vs {estimate.shape}")
    return reference.astype(np.float64), estimate.astype(np.float64)


def psnr(reference: np.ndarray, estimate: np.ndarray, data_range: float) -> float:
    """Peak signal-to-noise ratio in dB: 10 log10(R^2 / MSE) (eq. 5-6), MSE over all pixels and
    channels. ``data_range`` R is explicit: 255 for uint8, 1 for [0, 1] floats (eq. 6 uses 255).
    Identical images give inf."""
    if data_range <= 0:
        raise ValueError("data_range must be > 0")
    reference, estimate = _pair(reference, estimate)
    mse = float(np.mean((reference - estimate) ** 2))
    return float("inf") if mse == 0 else float(10.0 * np.log10(data_range**2 / mse))


def ssim(reference: np.ndarray, estimate: np.ndarray, data_range: float) -> float:
    """Structural similarity (eq. 7) through scikit-image with the settings of Wang et al. (2004):
    Gaussian window σ = 1.5 (11x11), K1 = 0.01, K2 = 0.03, population covariances; RGB is the
    mean of the per-channel SSIMs."""
    if data_range <= 0:
        raise ValueError("data_range must be > 0")
    reference, estimate = _pair(reference, estimate)
    return float(structural_similarity(
        reference, estimate, data_range=data_range, gaussian_weights=True, sigma=1.5,
        use_sample_covariance=False, channel_axis=2 if reference.ndim == 3 else None,
    ))  # fmt: skip
