"""Blur kernels from a video's own motion: the path of the image during each frame's exposure.

A frame of a video is blurred by the motion of the image during its exposure (eq. 1), and the
same motion moves the image from one frame to the next. Measured between consecutive frames
(phase correlation refined by ECC), the motion gives each frame's path: a curve through the
image positions of the frames before, at and after it, of which the exposure covers a share
around the frame's own position. Blurred frames align at their blurs' centroids, which a camera
that speeds up or slows down puts off mid-exposure: the measured positions are moved there
first (:func:`mid_exposure_shifts`). That share (exposure time over frame interval: about 1 for
frames averaged the GoPro way, whose N sub-frames spread over N steps of the motion; 0.5 for a
180° shutter) is a setting of the camera; where it is not known it can be read from the frames
themselves where their kernels differ: under the true share, each frame blurred by its
neighbour's kernel matches the neighbour blurred by its own (:func:`calibrate_exposure_share`).

Conventions as in :mod:`blurloc.blur`: images uint8 or float in [0, 1]; displacements in px of
the frames given, x right and y down.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import cv2
import numpy as np
from scipy.linalg import solve_banded
from scipy.ndimage import fourier_shift

from ..images import as_float_image, srgb_to_linear
from .kernels import kernel_to_otf, trajectory_kernel
from .spectrum import to_gray

#: Points per exposure path (:func:`exposure_paths`).
PATH_POINTS = 9
#: Exposure share assumed unless given: a frame blurred over its whole interval, as frames
#: averaged the GoPro way are (chosen among the calibrated share, 0.9, 1.0 and 1.2 on GoPro-style
#: videos of photographs that the test videos do not show: ``benchmarks/video_motion_deblur.py``).
DEFAULT_EXPOSURE_SHARE = 1.0
#: The measured shifts are moved from the blurs' centroids to mid-exposure
#: (:func:`mid_exposure_shifts`) where that amplifies their noise by at most this much: by
#: 1 / (1 - s^2 / 6) at the motion's fastest alternation, so for exposure shares s up to
#: MAX_CORRECTED_SHARE = sqrt(6 (1 - 1 / MAX_CORRECTION_GAIN)), 2.32 (the system turns singular
#: at sqrt(6) = 2.45).
MAX_CORRECTION_GAIN = 10.0
MAX_CORRECTED_SHARE = float(np.sqrt(6 * (1 - 1 / MAX_CORRECTION_GAIN)))
#: Frame pairs whose image moves less than this (px) do not calibrate the exposure share
#: (:func:`calibrate_exposure_share`),
CALIBRATION_MIN_MOTION_PX = 1.0
#: at most this many pairs count, those where the motion changes most (under a steady motion
#: both frames' blurs are alike and the comparison tells nothing; a long video is read as fast
#: as a short one),
CALIBRATION_MAX_PAIRS = 24
#: the shares it tries, then those within one step of the best every CALIBRATION_STEP,
CALIBRATION_SHARES = np.round(np.arange(0.2, 3.01, 0.2), 2)
CALIBRATION_STEP = 0.05
#: the weight of the comparison with one kernel on both sides that it subtracts (0 reads the
#: share long, 1 short),
CALIBRATION_ALIKE_WEIGHT = 0.75
#: and how far below zero its least difference must lie, as a share of the frames' gradient
#: energy, to tell the shares apart (a steady pan, whose frames share one kernel, stays at or
#: above 0). Both chosen on GoPro-style videos of training photographs exposed 5, 9 or 17 of
#: every 9 sub-frames (``benchmarks/choose_exposure_calibration.py``).
CALIBRATION_MIN_DEPTH = 0.0003
#: Refinement of the displacement between frames by ECC (:func:`frame_shifts`): at most this
#: many iterations,
ECC_ITERATIONS = 30
#: stopping once an iteration raises the correlation coefficient by less than this,
ECC_STOP_CORRELATION = 1e-3
#: on frames smoothed by a Gaussian filter this many px wide (OpenCV's default).
ECC_SMOOTHING_PX = 5
#: An alignment whose correlation coefficient stays under this explains under a quarter of the
#: frames' variance and counts as none (a frame without structure, or a lock onto a wrong peak).
ECC_MIN_CORRELATION = 0.5
#: A displacement that departs from a neighbouring pair's by more than this (px) and by more than
#: half the neighbour's length is measured again from that neighbour's (:func:`frame_shifts`).
#: A lock onto a wrong peak departs by far more (tens of px); a camera's motion can change by a
#: few px from one frame to the next (the photo videos' wobble changes a 13.5 px displacement by
#: up to about 4 px), where measuring again costs time only: the correlation coefficient decides.
NEIGHBOUR_RESTART_PX = 3.0
#: An affine warp whose displacement at the frame's centre departs from the translation by more
#: than this share of the frame's diagonal is not kept (:func:`frame_warps`): 3 px at 160x120,
#: 12 px at 640x480. Where the camera also turns about its optical axis, the translation, one
#: compromise over the whole frame, departs from the centre's displacement in proportion to the
#: frame's size (``benchmarks/video_motion_sizes.py`` reports the pairs whose warp is kept); an
#: affine fit gone astray departs by tens of px at any size.
AFFINE_ASTRAY_SHARE = 0.015
#: Points per side of the grid at which :func:`local_motion_kernels` gives each frame a kernel
#: of its own.
LOCAL_GRID = 3


def frame_shifts(frames: np.ndarray) -> np.ndarray:
    r"""The image's displacement from each frame to the next: phase correlation refined by ECC.

    Phase correlation gives the displacement to about a pixel,

    .. math::

        \Delta_t^{(0)} = \arg\max_{x} \, F^{-1}\left\{ \frac{\overline{F\{I_t\}} F\{I_{t+1}\}}
        {|\overline{F\{I_t\}} F\{I_{t+1}\}|} \right\}(x)

    on the gray frames under a Hann window, refined to sub-pixel precision
    (:func:`cv2.phaseCorrelate`); on blurred frames its peak moves by each frame's own blur,
    which weighs as much as the image at every frequency it keeps. From there the translation
    that maximises the enhanced correlation coefficient of the two frames,

    .. math::

        \Delta_t = \arg\max_{\Delta} \frac{\hat{I}_t \cdot \hat{I}_{t+1}(\cdot + \Delta)}
        {\lVert \hat{I}_t \rVert \, \lVert \hat{I}_{t+1}(\cdot + \Delta) \rVert}

    (:math:`\hat{I}`: zero-mean intensities; :func:`cv2.findTransformECC`), weighs the image's
    strong, low-frequency structure, which blur changes least. Where ECC does not converge the
    phase correlation's displacement is kept. Phase correlation can lock onto a wrong peak (a
    repeated structure, or a frame whose parts move differently), and ECC then climbs to a wrong
    optimum: a displacement that departs from a neighbouring pair's by more than
    NEIGHBOUR_RESTART_PX and more than half the neighbour's length is refined again from that
    neighbour's (a camera's motion changes little from one frame to the next), and the
    alignment with the larger correlation coefficient is kept, over two passes; a pair that ECC
    aligns from neither start (it does not converge, or its correlation coefficient stays under
    ECC_MIN_CORRELATION: a frame without structure) takes the neighbour's displacement where
    that one has one. One global translation per frame pair: right for a camera that turns, an
    approximation where parallax or a turn about the optical axis moves parts of the image
    differently (:func:`frame_warps`).

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W) or (T, H, W, 3) frames, T >= 2, uint8 or float in [0, 1].

    Returns
    -------
    numpy.ndarray
        (T - 1, 2) displacements of the image content from frame t to t + 1, px (x right, y
        down).

    Raises
    ------
    ValueError
        If fewer than two frames are given.

    References
    ----------
    Kuglin and Hines, "The phase correlation image alignment method", IEEE Conference on
    Cybernetics and Society, 1975. Evangelidis and Psarakis, "Parametric image alignment using
    enhanced correlation coefficient maximization", IEEE TPAMI 30(10), 2008.
    """
    if len(frames) < 2:
        raise ValueError(f"need at least 2 frames to measure motion, got {len(frames)}")
    gray = [to_gray(frame).astype(np.float32) for frame in frames]
    window = cv2.createHanningWindow(gray[0].shape[::-1], cv2.CV_32F)
    fits = []
    for previous, current in itertools.pairwise(gray):
        start = cv2.phaseCorrelate(previous.copy(), current.copy(), window)[0]  # windows in place
        fits.append(_refine(previous, current, _translation(start), cv2.MOTION_TRANSLATION))
    borrowed = set()  # pairs without an alignment of their own that took a neighbour's
    for _ in range(2):  # pairs that depart from a neighbour: refined again from its displacement
        changed = False
        for pair, neighbour in itertools.product(range(len(fits)), (-1, 1)):
            other = pair + neighbour
            if not 0 <= other < len(fits):
                continue
            shift, other_shift = fits[pair][1][:, 2], fits[other][1][:, 2]
            departure = np.linalg.norm(shift - other_shift)
            if departure > max(NEIGHBOUR_RESTART_PX, np.linalg.norm(other_shift) / 2):
                fit = _refine(gray[pair], gray[pair + 1], _translation(other_shift),
                              cv2.MOTION_TRANSLATION)  # fmt: skip
                if max(fit[0], fits[pair][0]) == -np.inf and (
                    fits[other][0] > -np.inf or other in borrowed
                ):
                    fits[pair], changed = (-np.inf, _translation(other_shift)), True
                    borrowed.add(pair)
                elif fit[0] > fits[pair][0]:
                    fits[pair], changed = fit, True
        if not changed:
            break
    return np.array([warp[:, 2] for _, warp in fits], np.float64)


def _translation(shift: np.ndarray | tuple[float, float]) -> np.ndarray:
    """The 2 x 3 float32 warp of a translation by ``shift`` (x, y)."""
    return np.float32([[1, 0, shift[0]], [0, 1, shift[1]]])


def _refine(
    previous: np.ndarray, current: np.ndarray, warp: np.ndarray, motion: int
) -> tuple[float, np.ndarray]:
    """ECC's (correlation coefficient, warp) from ``warp`` on two float32 gray frames; where it
    does not converge (e.g. a frame without structure), (-inf, the warp it started from); where
    the coefficient stays under ECC_MIN_CORRELATION, (-inf, ECC's warp): no alignment."""
    stop = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, ECC_ITERATIONS, ECC_STOP_CORRELATION)
    try:
        correlation, warp = cv2.findTransformECC(previous, current, warp.copy(), motion, stop,
                                                 None, ECC_SMOOTHING_PX)  # fmt: skip
    except cv2.error:
        return -np.inf, warp
    return (correlation if correlation >= ECC_MIN_CORRELATION else -np.inf), warp


