"""How much of a PSNR is sub-pixel misregistration (notebook 03)."""

from __future__ import annotations

import cv2
import numpy as np
from scipy.optimize import minimize
from skimage.filters import window
from skimage.registration import phase_cross_correlation

from ..images import as_float_image
from ..metrics import psnr


def _shifted(image: np.ndarray, dx: float, dy: float) -> np.ndarray:
    matrix = np.float32([[1, 0, dx], [0, 1, dy]])
    return cv2.warpAffine(np.float32(image), matrix, image.shape[1::-1], flags=cv2.INTER_CUBIC,
                          borderMode=cv2.BORDER_REFLECT)  # fmt: skip


def registered_psnr(
    reference: np.ndarray, estimate: np.ndarray, border: int = 8
) -> tuple[float, float, float]:
    """How much of a PSNR loss is misregistration.

    Finds the global sub-pixel shift of ``reference`` that best matches ``estimate`` (a
    Hann-windowed phase correlation at 1/20 px, refined by minimising the squared error) and
    compares the PSNR before and after that shift.

    Parameters
    ----------
    reference, estimate : numpy.ndarray
        Images of one shape, (H, W) or (H, W, 3), uint8 or float in [0, 1].
    border : int
        Pixels skipped at each side in both PSNRs.

    Returns
    -------
    shift : float
        Length of the shift, pixels.
    psnr, registered_psnr : float
        dB (data range 1), before and after the shift.

    References
    ----------
    Eq. 5-6 of the paper (PSNR).
    """
    reference, estimate = as_float_image(reference), as_float_image(estimate)
    if reference.shape != estimate.shape or min(reference.shape[:2]) <= 2 * border + 8:
        raise ValueError(f"images must share a shape larger than the border, got "
                         f"{reference.shape} and {estimate.shape}")  # fmt: skip
    gray = [x if x.ndim == 2 else x.mean(axis=2) for x in (reference, estimate)]
    hann = window("hann", gray[0].shape)
    (dy, dx), _, _ = phase_cross_correlation(gray[1] * hann, gray[0] * hann, upsample_factor=20)
    inner = (slice(border, -border), slice(border, -border))

    def error(shift: np.ndarray) -> float:
        moved = np.clip(_shifted(reference, *shift), 0.0, 1.0)
        return float(np.mean((moved[inner] - estimate[inner]) ** 2))

    best = minimize(error, [dx, dy], method="Nelder-Mead", options={"xatol": 0.01, "fatol": 1e-10})
    registered = np.clip(_shifted(reference, *best.x), 0.0, 1.0)
    return (float(np.hypot(*best.x)), psnr(reference[inner], estimate[inner], 1.0),
            psnr(registered[inner], estimate[inner], 1.0))  # fmt: skip
