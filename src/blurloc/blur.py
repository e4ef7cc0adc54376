"""Motion blur: kernels (PSFs), the blur model (eq. 1), spectra, detection and blind estimation.

Conventions: images are float arrays in [0, 1] (or uint8), rows downwards. Angles are degrees in
[0, 180), counter-clockwise from the image's horizontal axis as displayed (y up); lengths are
pixels of the image given. A kernel is a 2-D array summing to 1 with its centre at
``(rows // 2, cols // 2)``.
"""

from __future__ import annotations

import functools
import itertools
import os
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
import scipy.fft

from .images import as_float_image, check_image

_SUBSAMPLES_PER_PX = 16


def _splat(points: np.ndarray, weights: np.ndarray, size: int) -> np.ndarray:
    """Bilinear splat of points (x right, y down; 0 = kernel centre) into a size x size kernel."""
    kernel = np.zeros((size, size))
    x = points[:, 0] + size // 2
    y = points[:, 1] + size // 2
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - x0, y - y0
    for dx, dy, w in ((0, 0, (1 - fx) * (1 - fy)), (1, 0, fx * (1 - fy)),
                      (0, 1, (1 - fx) * fy), (1, 1, fx * fy)):  # fmt: skip
        np.add.at(kernel, (y0 + dy, x0 + dx), w * weights)
    return kernel / kernel.sum()


def motion_kernel(length_px: float, angle_deg: float, size: int | None = None) -> np.ndarray:
    """Linear motion PSF: a segment of ``length_px`` pixels at ``angle_deg``, anti-aliased.

    The segment is centred on the kernel centre and sampled 16 times per pixel with bilinear
    weights, so sub-pixel lengths and any angle are represented. ``size`` (odd) defaults to the
    smallest odd size that holds the segment.
    """
    length_px = float(length_px)
    if not np.isfinite(length_px) or length_px <= 0:
        raise ValueError(f"kernel length must be > 0, got {length_px}")
    needed = 2 * int(np.ceil(length_px / 2 + 1)) + 1
    size = size or needed
    if size < needed - 2 or size % 2 == 0:
        raise ValueError(f"kernel size must be odd and hold the segment (>= {needed - 2})")
    count = max(2, int(np.ceil(length_px * _SUBSAMPLES_PER_PX)))
    t = (np.arange(count) + 0.5) / count - 0.5
    theta = np.radians(angle_deg)
    points = np.column_stack([t * length_px * np.cos(theta), -t * length_px * np.sin(theta)])
    return _splat(points, np.ones(count), size)


def trajectory_kernel(
    trajectory_px: np.ndarray, size: int | None = None, origin: np.ndarray | None = None
) -> np.ndarray:
    """PSF of a camera-shake path: image positions (N, 2; x right, y down, px) at equal time
    steps over the exposure, sampled 16 times per pixel. ``origin`` (2,) is the position placed
    at the kernel centre (default: the path's mean); pass the mid-exposure position to get the
    kernel that maps a mid-exposure sharp frame to the blurred one without a shift."""
    path = np.asarray(trajectory_px, float)
    if path.ndim != 2 or path.shape[1] != 2 or len(path) < 1 or not np.isfinite(path).all():
        raise ValueError("trajectory must be a finite (N, 2) array of pixel positions")
    path = path - (path.mean(axis=0) if origin is None else np.asarray(origin, float))
    samples, weights = [path[:1]], [np.ones(1)]  # a single position: a sharp (delta) kernel
    for start, end in itertools.pairwise(path):
        count = max(1, int(np.ceil(np.linalg.norm(end - start) * _SUBSAMPLES_PER_PX)))
        t = (np.arange(count) + 0.5)[:, None] / count
        samples.append(start + t * (end - start))
        weights.append(np.full(count, 1.0 / count))  # equal time per segment
    if len(path) > 1:
        samples, weights = samples[1:], weights[1:]
    points, weight = np.concatenate(samples), np.concatenate(weights)
    needed = 2 * int(np.ceil(np.abs(points).max() + 1)) + 1
    return _splat(points, weight, size or needed)