def frame_warps(frames: np.ndarray, shifts: np.ndarray) -> np.ndarray:
    r"""The image's affine motion from each frame to the next, refined by ECC from ``shifts``.

    The content at :math:`x` in frame t lies at :math:`A_t x + b_t` in frame t + 1, with
    :math:`(A_t, b_t)` the affine warp that maximises the enhanced correlation coefficient of
    the two frames (:func:`cv2.findTransformECC`, ``MOTION_AFFINE``), started from the
    translation :math:`(I, \Delta_t)` of :func:`frame_shifts`. A turn about the optical axis, a
    move along it or a tilt moves the image differently in different parts of the frame, which
    one translation cannot describe. Where ECC does not align the frames (see
    :func:`frame_shifts`), or its warp moves the frame's centre further from where the
    translation does than AFFINE_ASTRAY_SHARE of the frame's diagonal (an affine fit gone astray
    on a frame with little structure), the translation is kept.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W) or (T, H, W, 3) frames, T >= 2, uint8 or float in [0, 1].
    shifts : numpy.ndarray
        (T - 1, 2) displacements between them (:func:`frame_shifts`).

    Returns
    -------
    numpy.ndarray
        (T - 1, 2, 3) warps :math:`[A_t \; b_t]`, px (x right, y down).

    Raises
    ------
    ValueError
        If ``shifts`` does not hold one displacement per pair of consecutive frames.

    References
    ----------
    Evangelidis and Psarakis, "Parametric image alignment using enhanced correlation
    coefficient maximization", IEEE TPAMI 30(10), 2008.
    """
    shifts = np.asarray(shifts, float)
    if shifts.shape != (len(frames) - 1, 2):
        raise ValueError(f"shifts must be ({len(frames) - 1}, 2) for {len(frames)} frames, got "
                         f"{shifts.shape}")  # fmt: skip
    gray = [to_gray(frame).astype(np.float32) for frame in frames]
    centre = np.array([gray[0].shape[1], gray[0].shape[0]], float) / 2
    astray_px = AFFINE_ASTRAY_SHARE * 2 * np.linalg.norm(centre)
    warps = np.empty((len(shifts), 2, 3))
    for pair, ((previous, current), shift) in enumerate(
        zip(itertools.pairwise(gray), shifts, strict=True)
    ):
        correlation, warp = _refine(previous, current, _translation(shift), cv2.MOTION_AFFINE)
        moved = warp[:, :2] @ centre + warp[:, 2] - centre
        astray = np.linalg.norm(moved - shift) > astray_px
        warps[pair] = _translation(shift) if astray or correlation == -np.inf else warp
    return warps


