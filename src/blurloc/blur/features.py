"""Spectral and gradient features of an image that the blind blur estimator reads.

Conventions: images are float arrays in [0, 1] (or uint8), rows downwards. Angles are degrees in
[0, 180), counter-clockwise from the image's horizontal axis as displayed (y up); lengths are
pixels of the image given.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import cv2
import numpy as np
import scipy.fft

from .spectrum import _hann, estimate_noise_sigma, to_gray

#: Smallest image side (px) on which blur can be detected or estimated.
MIN_ANALYSIS_SIDE = 16


#: Short side (px) of the copy of an image on which :func:`blur_features` measures the spectrum
#: (larger images are area-averaged down to it; lengths are scaled back). 160x120 frames are
#: measured as they are; a 640x480 frame at half size, so that 3 px of its blur are still 1.5 px.
ANALYSIS_SIDE = 240
_TILE = 64  # Welch tile (px) at the analysis scale
_ANGLES, _RADII = 36, 14  # polar bins of the half-plane spectrum: 5° sectors, log-spaced rings
_EDGE_WINDOWS = (5, 9, 17)  # sides (px at the analysis scale) of the windows that span an edge


@functools.cache
def _polar_bins(size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Polar bin of every frequency of a ``size`` x ``size`` real FFT (``rfft2`` layout): sector
    (direction of the frequency, folded onto the upper half-plane) * _RADII + ring, -1 outside
    1.5 bins .. 0.48 cycles/px; the number of frequencies per bin; and each sector's direction
    (rad, x right / y down). Cached per size."""
    fy = np.fft.fftfreq(size)[:, None] * np.ones((1, size // 2 + 1))
    fx = np.fft.rfftfreq(size)[None, :] * np.ones((size, 1))
    flip = fy < 0
    fx, fy = np.where(flip, -fx, fx), np.abs(fy)
    radius = np.hypot(fx, fy)
    low, high = 1.5 / size, 0.48
    sector = np.rint(np.arctan2(fy, fx) / np.pi * _ANGLES).astype(int) % _ANGLES
    ring = np.log(np.maximum(radius, low) / low) / np.log(high / low) * _RADII
    index = sector * _RADII + np.minimum(ring.astype(int), _RADII - 1)
    index = np.where((radius >= low) & (radius <= high), index, -1).ravel()
    counts = np.bincount(index[index >= 0], minlength=_ANGLES * _RADII)
    return index, np.maximum(counts, 1), np.arange(_ANGLES) * np.pi / _ANGLES


def _analysis_copy(image: np.ndarray) -> tuple[np.ndarray, float]:
    """Gray float32 copy at the analysis scale and the factor (>= 1) from its pixels to the
    image's."""
    gray = to_gray(image).astype(np.float32, copy=False)  # to_gray checks the image
    short = min(gray.shape)
    if short < MIN_ANALYSIS_SIDE:
        raise ValueError(f"image too small to estimate blur: {gray.shape} "
                         f"(needs >= {MIN_ANALYSIS_SIDE} px)")  # fmt: skip
    if short <= ANALYSIS_SIDE:
        return gray, 1.0
    factor = short / ANALYSIS_SIDE
    size = (round(gray.shape[1] / factor), round(gray.shape[0] / factor))
    return cv2.resize(gray, size, interpolation=cv2.INTER_AREA), factor


def _log_energy(values: np.ndarray) -> float:
    return float(np.log(np.mean(np.square(values, dtype=np.float64)) + 1e-12))


def edge_widths(gray: np.ndarray, sigma: float) -> np.ndarray:
    r"""Log widths of an image's strong edges, in 16 values.

    Edge pixels are the local maxima (3x3) of the gradient magnitude :math:`|\nabla I|` (Sobel,
    per px) that exceed 3 noise σ, away from a border of up to 8 px, and of those the stronger
    half. An edge of contrast C spread over w px rises by C/w per px, so its width is the
    intensity range of a window of side k around the edge pixel over the gradient there:

    .. math::

        w_k = \frac{\max_{k \times k} I - \min_{k \times k} I}{|\nabla I|}

    (clipped to 0.5-40 px; a window shorter than the edge cuts it to about k). Motion blur of
    length L widens edges across the motion by up to L, and leaves those along it as they are.
    For windows of 5, 9 and 17 px: the log of the quartiles and the median of w over all edge
    pixels, and the log of the largest and the smallest median over four gradient directions
    (45° bins; a bin with under 3 pixels takes the overall median); then the log of 1 + the
    number of edge pixels. Without edge pixels every width is 1 px.

    Parameters
    ----------
    gray : numpy.ndarray
        (H, W) float32 gray image in [0, 1].
    sigma : float
        Noise σ of the image ([0, 1] scale).

    Returns
    -------
    numpy.ndarray
        (16,) values.

    References
    ----------
    Marziliano, Dufaux, Winkler and Ebrahimi, "A no-reference perceptual blur metric", ICIP
    2002 (blur as the width of the image's edges).
    The paper's Section III.A.1 (features for the blur length of eq. 1's c).
    """
    gx = cv2.Sobel(gray, cv2.CV_32F, 1, 0) / 8
    gy = cv2.Sobel(gray, cv2.CV_32F, 0, 1) / 8
    magnitude = np.hypot(gx, gy)
    peak = (magnitude >= cv2.dilate(magnitude, np.ones((3, 3), np.uint8))) & (
        magnitude > 3 * sigma + 1e-3
    )
    border = min(8, min(gray.shape) // 4)
    inside = np.zeros_like(peak)
    inside[border : gray.shape[0] - border, border : gray.shape[1] - border] = True
    peak &= inside
    if peak.sum() > 20:
        peak &= magnitude >= np.median(magnitude[peak])
    direction = np.floor(np.arctan2(gy[peak], gx[peak]) % np.pi / (np.pi / 4) + 0.5) % 4
    values = []
    for side in _EDGE_WINDOWS:
        window = np.ones((side, side), np.uint8)
        span = (cv2.dilate(gray, window) - cv2.erode(gray, window))[peak]
        width = np.clip(span / np.maximum(magnitude[peak], 1e-6), 0.5, 40.0)
        if width.size == 0:
            values += [0.0] * 5
            continue
        overall = float(np.median(width))
        medians = [float(np.median(width[direction == b])) if (direction == b).sum() >= 3
                   else overall for b in range(4)]  # fmt: skip
        values += [*np.log(np.quantile(width, [0.25, 0.5, 0.75])), np.log(max(medians)),
                   np.log(min(medians))]  # fmt: skip
    values.append(float(np.log1p(peak.sum())))
    return np.array(values)


@dataclass(frozen=True)
class BlurFeatures:
    """What the blur estimator reads off an image (see :func:`blur_features`).

    ``values`` (78,): the log power spectrum, relative to its lowest frequencies, in 14 rings
    along the motion direction, 14 across it, 14 over all directions, and 14 over all directions
    without the noise floor removed; the log energies of the gradient, of the Laplacian, of the
    gradient at half size and of the image; the log noise σ; the anisotropy; the 16 edge widths
    of :func:`edge_widths`. ``angle_deg``: the
    motion direction (module conventions); ``anisotropy``: how strongly the spectrum's fall-off
    depends on direction (0 for an isotropic spectrum); ``scale``: image px per analysis px.

    The image's size is not among the values: a model that reads it learns how sharp one
    renderer's pixels are at each size, while a camera's optics, demosaicing and compression
    soften its finest pixels at any size, so that sharp photographs would read as blurred.
    """

    values: np.ndarray
    angle_deg: float
    anisotropy: float
    scale: float


def blur_features(image: np.ndarray) -> BlurFeatures:
    r"""Spectral and gradient features of an image, for blur of about 1-15 px at 160x120 and
    2-40 px at 640x480.

    An image whose short side exceeds ANALYSIS_SIDE px is area-averaged to it; the Welch power
    spectrum (Hann tiles of 64 px, half overlap) minus the white-noise floor (Immerkær's σ of the
    gray image) is averaged in 36 direction sectors x 14 log-spaced rings. Blur of length L along d
    multiplies the spectrum by |sinc(L f·d)|^2, so the power falls off fastest along d: the
    direction is the phase of the second angular harmonic of each sector's fall-off (log power in
    the lowest third of the rings minus the highest half). The radial profiles along d, across d
    and over all directions, each relative to the lowest rings, describe the fall-off; the
    profile across d is the scene's own spectrum, against which the one along d shows the blur.
    Gradient energies at two scales (Crété-Roffet et al.'s re-blur idea: blur removes the fine
    gradients, not the coarse ones), the noise σ and the widths of the strongest edges
    (:func:`edge_widths`: what blur does where a scene has few edges on flat surfaces, whose
    spectrum is mostly noise) complete them.

    The direction comes from the second angular harmonic of the fall-off :math:`D_s` of sector
    s (at angle :math:`\phi_s`), since blur along d multiplies the spectrum by (eq. 2: the
    spectrum of b is that of x times that of c)

    .. math::

        |F\{c\}(f)|^2 = \mathrm{sinc}^2(L\, f \cdot d), \qquad
        \hat{d} = \tfrac{1}{2} \arg \sum_s D_s\, e^{2 i \phi_s}

    Parameters
    ----------
    image : np.ndarray
        (H, W) or (H, W, 3) image, uint8 or float in [0, 1]; short side >= 16 px.

    Returns
    -------
    BlurFeatures
        The 78 values, the direction (degrees, y up), the anisotropy and the scale.

    References
    ----------
    Yitzhaky and Kopeika, "Identification of blur parameters from motion blurred images", CVGIP
    1997: the motion direction is where the blurred image loses most high-frequency energy.
    Crété-Roffet, Dolmière, Ladret and Nicolas, "The blur effect: perception and estimation with
    a new no-reference perceptual blur metric", SPIE 2007. Welch, IEEE Trans. Audio
    Electroacoust. 1967 (averaged periodograms). Immerkær, CVIU 1996. Marziliano, Dufaux,
    Winkler and Ebrahimi, ICIP 2002 (edge widths).
    """
    gray, scale = _analysis_copy(image)
    size = min(_TILE, min(gray.shape) // 2 * 2)
    step = size // 2
    tiles = np.stack([gray[r : r + size, c : c + size]
                      for r in range(0, gray.shape[0] - size + 1, step)
                      for c in range(0, gray.shape[1] - size + 1, step)])  # fmt: skip
    window = _hann(size)
    tiles = (tiles - tiles.mean(axis=(1, 2), keepdims=True)) * window
    power = (np.abs(scipy.fft.rfft2(tiles)) ** 2).mean(axis=0).ravel()
    power /= float((window.astype(np.float64) ** 2).sum())  # white noise of variance v: v
    index, counts, sectors = _polar_bins(size)
    inside = index >= 0
    binned = np.bincount(index[inside], power[inside], minlength=counts.size) / counts
    sigma = estimate_noise_sigma(gray)
    noise = sigma**2
    log_power = np.log(np.maximum(binned - noise, 0.1 * noise + 1e-12)).reshape(_ANGLES, _RADII)
    falloff = log_power[:, : _RADII // 3].mean(axis=1) - log_power[:, -_RADII // 2 :].mean(axis=1)
    harmonic = (falloff * np.exp(2j * sectors)).sum()
    direction = float(np.angle(harmonic) / 2 % np.pi)  # rad, x right / y down
    along = int(np.rint(direction / np.pi * _ANGLES)) % _ANGLES
    across = (along + _ANGLES // 2) % _ANGLES
    reference = log_power[:, :2].mean()
    neighbours = np.arange(-1, 2)
    raw = np.log(binned + 1e-12).reshape(_ANGLES, _RADII).mean(axis=0)
    half = cv2.resize(gray, None, fx=0.5, fy=0.5, interpolation=cv2.INTER_AREA)
    gradients = [
        float(np.logaddexp(_log_energy(cv2.Sobel(copy, cv2.CV_32F, 1, 0)),
                           _log_energy(cv2.Sobel(copy, cv2.CV_32F, 0, 1))))
        for copy in (gray, half)
    ]  # fmt: skip
    anisotropy = float(abs(harmonic) / _ANGLES)
    values = np.concatenate([
        log_power[(along + neighbours) % _ANGLES].mean(axis=0) - reference,
        log_power[(across + neighbours) % _ANGLES].mean(axis=0) - reference,
        log_power.mean(axis=0) - reference,
        raw - raw[:2].mean(),
        [gradients[0], _log_energy(cv2.Laplacian(gray, cv2.CV_32F)), gradients[1],
         float(np.log(gray.var(dtype=np.float64) + 1e-12)), float(np.log(sigma + 1e-6)),
         anisotropy],
        edge_widths(gray, sigma),
    ])  # fmt: skip
    angle = float(np.degrees(np.arctan2(-np.sin(direction), np.cos(direction))) % 180.0)
    return BlurFeatures(values, angle, anisotropy, scale)