def shake_path(extent_px: float, rng: np.random.Generator, steps: int = 500) -> np.ndarray:
    """A random hand-shake path over one exposure, for kernels like those of real camera shake.

    Boracchi and Foi's model: a point moves at constant speed; at each step its velocity is
    pushed by a Gaussian term and pulled back towards the start (a centripetal term), both
    scaled by a random "anxiety", and now and then reversed by an abrupt shake. The shape's
    parameters are drawn per path from ``rng``; the path is then scaled so that the longer side
    of its bounding box is ``extent_px``.

    Parameters
    ----------
    extent_px : float
        Longer side of the path's bounding box, px (> 0).
    rng : numpy.random.Generator
        Source of the path's shape.
    steps : int
        Positions along the path (>= 2).

    Returns
    -------
    numpy.ndarray
        (steps, 2) positions (x right, y down, px) at equal time steps, for
        :func:`trajectory_kernel`.

    References
    ----------
    Boracchi and Foi, "Modeling the performance of image restoration from motion blur", IEEE
    Trans. Image Process. 21(8), 2012 (their random trajectory generator).
    """
    if not np.isfinite(extent_px) or extent_px <= 0:
        raise ValueError(f"extent_px must be > 0, got {extent_px}")
    if steps < 2:
        raise ValueError(f"steps must be >= 2, got {steps}")
    anxiety, centripetal = 0.1 * rng.random(), 0.7 * rng.random()
    gaussian, abrupt = 10.0 * rng.random(), 0.2 * rng.random()
    speed = 1.0 / (steps - 1)
    velocity = speed * np.exp(2j * np.pi * rng.random())
    points = np.zeros(steps, complex)
    for step in range(steps - 1):
        push = (anxiety * (gaussian * complex(*rng.normal(size=2)) - centripetal * points[step])
                * speed)  # fmt: skip
        if rng.random() < abrupt * anxiety:  # an abrupt shake turns the motion about
            push += 2.0 * velocity * np.exp(1j * (np.pi + rng.random() - 0.5))
        velocity += push
        velocity *= speed / max(abs(velocity), 1e-12)
        points[step + 1] = points[step] + velocity
    path = np.column_stack([points.real, points.imag])
    return (path - path.min(axis=0)) * (extent_px / np.ptp(path, axis=0).max())


def check_kernel(kernel: np.ndarray, image_shape: tuple[int, ...] | None = None) -> np.ndarray:
    """A kernel as float64 normalised to sum 1, or a ValueError saying what is wrong."""
    kernel = np.asarray(kernel, float)
    if kernel.ndim != 2 or kernel.size == 0:
        raise ValueError(f"kernel must be a non-empty 2-D array, got shape {kernel.shape}")
    if not np.isfinite(kernel).all():
        raise ValueError("kernel holds NaN or inf")
    total = kernel.sum()
    if abs(total) < 1e-12:
        raise ValueError("kernel sums to 0: it cannot be normalised")
    if image_shape is not None and (
        kernel.shape[0] > image_shape[0] or kernel.shape[1] > image_shape[1]
    ):
        raise ValueError(f"kernel {kernel.shape} is larger than the image {image_shape[:2]}")
    return kernel / total