def grid_points(height: int, width: int, grid: int) -> np.ndarray:
    r"""The centres of a ``grid`` x ``grid`` partition of a frame, row by row.

    Parameters
    ----------
    height, width : int
        Frame size, px.
    grid : int
        Cells per side, >= 1.

    Returns
    -------
    numpy.ndarray
        (grid * grid, 2) points (x, y), px, pixel i covering [i, i + 1) (the warps of
        :func:`frame_warps` put pixel centres at integers: read there, a point's displacement
        is off by :math:`(A - I)\,0.5` px, a few hundredths of a pixel).
    """
    xs = (np.arange(grid) + 0.5) * width / grid
    ys = (np.arange(grid) + 0.5) * height / grid
    x, y = np.meshgrid(xs, ys)
    return np.column_stack([x.ravel(), y.ravel()])


def exposure_paths(
    shifts: np.ndarray, exposure_share: float, points: int = PATH_POINTS
) -> list[np.ndarray]:
    r"""Each frame's image path during its exposure, from the displacements between frames.

    With :math:`p_t` the image position at frame t (the sum of the displacements before it), the
    path of frame t is the parabola through :math:`p_{t-1}, p_t, p_{t+1}` at times -1, 0, 1
    (frame intervals), over the exposure :math:`|u| \le s / 2`:

    .. math::

        p(u) = p_t + u \, \frac{p_{t+1} - p_{t-1}}{2} + u^2 \, \frac{p_{t+1} - 2 p_t + p_{t-1}}{2}

    relative to :math:`p_t`, so that the kernel maps the frame at mid-exposure to the blurred
    one without a shift. The first and last frames continue their one neighbour's motion.

    Parameters
    ----------
    shifts : numpy.ndarray
        (T - 1, 2) displacements between consecutive frames (:func:`frame_shifts`).
    exposure_share : float
        s: exposure time over frame interval, > 0.
    points : int
        Points per path (equal time steps), >= 2.

    Returns
    -------
    list of numpy.ndarray
        T paths, each (points, 2), px relative to the frame's mid-exposure position.

    Raises
    ------
    ValueError
        If ``shifts`` is not (T - 1, 2) with T >= 2, ``exposure_share`` is not positive or
        ``points`` < 2.
    """
    shifts = np.asarray(shifts, float)
    if shifts.ndim != 2 or shifts.shape[1] != 2 or len(shifts) < 1:
        raise ValueError(f"shifts must be (T - 1, 2) with T >= 2, got {shifts.shape}")
    if not exposure_share > 0 or points < 2:
        raise ValueError(f"exposure_share must be > 0 and points >= 2, got {exposure_share}, "
                         f"{points}")  # fmt: skip
    positions = np.vstack([np.zeros((1, 2)), np.cumsum(shifts, axis=0)])
    before = np.vstack([2 * positions[0] - positions[1], positions[:-1]])
    after = np.vstack([positions[1:], 2 * positions[-1] - positions[-2]])
    u = np.linspace(-exposure_share / 2, exposure_share / 2, points)[None, :, None]
    velocity = ((after - before) / 2)[:, None, :]
    curvature = ((after - 2 * positions + before) / 2)[:, None, :]
    return list(u * velocity + u**2 * curvature)


