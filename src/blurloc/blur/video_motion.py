"""Blur kernels from a video's own motion: the path of the image during each frame's exposure.

A frame of a video is blurred by the motion of the image during its exposure (eq. 1), and the
same motion moves the image from one frame to the next. Measured between consecutive frames
(phase correlation refined by ECC), the motion gives each frame's path: a curve through the
image positions of the frames before, at and after it, of which the exposure covers a share
around the frame's own position. That share (exposure time over frame interval: about 1 for
frames averaged the GoPro way, whose N sub-frames spread over N steps of the motion; 0.5 for a
180° shutter) is a setting of the camera; where it is not known it can be read from the frames'
blind blur estimates where their sinc zeros are trusted (:func:`calibrate_exposure_share`).

Conventions as in :mod:`blurloc.blur`: images uint8 or float in [0, 1]; displacements in px of
the frames given, x right and y down.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import cv2
import numpy as np

from .estimation import estimate_motion_blur
from .kernels import trajectory_kernel
from .spectrum import to_gray

#: Points per exposure path (:func:`exposure_paths`).
PATH_POINTS = 9
#: Exposure share assumed unless given: a frame blurred over its whole interval, as frames
#: averaged the GoPro way are (chosen among the calibrated share, 0.9, 1.0 and 1.2 on GoPro-style
#: videos of photographs that the test videos do not show: ``benchmarks/video_motion_deblur.py``).
DEFAULT_EXPOSURE_SHARE = 1.0
#: Frames whose image moves less than this (px per frame) do not calibrate the exposure share.
CALIBRATION_MIN_MOTION_PX = 1.0
#: Refinement of the displacement between frames by ECC (:func:`frame_shifts`): at most this
#: many iterations,
ECC_ITERATIONS = 30
#: stopping once an iteration moves the displacement by less than this (px),
ECC_STOP_PX = 1e-3
#: on frames smoothed by a Gaussian filter this many px wide (OpenCV's default).
ECC_SMOOTHING_PX = 5


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
    phase correlation's displacement is kept. One global translation per frame pair: right for
    a camera that turns, an approximation where parallax or a turn about the optical axis moves
    parts of the image differently.

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
    gray = (to_gray(frame).astype(np.float32) for frame in frames)  # two held at a time
    first = next(gray)
    window = cv2.createHanningWindow(first.shape[::-1], cv2.CV_32F)
    stop = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, ECC_ITERATIONS, ECC_STOP_PX)
    shifts = []
    for previous, current in itertools.pairwise(itertools.chain([first], gray)):
        start = cv2.phaseCorrelate(previous.copy(), current.copy(), window)[0]  # windows in place
        warp = np.float32([[1, 0, start[0]], [0, 1, start[1]]])
        try:
            warp = cv2.findTransformECC(previous, current, warp, cv2.MOTION_TRANSLATION, stop,
                                        None, ECC_SMOOTHING_PX)[1]  # fmt: skip
        except cv2.error:  # no convergence (e.g. a frame without structure): keep the start
            pass
        shifts.append(warp[:, 2].astype(np.float64))
    return np.array(shifts)


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


def calibrate_exposure_share(frames: np.ndarray, shifts: np.ndarray) -> float | None:
    r"""The exposure share that the frames' blind blur estimates imply, where they are trusted.

    .. math::

        \hat{s} = \operatorname{median}_t \; \frac{\hat{L}_t}{\lVert (\Delta_{t-1} +
        \Delta_t) / 2 \rVert}

    over the frames whose length was refined from their sinc zeros
    (:func:`~blurloc.blur.estimate_motion_blur`, ``fit > 0``) and whose image moves at least
    CALIBRATION_MIN_MOTION_PX per frame: a straight blur of length L during an exposure share s
    of a motion of v px per frame has L = s v.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W[, 3]) frames.
    shifts : numpy.ndarray
        (T - 1, 2) displacements between them (:func:`frame_shifts`).

    Returns
    -------
    float or None
        The share, or None when no frame qualifies.
    """
    shifts = np.asarray(shifts, float)
    padded = np.vstack([shifts[:1], shifts, shifts[-1:]])
    speed = np.linalg.norm((padded[:-1] + padded[1:]) / 2, axis=1)
    ratios = []
    for frame, motion in zip(frames, speed, strict=True):
        if motion < CALIBRATION_MIN_MOTION_PX:
            continue
        estimate = estimate_motion_blur(frame)
        if estimate.fit > 0:
            ratios.append(estimate.length_px / motion)
    return float(np.median(ratios)) if ratios else None


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
        on the frames (:func:`calibrate_exposure_share`, DEFAULT_EXPOSURE_SHARE where no frame
        qualifies).

    Returns
    -------
    VideoMotion
        The kernels (:func:`~blurloc.blur.trajectory_kernel`), their path lengths and the share.
    """
    shifts = frame_shifts(frames)
    if exposure_share is None:
        exposure_share = calibrate_exposure_share(frames, shifts) or DEFAULT_EXPOSURE_SHARE
    paths = exposure_paths(shifts, exposure_share)
    return VideoMotion(kernels=[trajectory_kernel(path, origin=np.zeros(2)) for path in paths],
                       lengths_px=np.array([path_length(path) for path in paths]),
                       exposure_share=float(exposure_share))  # fmt: skip
