"""The stand-in's camera: what becomes of the rendered linear light on its way to a stored frame
(exposure gain, optics blur, signal-dependent sensor noise, gamma encoding, quantisation and
JPEG compression)."""

from __future__ import annotations

import cv2
import numpy as np

from ..images import to_uint8
from .synth_config import SynthConfig


def gaussian_kernel(sigma_px: float) -> np.ndarray:
    r"""A 1-D kernel whose frequency response is a continuous Gaussian's of ``sigma_px`` pixels.

    Sampling the Gaussian at whole pixels would blur far less than it when sigma is under a
    pixel (at 0.4 px the neighbours get 4 %); the kernel is instead the inverse DFT of the
    continuous Gaussian's transfer function, over 2 ceil(4 sigma) + 7 taps.

    .. math:: H(f) = \exp(-2 \pi^2 \sigma^2 f^2)

    Parameters
    ----------
    sigma_px : float
        Standard deviation, pixels (> 0).

    Returns
    -------
    numpy.ndarray
        float32 taps, odd in number, summing to 1.
    """
    taps = 2 * int(np.ceil(4 * sigma_px)) + 7
    response = np.exp(-2 * np.pi**2 * sigma_px**2 * np.fft.fftfreq(taps) ** 2)
    kernel = np.fft.fftshift(np.fft.ifft(response).real)
    return (kernel / kernel.sum()).astype(np.float32)


def optics_blur(linear: np.ndarray, sigma_px: float) -> np.ndarray:
    """The image the lens forms: a Gaussian point spread function of ``sigma_px`` pixels
    (:func:`gaussian_kernel`, along rows and columns).

    Parameters
    ----------
    linear : numpy.ndarray
        (H, W) or (H, W, 3) float32 linear light.
    sigma_px : float
        Standard deviation of the blur, pixels (0: the image itself).

    Returns
    -------
    numpy.ndarray
        Same shape and type, blurred (mirrored at the borders).
    """
    if sigma_px == 0:
        return linear
    kernel = gaussian_kernel(sigma_px)
    return cv2.sepFilter2D(linear, -1, kernel, kernel, borderType=cv2.BORDER_REFLECT)


def sensor_noise(
    linear: np.ndarray, shot: float, read: float, rng: np.random.Generator
) -> np.ndarray:
    """Signal-dependent noise of a sensor at linear signal ``linear``: photon shot noise, whose
    variance grows with the signal, and read noise, which does not (Gaussian approximation).

    .. math:: \\eta \\sim \\mathcal{N}\\left(0,\\; a \\max(x, 0) + \\sigma_r^2\\right)

    Parameters
    ----------
    linear : numpy.ndarray
        Linear light x, any shape.
    shot : float
        Variance a per unit signal.
    read : float
        Read-noise sigma :math:`\\sigma_r`, linear light.
    rng : numpy.random.Generator
        Source of the noise.

    Returns
    -------
    numpy.ndarray
        float32 noise of the shape of ``linear``, to add to it.
    """
    sigma = np.sqrt(shot * np.maximum(linear, 0) + read**2)
    return (rng.standard_normal(linear.shape) * sigma).astype(np.float32)


def jpeg(image: np.ndarray, quality: int) -> np.ndarray:
    """``image`` (H, W, 3) uint8 RGB after JPEG compression at ``quality`` (1-100)."""
    _, encoded = cv2.imencode(".jpg", image[..., ::-1], [cv2.IMWRITE_JPEG_QUALITY, quality])
    return cv2.imdecode(encoded, cv2.IMREAD_COLOR)[..., ::-1]


def capture(
    blurred: np.ndarray, sharp: np.ndarray, config: SynthConfig, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """The stored frames of one exposure: the captured (blurred, noisy) frame and the sharp one.

    Both pass the exposure gain and the optics blur (``config.exposure_gain``,
    ``config.optics_blur_px``); the captured frame then gets sensor noise in linear light
    (:func:`sensor_noise`), Gaussian noise of ``config.noise_sigma`` on the gamma-encoded
    intensities, quantisation and, with ``config.jpeg_quality`` > 0, JPEG compression. The
    sharp frame is only encoded and quantised. Noise is drawn from ``rng`` only for settings
    that are not 0, the encoded noise first.

    Parameters
    ----------
    blurred, sharp : numpy.ndarray
        (H, W, 3) float32 linear light rendered over the exposure and at its middle.
    config : SynthConfig
        The camera's settings.
    rng : numpy.random.Generator
        Source of the noise.

    Returns
    -------
    color, sharp : numpy.ndarray
        (H, W, 3) uint8 RGB, gamma-encoded.
    """
    images = []
    for image in (blurred, sharp):
        if config.exposure_gain != 1:
            image = image * np.float32(config.exposure_gain)
        images.append(optics_blur(image, config.optics_blur_px))
    blurred, sharp = images
    encoded = rng.normal(0.0, config.noise_sigma, blurred.shape) if config.noise_sigma else None
    if config.shot_noise or config.read_noise:
        blurred = blurred + sensor_noise(blurred, config.shot_noise, config.read_noise, rng)
    color = to_uint8(blurred, encoded)
    if config.jpeg_quality:
        color = jpeg(color, config.jpeg_quality)
    return color, to_uint8(sharp)
