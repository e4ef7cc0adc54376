"""Gray conversion, the log power spectrum of an image (Welch's method) and its noise level."""

from __future__ import annotations

import functools

import cv2
import numpy as np
import scipy.fft

from ..images import check_image


def to_gray(image: np.ndarray) -> np.ndarray:
    r"""Float gray image in [0, 1]: the mean of the channels of an RGB image.

    .. math::

        g = \frac{R + G + B}{3}

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) image, uint8 (scaled by 1/255) or float in [0, 1].

    Returns
    -------
    numpy.ndarray
        (H, W) gray image, float64 for float64 input, else float32.

    References
    ----------
    Gonzalez and Woods, *Digital Image Processing*, 4th ed., Pearson, 2018, Section 6.2 (the
    intensity of an RGB pixel as the mean of its components).
    """
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
    r"""Centred log power spectrum, averaged over Hann-windowed tiles (Welch's method).

    .. math::

        S(u, v) = \log \frac{1}{K} \sum_{k=1}^{K}
        \bigl| F\{ w \cdot (g_k - \bar{g}_k) \}(u, v) \bigr|^2

    over K tiles :math:`g_k` of ``window`` x ``window`` px overlapping by half (the whole image,
    cropped square, when it is smaller), each minus its mean and times the 2-D Hann window w,
    which removes the border discontinuity that would otherwise draw a bright cross through the
    spectrum. Linear motion blur multiplies it by :math:`|\mathrm{sinc}|^2` across the motion
    (eq. 2), whose zeros show as dark lines.

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) image, uint8 or float in [0, 1]; short side >= 8 px.
    window : int
        Tile side, px.

    Returns
    -------
    numpy.ndarray
        (n, n) float64 log power, zero frequency at the centre (n even, at most ``window``).

    Raises
    ------
    ValueError
        If the image is smaller than 8 px on a side.

    References
    ----------
    Welch, "The use of fast Fourier transform for the estimation of power spectra", IEEE Trans.
    Audio Electroacoust. 15(2), 1967. The paper's eq. 2.
    """
    gray = to_gray(image)  # checks the image
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
    r"""Standard deviation of Gaussian noise in an image ([0, 1] scale), by Immerkær's method.

    .. math::

        \hat{\sigma} = \sqrt{\frac{\pi}{2}}\, \frac{1}{6 (W - 2)(H - 2)}
        \sum_{x, y} \bigl| (I * N)(x, y) \bigr|, \qquad
        N = \begin{pmatrix} 1 & -2 & 1 \\ -2 & 4 & -2 \\ 1 & -2 & 1 \end{pmatrix}

    The 3x3 kernel N cancels smooth image structure (the difference of two Laplacians), so what
    is left of the interior pixels is mostly noise; channels are averaged. This estimates the
    :math:`\eta` of eq. 1.

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) image, uint8 (scaled by 1/255) or float; at least 3x3 px.

    Returns
    -------
    float
        :math:`\hat{\sigma}` on the [0, 1] intensity scale.

    Raises
    ------
    ValueError
        If the image is smaller than 3x3 px.

    References
    ----------
    Immerkær, "Fast noise variance estimation", Computer Vision and Image Understanding 64(2),
    1996. The paper's eq. 1 (the noise term).
    """
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
