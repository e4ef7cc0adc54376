"""Blind estimation of linear motion blur on natural photographs (notebook 01): random crops of
scikit-image's photographs, blurred at known lengths and angles, estimated blindly."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import skimage.data
from tqdm.auto import tqdm

from ..blur import SINC_AGREEMENT, blur_image, estimate_motion_blur, motion_kernel
from ..images import as_float_image

#: scikit-image's bundled photographs used as sharp natural test content (gray, [0, 1]). Its
#: ``clock`` is left out: that photograph is itself motion-blurred (notebook 01 estimates its
#: blur), so it cannot serve as the sharp truth.
PHOTOS = ("astronaut", "camera", "coffee", "chelsea", "rocket", "brick", "grass", "gravel",
          "immunohistochemistry", "hubble_deep_field", "coins", "moon", "retina",
          "cell")  # fmt: skip


def crop_photo(index: int) -> str:
    """The photograph (a name in PHOTOS) that crop number ``index`` of :func:`photo_crops` is
    cut from: the crops cycle through PHOTOS."""
    return PHOTOS[index % len(PHOTOS)]


def photo_crops(count: int, size: int = 256, seed: int = 0) -> list[np.ndarray]:
    """Random square gray crops of scikit-image's photographs, cycling through PHOTOS
    (:func:`crop_photo` names the photograph of each).

    Parameters
    ----------
    count : int
        Number of crops.
    size : int
        Side of each crop, pixels.
    seed : int
        Seed of the crop positions.

    Returns
    -------
    list of numpy.ndarray
        ``count`` arrays (size, size), float64 in [0, 1].
    """
    rng = np.random.default_rng(seed)
    crops = []
    for index in range(count):
        photo = as_float_image(getattr(skimage.data, crop_photo(index))())
        gray = photo.mean(axis=2) if photo.ndim == 3 else photo
        if min(gray.shape) < size:
            raise ValueError(f"photo {crop_photo(index)} is smaller than {size} px")
        row = rng.integers(0, gray.shape[0] - size + 1)
        col = rng.integers(0, gray.shape[1] - size + 1)
        crops.append(gray[row : row + size, col : col + size])
    return crops


def angle_error_deg(a: float | np.ndarray, b: float | np.ndarray) -> np.ndarray:
    """Smallest difference between two line directions, modulo 180 degrees.

    Parameters
    ----------
    a, b : float or numpy.ndarray
        Directions, degrees (broadcast against each other).

    Returns
    -------
    numpy.ndarray
        Degrees in [0, 90].
    """
    difference = np.abs(np.asarray(a) - np.asarray(b)) % 180.0
    return np.minimum(difference, 180.0 - difference)


def estimation_trials(
    images: list[np.ndarray],
    lengths: Iterable[float],
    noise_sigmas: Iterable[float],
    seed: int = 0,
    progress: bool = False,
    agreement: tuple[float, float] = SINC_AGREEMENT,
) -> list[dict]:
    """Blur every image by a linear kernel of each length at a random angle, add Gaussian noise
    of each sigma, and estimate length and angle blindly.

    Parameters
    ----------
    images : list of numpy.ndarray
        Gray images (H, W), float in [0, 1].
    lengths : iterable of float
        Blur lengths L, pixels.
    noise_sigmas : iterable of float
        Standard deviations of the added Gaussian noise ([0, 1] intensities).
    seed : int
        Seed of the angles and the noise.
    progress : bool
        Show a progress bar.
    agreement : tuple of float
        The sinc refinement's band (:func:`~blurloc.blur.estimate_motion_blur`).

    Returns
    -------
    list of dict
        One row per (image, length, sigma): image, length_px, angle_deg, noise_sigma,
        estimated_length_px, estimated_angle_deg, length_error_px, angle_error_deg.

    References
    ----------
    Eq. 1 of the paper (the blur model).
    """
    rng = np.random.default_rng(seed)
    trials = [(i, float(L), float(s)) for i in range(len(images)) for L in lengths
              for s in noise_sigmas]  # fmt: skip
    rows = []
    for index, length, sigma in tqdm(trials, disable=not progress, desc="estimation"):
        angle = float(rng.uniform(0, 180))
        blurred = blur_image(images[index], motion_kernel(length, angle), sigma, rng=rng)
        estimate = estimate_motion_blur(blurred, agreement=agreement)
        rows.append({
            "image": index, "length_px": length, "angle_deg": angle, "noise_sigma": sigma,
            "estimated_length_px": estimate.length_px, "estimated_angle_deg": estimate.angle_deg,
            "length_error_px": abs(estimate.length_px - length),
            "angle_error_deg": float(angle_error_deg(estimate.angle_deg, angle)),
        })  # fmt: skip
    return rows


def accuracy_by_noise(trials: list[dict]) -> list[dict]:
    """Angle and length errors of blind estimation trials, summarised per noise level.

    Parameters
    ----------
    trials : list of dict
        Rows of :func:`estimation_trials` (``noise_sigma``, ``angle_error_deg``,
        ``length_error_px``).

    Returns
    -------
    list of dict
        Per noise level, in first-seen order: ``trials``, median and 90th percentile of the
        angle (degrees) and length (px) errors, and the share of trials within 2° and 1 px.
    """
    summary = []
    for sigma in dict.fromkeys(r["noise_sigma"] for r in trials):
        subset = [r for r in trials if r["noise_sigma"] == sigma]
        angle = np.array([r["angle_error_deg"] for r in subset])
        length = np.array([r["length_error_px"] for r in subset])
        summary.append({
            "noise_sigma": sigma, "trials": len(subset),
            "angle_median_deg": round(float(np.median(angle)), 2),
            "angle_p90_deg": round(float(np.percentile(angle, 90)), 2),
            "length_median_px": round(float(np.median(length)), 2),
            "length_p90_px": round(float(np.percentile(length, 90)), 2),
            "within_2deg_1px": round(float(np.mean((angle <= 2) & (length <= 1))), 3),
        })  # fmt: skip
    return summary