def blur_image(
    image: np.ndarray,
    kernel: np.ndarray,
    noise_sigma: float = 0.0,
    boundary: str = "reflect",
    rng: np.random.Generator | None = None,
) -> np.ndarray:
    """The blur model of eq. 1, b = c * x + η: convolve with ``kernel``, add Gaussian noise.

    ``boundary`` is how the image continues beyond its border: ``reflect`` (mirror, without
    repeating the edge pixel), ``wrap`` (periodic, the model the DFT assumes) or ``constant``
    (zeros). Returns float64 (noise is not clipped); uint8 input is scaled to [0, 1] first.
    """
    image = as_float_image(image)
    kernel = check_kernel(kernel, image.shape)
    modes = {"reflect": cv2.BORDER_REFLECT_101, "wrap": cv2.BORDER_WRAP,
             "constant": cv2.BORDER_CONSTANT}  # fmt: skip
    if boundary not in modes:
        raise ValueError(f"boundary must be one of {sorted(modes)}, got {boundary!r}")
    if noise_sigma < 0:
        raise ValueError("noise_sigma must be >= 0")
    flipped = np.ascontiguousarray(kernel[::-1, ::-1])  # filter2D correlates: flip to convolve
    anchor = (kernel.shape[1] // 2, kernel.shape[0] // 2)
    if boundary == "wrap":  # OpenCV's filter2D has no wrap mode: pad periodically, then crop
        ph, pw = kernel.shape[0], kernel.shape[1]
        padded = np.pad(image, ((ph, ph), (pw, pw)) + ((0, 0),) * (image.ndim - 2), mode="wrap")
        out = cv2.filter2D(padded, cv2.CV_64F, flipped, anchor=anchor)[ph:-ph, pw:-pw]
    else:
        out = cv2.filter2D(image, cv2.CV_64F, flipped, anchor=anchor, borderType=modes[boundary])
    if noise_sigma:
        rng = rng or np.random.default_rng()
        out = out + rng.normal(0.0, noise_sigma, out.shape)
    return out


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


#: Smallest image side (px) on which blur can be detected or estimated.
MIN_ANALYSIS_SIDE = 16
#: The detector's classes, by recorded blur extent (px): frames with at least BLURRED_FROM_PX are
#: blurred; frames under SHARP_BELOW_PX (too little blur for deblurring to help) count as sharp,
#: beside the sharp renders; frames in between are left out of calibration.
BLURRED_FROM_PX = 3.0
SHARP_BELOW_PX = 1.5


def calibrate_blur_threshold(
    scores: np.ndarray, blurred: np.ndarray, sharp_groups: np.ndarray | None = None
) -> float:
    """The threshold that maximises balanced accuracy on labelled scores: the mean of the share
    of blurred examples flagged and the share of sharp examples passed; midway between the two
    scores around the cut.

    Parameters
    ----------
    scores : numpy.ndarray
        (N,) blur scores (:func:`blur_score`).
    blurred : numpy.ndarray
        (N,) bool, True for blurred examples; both classes must be present.
    sharp_groups : numpy.ndarray, optional
        (N,) group of each example (read for the sharp ones only). When given, the share of sharp
        examples passed is the mean over the groups of each group's share, so that a small group
        (frames with a little blur) counts as much as a large one (sharp renders).

    Returns
    -------
    float
        The threshold, px.
    """
    scores, blurred = np.asarray(scores, float), np.asarray(blurred, bool)
    if blurred.all() or not blurred.any():
        raise ValueError("calibration needs both blurred and sharp examples")
    groups = np.zeros(len(scores), int) if sharp_groups is None else np.asarray(sharp_groups)
    sharp_sets = [scores[~blurred & (groups == g)] for g in np.unique(groups[~blurred])]
    candidates = np.sort(scores)
    cuts = (candidates[:-1] + candidates[1:]) / 2

    def share_at_or_below(values: np.ndarray) -> np.ndarray:
        return np.searchsorted(np.sort(values), cuts, side="right") / len(values)

    flagged = 1.0 - share_at_or_below(scores[blurred])
    passed = np.mean([share_at_or_below(group) for group in sharp_sets], axis=0)
    balanced = np.round(flagged + passed, 12)  # exact ties go to the lowest cut
    return float(cuts[int(np.argmax(balanced))])


def detection_rates(
    scores: np.ndarray, blurred: np.ndarray, threshold: float
) -> tuple[float, float, float]:
    """How a threshold on blur scores separates blurred from sharp frames.

    Parameters
    ----------
    scores : numpy.ndarray
        (N,) blur scores (:func:`blur_score`).
    blurred : numpy.ndarray
        (N,) bool, True for frames that are blurred; both classes must be present.
    threshold : float
        Frames scoring above it are flagged as blurred.

    Returns
    -------
    flagged, passed, balanced : float
        Share of blurred frames flagged, share of sharp frames passed, and their mean
        (balanced accuracy).
    """
    scores, blurred = np.asarray(scores, float), np.asarray(blurred, bool)
    flagged = float((scores[blurred] > threshold).mean())
    passed = float((scores[~blurred] <= threshold).mean())
    return flagged, passed, (flagged + passed) / 2


@dataclass(frozen=True)
class BlurEstimate:
    """Blind estimate of motion blur: ``length_px`` at ``angle_deg`` (module conventions) and
    ``fit``, the correlation of the spectrum's profile with the sinc model (1 = perfect) when the
    length was refined from the sinc zeros, else 0."""

    length_px: float
    angle_deg: float
    fit: float

    def kernel(self) -> np.ndarray:
        """The linear motion kernel of this estimate."""
        return motion_kernel(max(self.length_px, 1.0), self.angle_deg)


def _whiten(log_spectrum: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Log spectrum minus its radial mean, and the centred frequency grids (in bins)."""
    size = log_spectrum.shape[0]
    fy, fx = np.mgrid[-(size // 2) : size - size // 2, -(size // 2) : size - size // 2]
    radius = np.hypot(fx, fy)
    ring = np.round(radius).astype(int)
    radial_mean = np.bincount(ring.ravel(), log_spectrum.ravel()) / np.bincount(ring.ravel())
    return log_spectrum - radial_mean[ring], fx, fy


def _profile(
    values: np.ndarray, fx: np.ndarray, fy: np.ndarray, angle_rad: float, resolution: float = 0.5
) -> tuple[np.ndarray, np.ndarray]:
    """Mean of spectrum ``values`` (at frequencies fx, fy in bins, one half-plane) along lines
    perpendicular to direction ``angle_rad`` (x right, y down), against the distance |r| (bins)
    along it: the Radon projection of the (symmetric) spectrum onto that direction, folded."""
    index = np.rint(np.abs(fx * np.cos(angle_rad) + fy * np.sin(angle_rad)) / resolution)
    index = index.astype(int)
    counts = np.bincount(index)
    sums = np.bincount(index, values)
    keep = counts > 0
    return np.arange(counts.size)[keep] * resolution, sums[keep] / counts[keep]


_ANGLE_STEPS_DEG = (3.0, 0.5, 0.1)  # coarse-to-fine search of the motion direction


def _sinc_fit(r: np.ndarray, profile: np.ndarray, size: int) -> tuple[float, float]:
    """Length L (px) whose log |sinc(L r / N)|^2 correlates best with the profile, and that
    correlation. Zeros of a length-L box lie every N / L frequency bins. Searched on a 0.5 px
    grid from 1 px to min(64, N/2) px, then refined to 0.02 px."""
    keep = np.abs(r) >= 1.0
    radius, values = np.abs(r[keep]), profile[keep]
    centred = values - values.mean()

    def correlations(lengths: np.ndarray) -> np.ndarray:
        models = np.log(np.sinc(lengths[:, None] * radius[None, :] / size) ** 2 + 1e-3)
        models -= models.mean(axis=1, keepdims=True)
        norms = np.linalg.norm(models, axis=1) * np.linalg.norm(centred) + 1e-12
        return models @ centred / norms

    lengths = np.arange(1.0, min(64.0, size / 2), 0.5)
    best = lengths[int(np.argmax(correlations(lengths)))]
    lengths = np.arange(max(1.0, best - 0.5), best + 0.5 + 1e-9, 0.02)
    fits = correlations(lengths)
    return float(lengths[int(np.argmax(fits))]), float(fits.max())


def _analyse(gray: np.ndarray, window: int, around_deg: float) -> tuple[float, float, float]:
    """Direction (rad, x right / y down), length (px) and sinc-fit correlation. The direction is
    searched within 12° of ``around_deg`` (degrees, same convention)."""
    spectrum = log_power_spectrum(gray, window)
    size = spectrum.shape[0]
    whitened, fx, fy = _whiten(spectrum)
    radius = np.hypot(fx, fy)
    # the spectrum of a real image is symmetric: one half-plane holds all of it
    upper = (fy > 0) | ((fy == 0) & (fx > 0))
    mask = (radius >= 2) & (radius <= 0.9 * size / 2) & upper
    values, fx, fy = whitened[mask], fx[mask].astype(float), fy[mask].astype(float)

    def spread(angle: float) -> float:
        return float(np.var(_profile(values, fx, fy, angle)[1]))

    best = None
    for level, step in enumerate(_ANGLE_STEPS_DEG):
        if best is None:
            candidates = around_deg + np.arange(-12.0, 12.0 + 1e-9, step)
        else:
            span = _ANGLE_STEPS_DEG[level - 1]
            candidates = best + np.arange(-span, span + 1e-9, step)
        best = candidates[int(np.argmax([spread(np.radians(a)) for a in candidates]))]
    direction = float(np.radians(best))
    r, profile = _profile(values, fx, fy, direction)
    length, correlation = _sinc_fit(r, profile, size)
    return direction, length, correlation


#: Short side (px) of the copy of an image on which :func:`blur_features` measures the spectrum
#: (larger images are area-averaged down to it; lengths are scaled back). 160x120 frames are
#: measured as they are; a 640x480 frame at half size, so that 3 px of its blur are still 1.5 px.
ANALYSIS_SIDE = 240
_TILE = 64  # Welch tile (px) at the analysis scale
_ANGLES, _RADII = 36, 14  # polar bins of the half-plane spectrum: 5° sectors, log-spaced rings
#: Length model shipped with the package: :func:`fit_length_model` on the stand-in's training
#: split (notebook 01 refits it and compares).
LENGTH_MODEL_PATH = Path(__file__).parent / "weights" / "blur_length.npz"
#: Coarse estimates at least this long (px of the image given) are refined from the sinc zeros.
SINC_MIN_PX = 6.0
#: The refined length is kept only within these factors of the coarse one. Chosen among eleven
#: bands on held-out examples (``benchmarks/choose_sinc_agreement.py``: a 640x480 stand-in
#: render of seed 3 and line-blurred photo crops, neither fitted nor tested on): a lower factor
#: of 0.67 instead of 0.5 lifted the 640x480 rank correlation from 0.84 to 0.87 (below it the
#: sinc fit locks onto content or noise, which 3-D camera blur leaves without clear zeros), and
#: an upper factor of 2 instead of 1.5 cut the photo crops' median length error by a third
#: (0.37 to 0.24 px; beyond 2 lie multiples of the length).
SINC_AGREEMENT = (0.67, 2.0)


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
    gray = to_gray(check_image(image)).astype(np.float32, copy=False)
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


@dataclass(frozen=True)
class BlurFeatures:
    """What the blur estimator reads off an image (see :func:`blur_features`).

    ``values`` (63,): the log power spectrum, relative to its lowest frequencies, in 14 rings
    along the motion direction, 14 across it, 14 over all directions, and 14 over all directions
    without the noise floor removed; the log energies of the gradient, of the Laplacian, of the
    gradient at half size and of the image; the log noise σ; the anisotropy; the log of
    ``scale`` (a 640x480 frame's copy holds finer texture than a 160x120 frame). ``angle_deg``: the
    motion direction (module conventions); ``anisotropy``: how strongly the spectrum's fall-off
    depends on direction (0 for an isotropic spectrum); ``scale``: image px per analysis px.
    """

    values: np.ndarray
    angle_deg: float
    anisotropy: float
    scale: float


def blur_features(image: np.ndarray) -> BlurFeatures:
    """Spectral and gradient features of an image, for blur of about 1-15 px at 160x120 and
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
    gradients, not the coarse ones) and the noise σ complete them.

    Parameters
    ----------
    image : np.ndarray
        (H, W) or (H, W, 3) image, uint8 or float in [0, 1]; short side >= 16 px.

    Returns
    -------
    BlurFeatures
        The 63 values, the direction (degrees, y up), the anisotropy and the scale.

    References
    ----------
    Yitzhaky and Kopeika, "Identification of blur parameters from motion blurred images", CVGIP
    1997: the motion direction is where the blurred image loses most high-frequency energy.
    Crété-Roffet, Dolmière, Ladret and Nicolas, "The blur effect: perception and estimation with
    a new no-reference perceptual blur metric", SPIE 2007. Welch, IEEE Trans. Audio
    Electroacoust. 1967 (averaged periodograms). Immerkær, CVIU 1996.
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
         anisotropy, float(np.log(scale))],
    ])  # fmt: skip
    angle = float(np.degrees(np.arctan2(-np.sin(direction), np.cos(direction))) % 180.0)
    return BlurFeatures(values, angle, anisotropy, scale)