def mid_exposure_shifts(shifts: np.ndarray, exposure_share: float) -> np.ndarray:
    r"""Displacements between the frames' mid-exposure positions, from those between blurred frames.

    Two blurred frames align where their blurs' centroids coincide: what :func:`frame_shifts`
    measures is the displacement between the exposure paths' centroids :math:`c_t`, and the
    paths of :func:`exposure_paths` pass through the mid-exposure positions :math:`m_t`, which
    the truth of a video averaged the GoPro way shows (its middle frame). Averaged over the
    exposure :math:`|u| \le s / 2`, that parabola is

    .. math::

        c_t = m_t + \frac{s^2}{24} \left( m_{t+1} - 2 m_t + m_{t-1} \right)

    (:math:`\langle u^2 \rangle = s^2 / 12`), so a camera that speeds up or slows down puts the
    centroid off the middle by a few hundredths of its change of speed. The tridiagonal system is
    solved for :math:`m`; the first and last frames continue their one neighbour's motion (no
    curvature: :math:`m = c` there). The solve amplifies the measurement's noise by up to
    :math:`1 / (1 - s^2 / 6)` (the motion's fastest alternation; singular at :math:`s = \sqrt{6}`):
    shares beyond MAX_CORRECTED_SHARE, where that exceeds MAX_CORRECTION_GAIN, keep the
    centroids' shifts. A real camera's exposure fits in its frame interval (:math:`s \le 1`:
    at most 1.2x).

    Parameters
    ----------
    shifts : numpy.ndarray
        (T - 1, 2) displacements between consecutive blurred frames (:func:`frame_shifts`).
    exposure_share : float
        s: exposure time over frame interval, > 0.

    Returns
    -------
    numpy.ndarray
        (T - 1, 2) displacements between consecutive mid-exposure positions, px.

    Raises
    ------
    ValueError
        If ``shifts`` is not (T - 1, 2) with T >= 2 or ``exposure_share`` is not positive.
    """
    shifts = np.asarray(shifts, float)
    if shifts.ndim != 2 or shifts.shape[1] != 2 or len(shifts) < 1:
        raise ValueError(f"shifts must be (T - 1, 2) with T >= 2, got {shifts.shape}")
    if not exposure_share > 0:
        raise ValueError(f"exposure_share must be > 0, got {exposure_share}")
    if exposure_share > MAX_CORRECTED_SHARE:
        return shifts
    centroids = np.vstack([np.zeros((1, 2)), np.cumsum(shifts, axis=0)])
    weight = exposure_share**2 / 24
    count = len(centroids)
    banded = np.zeros((3, count))  # rows: above, on and below the diagonal
    banded[1] = 1.0
    banded[1, 1:-1] -= 2 * weight
    banded[0, 2:] = weight
    banded[2, :-2] = weight
    return np.diff(solve_banded((1, 1), banded, centroids), axis=0)


