"""Gray conversion, the log power spectrum of an image (Welch's method) and its noise level."""

from __future__ import annotations

import functools

import cv2
import numpy as np
import scipy.fft

from ..images import check_image


def to_gray(image: np.ndarray) -> np.ndarray:
    """Float gray image in [0, 1] (mean of the channels of an RGB image); float32 unless the
    input is float64."""
    image = check_image(image)
    dtype = np.float64 if image.dtype == np.float64 else np.float32
    scale = 1.0 / 255.0 if image.dtype == np.uint8 else 1.0
    if image.ndim == 2:
        return image.astype(dtype) * dtype(scale)
    weights = np.full((1, 3), scale / 3.0)
    return cv2.transform(image.astype(dtype), weights)


@functools.cache
def _hann(size: int) -> np.ndarray:
    """2-D Hann window (float32), cached per size: a folder of frames plans it once."""
    return np.outer(np.hanning(size), np.hanning(size)).astype(np.float32)


def log_power_spectrum(image: np.ndarray, window: int = 256) -> np.ndarray:
    """Centred log power spectrum, averaged over Hann-windowed tiles (Welch's method).

    Tiles of ``window`` x ``window`` px (the whole image, cropped square, if it is smaller)
    overlap by half; the Hann window removes the border discontinuity that would otherwise draw
    a bright cross through the spectrum. Returns log(mean |FFT|^2), zero frequency at the centre.
    """
    gray = to_gray(check_image(image))
    size = min(window, *gray.shape)
    size -= size % 2
    if size < 8:
        raise ValueError(f"image too small for a spectrum: {gray.shape}")
    hann = _hann(size)
    step = size // 2
    tiles = [
        gray[r : r + size, c : c + size]
        for r in range(0, gray.shape[0] - size + 1, step)
        for c in range(0, gray.shape[1] - size + 1, step)
    ]
    stack = np.stack(tiles).astype(np.float32)
    stack = (stack - stack.mean(axis=(1, 2), keepdims=True)) * hann
    half = (np.abs(scipy.fft.rfft2(stack, workers=-1)) ** 2).mean(axis=0, dtype=np.float64)
    power = np.empty((size, size))  # the other half by symmetry: P(-f) = P(f) for real tiles
    power[:, : size // 2 + 1] = half
    power[:, size // 2 + 1 :] = half[(-np.arange(size)) % size, size // 2 - 1 : 0 : -1]
    return np.fft.fftshift(np.log(power + 1e-12))


_IMMERKAER = np.float32([[1.0, -2.0, 1.0], [-2.0, 4.0, -2.0], [1.0, -2.0, 1.0]])


def estimate_noise_sigma(image: np.ndarray) -> float:
    """Standard deviation of Gaussian noise in ``image`` ([0, 1] scale), by Immerkær's method
    (1996): the mean absolute response to a 3x3 kernel that cancels smooth image structure,
    times sqrt(pi / 2) / 6. Channels are averaged."""
    image = check_image(image)
    if min(image.shape[:2]) < 3:
        raise ValueError("image must be at least 3x3 pixels to estimate noise")
    scale = 1.0 / 255.0 if image.dtype == np.uint8 else 1.0
    if image.dtype == np.uint8:  # exact in 16-bit integers (|response| <= 16 * 255)
        response = cv2.filter2D(image, cv2.CV_16S, _IMMERKAER.astype(np.int16))
    else:
        response = cv2.filter2D(image.astype(np.float32, copy=False), cv2.CV_32F, _IMMERKAER)
    interior = response[1:-1, 1:-1]
    mean_abs = cv2.norm(np.ascontiguousarray(interior), cv2.NORM_L1) / interior.size
    return float(np.sqrt(np.pi / 2) / 6 * scale * mean_abs)