Layers = tuple[tuple[np.ndarray, np.ndarray], ...]


def _perceptron(layers: Layers, inputs: np.ndarray) -> np.ndarray:
    """Output (N,) of one tanh perceptron (each layer's weight (out, in) and bias (out,))."""
    hidden = inputs
    for number, (weight, bias) in enumerate(layers):
        hidden = hidden @ weight.T + bias
        if number < len(layers) - 1:
            hidden = np.tanh(hidden)
    return hidden[:, 0]


@dataclass(frozen=True)
class LengthModel:
    """Small multilayer perceptrons from :func:`blur_features` values to the blur extent (px at
    the analysis scale), averaged: standardised features, tanh hidden layers, one linear output.

    ``mean`` and ``spread`` (k,) standardise the features; ``members`` holds, for each
    perceptron, each layer's weight (out, in) and bias (out,).
    """

    mean: np.ndarray
    spread: np.ndarray
    members: tuple[Layers, ...]

    def predict(self, values: np.ndarray) -> np.ndarray:
        """Extents (N,) in px at the analysis scale from feature values (N, k) or (k,): the
        mean of the members' outputs."""
        inputs = (np.atleast_2d(values) - self.mean) / self.spread
        return np.mean([_perceptron(layers, inputs) for layers in self.members], axis=0)

    def save(self, path: str | os.PathLike) -> None:
        """Write the model to an ``.npz`` file."""
        arrays = {"mean": self.mean, "spread": self.spread}
        for member, layers in enumerate(self.members):
            for number, (weight, bias) in enumerate(layers):
                arrays[f"member{member}_weight{number}"] = weight
                arrays[f"member{member}_bias{number}"] = bias
        np.savez(path, **arrays)

    @classmethod
    def load(cls, path: str | os.PathLike) -> LengthModel:
        """Read a model written by :meth:`save`."""
        with np.load(path) as arrays:
            names = arrays.files
            count = len({name.split("_")[0] for name in names if name.startswith("member")})
            members = []
            for member in range(count):
                depth = sum(name.startswith(f"member{member}_weight") for name in names)
                members.append(tuple((arrays[f"member{member}_weight{n}"],
                                      arrays[f"member{member}_bias{n}"])
                                     for n in range(depth)))  # fmt: skip
            return cls(arrays["mean"], arrays["spread"], tuple(members))