def path_length(path: np.ndarray) -> float:
    """Length of a path (px): the sum of its segments.

    Parameters
    ----------
    path : numpy.ndarray
        (N, 2) positions.

    Returns
    -------
    float
        Length in px.
    """
    return float(np.linalg.norm(np.diff(np.asarray(path, float), axis=0), axis=1).sum())


def calibrate_exposure_share(
    frames: np.ndarray, shifts: np.ndarray, min_depth: float = CALIBRATION_MIN_DEPTH
) -> float | None:
    """The exposure share read from the video (:func:`fit_exposure_share`), where it is told
    apart: its depth above ``min_depth``.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W[, 3]) frames, uint8 or float in [0, 1].
    shifts : numpy.ndarray
        (T - 1, 2) displacements between them (:func:`frame_shifts`).
    min_depth : float
        The least depth at which the share is returned (default CALIBRATION_MIN_DEPTH).

    Returns
    -------
    float or None
        The share, or None when no pair moves enough or the depth is not above ``min_depth``
        (a steady pan, whose frames share one kernel).

    Raises
    ------
    ValueError
        If ``shifts`` does not hold one displacement per pair of consecutive frames.
    """
    fit = fit_exposure_share(frames, shifts)
    return fit.share if fit is not None and fit.depth > min_depth else None


