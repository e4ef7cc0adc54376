"""Checks and conversions shared by the image functions: what they accept and what they return."""

from __future__ import annotations

import numpy as np

SUPPORTED_DTYPES = (np.uint8, np.float32, np.float64)
#: File suffixes read as images when a folder is given.
IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")


def check_image(image: np.ndarray) -> np.ndarray:
    """Check that an array is a usable image.

    Parameters
    ----------
    image : numpy.ndarray
        Gray (H, W) or RGB (H, W, 3); uint8 (0-255) or float32/float64 (nominally [0, 1]);
        at least 2x2 pixels; finite.

    Returns
    -------
    numpy.ndarray
        ``image`` itself.

    Raises
    ------
    ValueError
        Naming what is wrong.
    """
    if not isinstance(image, np.ndarray):
        raise ValueError(f"image must be a NumPy array, got {type(image).__name__}")
    if image.dtype.type not in SUPPORTED_DTYPES:
        raise ValueError(f"unsupported dtype {image.dtype}: use uint8, float32 or float64")
    if image.ndim not in (2, 3) or (image.ndim == 3 and image.shape[2] != 3):
        raise ValueError(f"image must be (H, W) or (H, W, 3), got shape {image.shape}")
    if image.shape[0] < 2 or image.shape[1] < 2:
        raise ValueError(f"image must be at least 2x2 pixels, got {image.shape[:2]}")
    if image.dtype != np.uint8 and not np.isfinite(image).all():
        raise ValueError("image holds NaN or inf pixels")
    return image


def as_float_image(image: np.ndarray) -> np.ndarray:
    """The image as float64 in [0, 1]; checked first.

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3), uint8 (divided by 255) or float.

    Returns
    -------
    numpy.ndarray
        Same shape, float64.
    """
    image = check_image(image)
    if image.dtype == np.uint8:
        return image.astype(np.float64) / 255.0
    return image.astype(np.float64)


def like_input(result: np.ndarray, original: np.ndarray) -> np.ndarray:
    """Convert a float result back to the dtype of the input it came from.

    Parameters
    ----------
    result : numpy.ndarray
        Float image, nominally [0, 1].
    original : numpy.ndarray
        The input image; its dtype is restored.

    Returns
    -------
    numpy.ndarray
        ``result`` in the dtype of ``original`` (uint8: clipped to [0, 1], scaled and rounded).
    """
    if original.dtype == np.uint8:
        return np.round(np.clip(result, 0.0, 1.0) * 255.0).astype(np.uint8)
    return result.astype(original.dtype)


#: Display gamma of the stand-in renderer and of the photo-made videos (as the GoPro benchmark).
GAMMA = 2.2


def srgb_to_linear(image: np.ndarray) -> np.ndarray:
    """Gamma-encoded intensities to linear light.

    Parameters
    ----------
    image : numpy.ndarray
        Any shape, float, nominally [0, 1] (clipped to it).

    Returns
    -------
    numpy.ndarray
        Same shape, ``image ** GAMMA`` (gamma 2.2, as the GoPro benchmark).
    """
    return np.power(np.clip(image, 0.0, 1.0), GAMMA)


def linear_to_srgb(image: np.ndarray) -> np.ndarray:
    """Linear light to gamma-encoded intensities, clipped to [0, 1] (the sensor saturates).

    Parameters
    ----------
    image : numpy.ndarray
        Any shape, float, linear light.

    Returns
    -------
    numpy.ndarray
        Same shape, ``clip(image, 0, 1) ** (1 / GAMMA)``.
    """
    return np.power(np.clip(image, 0.0, 1.0), 1.0 / GAMMA)


def to_uint8(linear: np.ndarray, noise: np.ndarray | None = None) -> np.ndarray:
    """Gamma-encode linear light, add noise on the encoded intensities and quantise to uint8.

    Parameters
    ----------
    linear : numpy.ndarray
        Image (H, W) or (H, W, 3), float, linear light in [0, 1].
    noise : numpy.ndarray, optional
        Same shape as ``linear``, added after gamma encoding ([0, 1] intensity units).

    Returns
    -------
    numpy.ndarray
        Same shape, uint8 (0-255), rounded.
    """
    encoded = linear_to_srgb(linear)
    if noise is not None:
        encoded = encoded + noise
    return np.round(np.clip(encoded, 0.0, 1.0) * 255.0).astype(np.uint8)