@functools.cache
def default_length_model() -> LengthModel:
    """The shipped length model (LENGTH_MODEL_PATH), read once."""
    return LengthModel.load(LENGTH_MODEL_PATH)


def _fit_perceptron(
    inputs: np.ndarray,
    extents: np.ndarray,
    hidden: int,
    steps: int,
    weight_decay: float,
    seed: int,
) -> Layers:
    """One two-hidden-layer tanh perceptron fitted by full-batch Adam (least squares)."""
    import torch

    generator = torch.Generator().manual_seed(seed)
    sizes = (inputs.shape[1], hidden, hidden, 1)
    linear = [torch.nn.Linear(a, b) for a, b in itertools.pairwise(sizes)]
    with torch.no_grad():
        for layer in linear:  # PyTorch's default initialisation, drawn from our generator
            bound = 1.0 / np.sqrt(layer.in_features)
            layer.weight.uniform_(-bound, bound, generator=generator)
            layer.bias.uniform_(-bound, bound, generator=generator)
    network = torch.nn.Sequential(linear[0], torch.nn.Tanh(), linear[1], torch.nn.Tanh(),
                                  linear[2])  # fmt: skip
    inputs_t = torch.tensor(inputs, dtype=torch.float32)
    target = torch.tensor(extents, dtype=torch.float32)
    optimiser = torch.optim.Adam(network.parameters(), lr=1e-2, weight_decay=weight_decay)
    for _ in range(steps):
        optimiser.zero_grad()
        loss = ((network(inputs_t).squeeze(1) - target) ** 2).mean()
        loss.backward()
        optimiser.step()
    return tuple(
        (layer.weight.detach().numpy().astype(np.float64),
         layer.bias.detach().numpy().astype(np.float64))
        for layer in linear
    )  # fmt: skip