@dataclass(frozen=True)
class ExposureFit:
    """The exposure share that best explains a video's frames by one another (``share``) and
    how clearly (``depth``: :func:`fit_exposure_share`)."""

    share: float
    depth: float


def fit_exposure_share(
    frames: np.ndarray, shifts: np.ndarray, alike_weight: float = CALIBRATION_ALIKE_WEIGHT
) -> ExposureFit | None:
    r"""The exposure share under which the video's blurred frames explain one another best, and
    how clearly.

    Blur commutes: with :math:`b_t = c_t * x_t` and the next frame's sharp image the content
    moved on, the blurred frames satisfy :math:`c_{t+1} * b_t = c_t * b_{t+1}` once both are
    moved to one place, whatever the image, for the kernels of the true share s (Rav-Acha and
    Peleg). The share minimises

    .. math::

        D(s) = \frac{1}{|P|} \sum_{t \in P} \left\langle
             \left( c_{t+1}(s) * b_t^{+} - c_t(s) * b_{t+1}^{-} \right)^2
             - w \left( \bar{c}_t(s) * (b_t^{+} - b_{t+1}^{-}) \right)^2 \right\rangle

    with :math:`c_t(s)` the kernels of the paths of :func:`exposure_paths` through the
    displacements of :func:`mid_exposure_shifts`, each centred on its centroid;
    :math:`b_t^{+}` and :math:`b_{t+1}^{-}` the frames in linear light (gamma 2.2: blur adds
    light) moved half-way towards each other by the measured displacement (blurred frames align
    at their blurs' centroids), exactly, by the shift theorem; :math:`\langle \cdot \rangle`
    the mean over the pixels away from the frame's border (by the kernels' size and the move);
    P the pairs, :math:`\bar{c}_t = (c_t + c_{t+1}) / 2` and w = ``alike_weight``.
    The second term, the same comparison with one kernel on both sides, holds what a longer
    kernel lowers whatever the share (noise, parallax, interpolation); the difference keeps
    what only the two frames' different kernels tell. :math:`D` is evaluated at
    CALIBRATION_SHARES, then every CALIBRATION_STEP within one of their steps of the best.
    Pairs whose image moves less than CALIBRATION_MIN_MOTION_PX do not count; of the others, at
    most CALIBRATION_MAX_PAIRS count, those where the displacement changes most from the
    previous pair to the next (:math:`\lVert d_{t+1} - d_{t-1} \rVert`: where the two frames'
    kernels differ most). How clearly the share is told apart is its depth, :math:`-D / G` at
    the best share, with G the frames' gradient energy (the mean of
    :math:`\langle |\partial_x b_t|^2 + |\partial_y b_t|^2 \rangle` over the pairs): where
    the kernels are alike (a steady pan) D is not below 0 (for w <= 1).

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W[, 3]) frames, uint8 or float in [0, 1].
    shifts : numpy.ndarray
        (T - 1, 2) displacements between them (:func:`frame_shifts`).
    alike_weight : float
        w, >= 0 (default CALIBRATION_ALIKE_WEIGHT).

    Returns
    -------
    ExposureFit or None
        The best share and its depth, or None when no pair moves enough.

    Raises
    ------
    ValueError
        If ``shifts`` does not hold one displacement per pair of consecutive frames or
        ``alike_weight`` is negative.

    References
    ----------
    Rav-Acha and Peleg, "Two motion-blurred images are better than one", Pattern Recognition
    Letters 26(3), 2005.
    """
    shifts = np.asarray(shifts, float)
    if shifts.shape != (len(frames) - 1, 2):
        raise ValueError(f"shifts must be ({len(frames) - 1}, 2) for {len(frames)} frames, got "
                         f"{shifts.shape}")  # fmt: skip
    if not alike_weight >= 0:
        raise ValueError(f"alike_weight must be >= 0, got {alike_weight}")
    pairs = np.nonzero(np.linalg.norm(shifts, axis=1) >= CALIBRATION_MIN_MOTION_PX)[0]
    if len(pairs) == 0:
        return None
    if len(pairs) > CALIBRATION_MAX_PAIRS:  # where the motion changes most, in time order
        before, after = np.vstack([shifts[:1], shifts[:-1]]), np.vstack([shifts[1:], shifts[-1:]])
        change = np.linalg.norm(after - before, axis=1)[pairs]
        pairs = np.sort(pairs[np.argsort(-change, kind="stable")[:CALIBRATION_MAX_PAIRS]])
    linear = {frame: to_gray(srgb_to_linear(as_float_image(frames[frame]))).astype(np.float32)
              for frame in sorted(set(pairs) | set(pairs + 1))}  # fmt: skip
    height, width = linear[pairs[0]].shape
    # spectra of each pair's frames moved half-way towards each other by the shift, taken from
    # the moved frames themselves (real images), as the direct convolution saw them
    moved = {}
    for pair in pairs:
        half = shifts[pair][::-1] / 2  # (rows, columns)
        moved[pair] = [np.fft.rfft2(np.fft.irfft2(fourier_shift(np.fft.rfft2(linear[frame]),
                                                                sign * half, n=width),
                                                  s=(height, width)).astype(np.float64))
                       for frame, sign in ((pair, 1), (pair + 1, -1))]  # fmt: skip
    gradient_energy = np.mean([sum(np.mean(np.diff(linear[pair], axis=axis) ** 2)
                                   for axis in (0, 1)) for pair in pairs])  # fmt: skip

    def difference(share: float) -> float:  # D(s) per pixel and pair; inf where nothing is left
        paths = exposure_paths(mid_exposure_shifts(shifts, share), share)
        kernels = {frame: trajectory_kernel(paths[frame], origin=paths[frame].mean(axis=0))
                   for frame in sorted(set(pairs) | set(pairs + 1))}  # fmt: skip
        if 2 * max(max(kernel.shape) for kernel in kernels.values()) >= min(height, width):
            return np.inf  # paths as long as the frame: nothing left to compare
        spectra = {frame: (kernel_to_otf(kernel, (height, width), np.float64), kernel.sum())
                   for frame, kernel in kernels.items()}  # fmt: skip
        total = 0.0
        for pair in pairs:
            size = max(max(kernels[pair].shape), max(kernels[pair + 1].shape))
            margin = size + int(np.ceil(np.abs(shifts[pair]).max() / 2)) + 2
            if 2 * margin >= min(height, width):
                return np.inf  # the kernels and the move leave no pixel to compare
            (first, first_sum), (second, second_sum) = spectra[pair], spectra[pair + 1]
            earlier, later = moved[pair]
            inside = np.s_[margin:-margin, margin:-margin]
            # products of spectra: circular convolutions, equal to the blur of eq. 1 inside the
            # margin (wider than any kernel), where no pixel reads beyond the frame
            crossed = np.fft.irfft2(
                earlier * (second / second_sum) - later * (first / first_sum), s=(height, width)
            )
            alike = np.fft.irfft2(
                (earlier - later) * ((first + second) / (first_sum + second_sum)), s=(height, width)
            )
            total += np.mean(crossed[inside] ** 2) - alike_weight * np.mean(alike[inside] ** 2)
        return total / len(pairs)

    coarse = {share: difference(share) for share in CALIBRATION_SHARES}
    best = min(coarse, key=coarse.get)
    step = CALIBRATION_SHARES[1] - CALIBRATION_SHARES[0]
    fine = {
        share: difference(share)
        for share in np.round(best + np.arange(-step, step * 1.01, CALIBRATION_STEP), 3)
        if share > 0
    }
    share, least = min({**coarse, **fine}.items(), key=lambda item: item[1])
    return ExposureFit(share=float(share), depth=float(-least / gradient_energy))


