"""Video deblurring by Wiener deconvolution with each frame's kernel from the video's motion.

The blind estimate of one frame (:func:`blurloc.deconv.deblur_blind`) reads a straight line off
the frame's spectrum; a video also shows where the image went between frames, and so the path
it took during each exposure (:mod:`blurloc.blur.video_motion`). Each frame is deconvolved with
that path's kernel by Wiener's filter with the gradient regulariser
(:func:`blurloc.deconv.wiener_deconvolve`); a frame whose path is under MIN_PATH_PX, or whose
kernel is larger than the frame, is passed through.
"""

from __future__ import annotations

import numpy as np

from .blur.video_motion import DEFAULT_EXPOSURE_SHARE, video_motion_kernels
from .deconv import blind_nsr, wiener_deconvolve
from .images import as_float_image, like_input

#: Smallest weight of the gradient regulariser, for frames without noise (chosen on GoPro-style
#: videos of the photographs that the test videos do not show:
#: ``benchmarks/video_motion_deblur.py``).
MIN_WEIGHT = 0.1
#: Frames whose image moves less than this during the exposure (px) are passed through.
MIN_PATH_PX = 1.0


def deblur_video_motion(
    frames: np.ndarray,
    exposure_share: float | None = DEFAULT_EXPOSURE_SHARE,
    min_weight: float = MIN_WEIGHT,
) -> np.ndarray:
    r"""Deblur a video frame by frame with kernels from its own motion.

    .. math::

        \tilde{x}_t = F^{-1}\left\{ \frac{\overline{F\{c_t\}}}{|F\{c_t\}|^2
        + \lambda_t |D(f)|^2} \, F\{b_t\} \right\}

    with :math:`c_t` the kernel of frame t's exposure path
    (:func:`~blurloc.blur.video_motion.video_motion_kernels`) and :math:`\lambda_t` = the larger
    of blind deblurring's weight (:func:`~blurloc.deconv.blind_nsr`: GRADIENT_WEIGHT_PER_NOISE
    σ_t) and ``min_weight``.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W, 3) uint8 consecutive frames, T >= 2.
    exposure_share : float or None
        Exposure time over frame interval, the camera's setting (default
        DEFAULT_EXPOSURE_SHARE, as for frames averaged the GoPro way); None calibrates it from
        the frames' blind estimates (:func:`~blurloc.blur.video_motion.calibrate_exposure_share`).
    min_weight : float
        :math:`\lambda_{\min}`, > 0.

    Returns
    -------
    numpy.ndarray
        (T, H, W, 3) uint8 restored frames.

    Raises
    ------
    ValueError
        If ``frames`` is not a (T, H, W, 3) uint8 video of at least two frames, or
        ``exposure_share`` or ``min_weight`` is not positive.
    """
    frames = np.asarray(frames)
    if frames.ndim != 4 or frames.shape[-1] != 3 or frames.dtype != np.uint8 or len(frames) < 2:
        raise ValueError(f"frames must be a (T, H, W, 3) uint8 video with T >= 2, got "
                         f"{frames.shape} {frames.dtype}")  # fmt: skip
    if not min_weight > 0:
        raise ValueError(f"min_weight must be > 0, got {min_weight}")
    motion = video_motion_kernels(frames, exposure_share)
    return deblur_by_kernels(frames, motion.kernels, motion.lengths_px, min_weight)


def deblur_by_kernels(
    frames: np.ndarray,
    kernels: list[np.ndarray],
    lengths_px: np.ndarray,
    min_weight: float = MIN_WEIGHT,
) -> np.ndarray:
    r"""Deconvolve each frame by its own kernel, as :func:`deblur_video_motion` does.

    The restoration step of :func:`deblur_video_motion` with the kernels given: with the
    kernels of the true exposure paths it bounds what that method can gain once its motion is
    measured exactly (``benchmarks/motion_wiener_bounds.py``). A frame whose path is under
    MIN_PATH_PX, or whose kernel is larger than the frame, is passed through.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W, 3) uint8 frames.
    kernels : list of numpy.ndarray
        T kernels, each centred on its frame's sharp instant (summing to 1).
    lengths_px : numpy.ndarray
        (T,) lengths of the paths the kernels were made from, px.
    min_weight : float
        :math:`\lambda_{\min}`, > 0.

    Returns
    -------
    numpy.ndarray
        (T, H, W, 3) uint8 restored frames.

    Raises
    ------
    ValueError
        If the counts of frames, kernels and lengths differ, or ``min_weight`` is not positive.
    """
    if not len(frames) == len(kernels) == len(lengths_px):
        raise ValueError(f"one kernel and one length per frame: {len(frames)} frames, "
                         f"{len(kernels)} kernels, {len(lengths_px)} lengths")  # fmt: skip
    if not min_weight > 0:
        raise ValueError(f"min_weight must be > 0, got {min_weight}")
    restored = np.array(frames, copy=True)
    for index, (frame, kernel, length) in enumerate(zip(frames, kernels, lengths_px, strict=True)):
        if length < MIN_PATH_PX or any(kernel.shape[axis] > frame.shape[axis] for axis in (0, 1)):
            continue  # no blur to undo, or a path that leaves the frame
        weight = max(blind_nsr(frame, "gradient"), min_weight)  # the blind rule, with a floor
        sharp = wiener_deconvolve(as_float_image(frame), kernel, nsr=weight, regulariser="gradient")
        restored[index] = like_input(sharp, frame)
    return restored