def fit_length_model(
    features: np.ndarray,
    extents_px: np.ndarray,
    hidden: int = 32,
    steps: int = 1000,
    weight_decay: float = 1e-3,
    seed: int = 0,
    members: int = 5,
) -> LengthModel:
    """Fit the length model: ``members`` two-hidden-layer tanh perceptrons, each by least
    squares with full-batch Adam from its own initial weights, whose outputs are averaged (a
    seed ensemble: one perceptron's estimates depend on its initial weights as much as the
    features allow, and the mean of several varies less).

    Parameters
    ----------
    features : np.ndarray
        (N, k) feature values of N training frames (``BlurFeatures.values``).
    extents_px : np.ndarray
        (N,) recorded blur extents, px at the analysis scale (0 for sharp frames).
    hidden : int
        Units per hidden layer.
    steps : int
        Adam steps (learning rate 0.01) on the whole set.
    weight_decay : float
        L2 penalty on the weights (Adam's ``weight_decay``).
    seed : int
        Seed of the first member's initial weights (member m uses ``seed + m``).
    members : int
        Number of perceptrons averaged.

    Returns
    -------
    LengthModel
        The fitted model.
    """
    features = np.asarray(features, np.float64)
    extents = np.asarray(extents_px, np.float64)
    if features.ndim != 2 or len(features) != len(extents) or len(extents) < 2:
        raise ValueError("features must be (N, k) and extents (N,), N >= 2")
    if not (np.isfinite(features).all() and np.isfinite(extents).all()):
        raise ValueError("features and extents must be finite")
    if members < 1:
        raise ValueError(f"members must be >= 1, got {members}")
    mean, spread = features.mean(axis=0), features.std(axis=0) + 1e-9
    inputs = (features - mean) / spread
    fitted = tuple(_fit_perceptron(inputs, extents, hidden, steps, weight_decay, seed + member)
                   for member in range(members))  # fmt: skip
    return LengthModel(mean, spread, fitted)