@dataclass(frozen=True)
class VideoMotion:
    """Blur kernels of a video's frames from its motion (:func:`video_motion_kernels`):
    ``kernels`` (T kernels, centred on mid-exposure), ``lengths_px`` (T path lengths) and the
    ``exposure_share`` used."""

    kernels: list[np.ndarray]
    lengths_px: np.ndarray
    exposure_share: float


def video_motion_kernels(
    frames: np.ndarray, exposure_share: float | None = DEFAULT_EXPOSURE_SHARE
) -> VideoMotion:
    """Each frame's blur kernel from the video's motion (:func:`exposure_paths`).

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W[, 3]) consecutive frames, T >= 2.
    exposure_share : float or None
        Exposure time over frame interval (default DEFAULT_EXPOSURE_SHARE); None calibrates it
        on the frames (:func:`calibrate_exposure_share`, DEFAULT_EXPOSURE_SHARE where it
        returns none).

    Returns
    -------
    VideoMotion
        The kernels (:func:`~blurloc.blur.trajectory_kernel`), their path lengths and the share.
    """
    motion = local_motion_kernels(frames, exposure_share, grid=1)
    return VideoMotion(kernels=[point_kernels[0] for point_kernels in motion.kernels],
                       lengths_px=motion.lengths_px[:, 0],
                       exposure_share=motion.exposure_share)  # fmt: skip