def length_from_features(features: BlurFeatures, model: LengthModel | None = None) -> float:
    """Coarse blur length (px of the image the features came from, >= 0) by the length model
    (default: the shipped one)."""
    model = model or default_length_model()
    return max(float(model.predict(features.values)[0]), 0.0) * features.scale


#: Estimated length (px) above which :func:`detect_blur` calls an image blurred, and at or below
#: which the estimator reports it sharp. Chosen by :func:`calibrate_blur_threshold` on the
#: stand-in's training split (frames with >= BLURRED_FROM_PX of blur against sharp renders and
#: frames under SHARP_BELOW_PX, each of the two sharp groups counted equally; notebook 01
#: recomputes it).
BLUR_THRESHOLD = 2.19


def blur_score(image: np.ndarray) -> float:
    """Blur score of an image: its coarse blind blur length in px (:func:`blur_features` and the
    length model, without the sinc refinement). Grows with blur; about 0 for sharp frames.
    Images with a side under MIN_ANALYSIS_SIDE px are refused (ValueError)."""
    return length_from_features(blur_features(image))


def detect_blur(image: np.ndarray, threshold: float = BLUR_THRESHOLD) -> tuple[bool, float]:
    """Whether ``image`` is motion-blurred (its :func:`blur_score`, the estimated blur length in
    px, exceeds ``threshold``), and the score."""
    score = blur_score(image)
    return score > threshold, score