@dataclass(frozen=True)
class LocalVideoMotion:
    """Blur kernels of a video's frames at points of a grid (:func:`local_motion_kernels`):
    ``points`` ((P, 2) x, y px, P = ``grid`` squared, the frame's centre when ``grid`` is 1),
    ``kernels`` (T lists of P kernels, centred on mid-exposure), ``lengths_px`` ((T, P) path
    lengths) and the ``exposure_share`` used."""

    grid: int
    points: np.ndarray
    kernels: list[list[np.ndarray]]
    lengths_px: np.ndarray
    exposure_share: float


def local_motion_kernels(
    frames: np.ndarray,
    exposure_share: float | None = DEFAULT_EXPOSURE_SHARE,
    grid: int = LOCAL_GRID,
) -> LocalVideoMotion:
    r"""Each frame's blur kernels at the points of a grid, from the video's affine motion.

    The displacement of the content at point :math:`x_j` from frame t to t + 1 is that of the
    affine warp (:func:`frame_warps`),

    .. math::

        \Delta_{t,j} = A_t x_j + b_t - x_j

    and the kernel of frame t at :math:`x_j` that of its exposure path through those
    displacements, moved from the blurs' centroids to mid-exposure (:func:`mid_exposure_shifts`,
    :func:`exposure_paths`). The step into frame t is read at :math:`x_j` too,
    where strictly it is that of the content which reaches :math:`x_j`: the two differ by about
    :math:`(A_{t-1} - I)\,\Delta_{t-1}`, a few tenths of a pixel for a camera turning 3° per
    frame while it pans 10 px. With ``grid=1`` the one point is the frame's centre
    and its displacements the translations of :func:`frame_shifts`: the kernels of
    :func:`video_motion_kernels`.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W[, 3]) consecutive frames, T >= 2.
    exposure_share : float or None
        Exposure time over frame interval (default DEFAULT_EXPOSURE_SHARE); None calibrates it
        on the frames (:func:`calibrate_exposure_share`, DEFAULT_EXPOSURE_SHARE where it
        returns none).
    grid : int
        Points per side of the grid (:func:`grid_points`), >= 1; 1 measures one translation.

    Returns
    -------
    LocalVideoMotion

    Raises
    ------
    ValueError
        If ``grid`` < 1 or fewer than two frames are given.
    """
    if grid < 1:
        raise ValueError(f"grid must be >= 1, got {grid}")
    shifts = frame_shifts(frames)
    if exposure_share is None:
        exposure_share = calibrate_exposure_share(frames, shifts) or DEFAULT_EXPOSURE_SHARE
    height, width = np.shape(frames)[1:3]
    points = grid_points(height, width, grid)
    displacements = shifts[:, None, :]  # (T - 1, 1, 2): one translation
    if grid > 1:
        warps = frame_warps(frames, shifts)
        displacements = (np.einsum("tij,pj->tpi", warps[:, :, :2], points)
                         + warps[:, None, :, 2] - points)  # fmt: skip
    paths = [exposure_paths(mid_exposure_shifts(displacements[:, point], exposure_share),
                            exposure_share) for point in range(displacements.shape[1])]  # fmt: skip
    return LocalVideoMotion(
        grid=grid,
        points=points,
        kernels=[[trajectory_kernel(point_paths[frame], origin=np.zeros(2))
                  for point_paths in paths] for frame in range(len(frames))],
        lengths_px=np.array([[path_length(point_paths[frame]) for point_paths in paths]
                             for frame in range(len(frames))]),
        exposure_share=float(exposure_share),
    )  # fmt: skip