def estimate_motion_blur(
    image: np.ndarray,
    window: int = 256,
    features: BlurFeatures | None = None,
    agreement: tuple[float, float] = SINC_AGREEMENT,
) -> BlurEstimate:
    """Blind estimate of the length and angle of motion blur, from 1 px to tens of px.

    Coarse, for any blur: :func:`blur_features` gives the direction; the length model (a small
    perceptron on the features, fitted on the stand-in's training split) gives the extent.
    Fine, for long linear blur (coarse length >= SINC_MIN_PX): the sinc zeros of the log
    spectrum of a copy area-averaged to a short side of at most ``window`` px, whitened by its
    radial mean, searched by Radon projection (3° grid within 12° of the coarse direction,
    refined to 0.1°) and fitted by log sinc^2(L r / N) (L on a 0.5 px grid, refined to
    0.02 px); kept when it agrees with the coarse estimate (SINC_AGREEMENT: 0.67 to 2 times its
    length by default; direction within 20°), which rejects the zeros of content or noise.

    Parameters
    ----------
    image : np.ndarray
        (H, W) or (H, W, 3) image, uint8 or float in [0, 1]; short side >= 16 px.
    window : int
        Tile size (px) of the spectrum used for the fine estimate.
    features : BlurFeatures, optional
        ``blur_features(image)`` when the caller has them already (blind deblurring).
    agreement : tuple of float
        (low, high): the refined length is kept only within these factors of the coarse one.

    Returns
    -------
    BlurEstimate
        Length (px of the image given), angle (degrees, module conventions) and ``fit`` (the sinc
        fit's correlation when the fine estimate is kept, else 0).

    References
    ----------
    Yitzhaky and Kopeika, CVGIP 1997 (direction from the directional loss of high frequencies);
    Rom, "On the cepstrum of two-dimensional functions", IEEE Trans. Inf. Theory 1975, and
    Oliveira, Figueiredo and Bioucas-Dias, "Blind estimation of motion blur parameters for image
    deconvolution", IbPRIA 2007 (length and angle from the zeros of the sinc in the spectrum);
    the paper's Section III.A.1 (estimate θ and L, then eq. 4).
    """
    features = features or blur_features(image)
    length, angle = length_from_features(features), features.angle_deg
    if length >= SINC_MIN_PX and min(np.shape(image)[:2]) >= 64:
        gray = to_gray(image)
        factor = max(1.0, min(gray.shape) / window)  # one tile is enough: average down to it
        if factor > 1.0:
            size = (round(gray.shape[1] / factor), round(gray.shape[0] / factor))
            gray = cv2.resize(gray, size, interpolation=cv2.INTER_AREA)
        direction, fine, fit = _analyse(gray, window, around_deg=-angle % 180.0)
        fine *= factor
        fine_angle = float(np.degrees(np.arctan2(-np.sin(direction), np.cos(direction))) % 180.0)
        turn = abs(fine_angle - angle) % 180.0
        low, high = agreement
        if low * length <= fine <= high * length and min(turn, 180.0 - turn) <= 20.0:
            return BlurEstimate(length_px=fine, angle_deg=fine_angle, fit=fit)
    return BlurEstimate(length_px=length, angle_deg=angle, fit=0.0)
