"""Video deblurring by Wiener deconvolution with each frame's kernel from the video's motion.

The blind estimate of one frame (:func:`blurloc.deconv.deblur_blind`) reads a straight line off
the frame's spectrum; a video also shows where the image went between frames, and so the path
it took during each exposure (:mod:`blurloc.blur.video_motion`). Each frame is deconvolved with
that path's kernel by Wiener's filter with the gradient regulariser, the image beyond the frame
solved for as unknown (:func:`blurloc.deconv.wiener_deconvolve`); where the image moves
differently in different parts of the frame (a turn about the optical axis, a move along it),
with the kernels of a grid of points, blended. A frame whose path is under MIN_PATH_PX, or whose
kernel is larger than the frame, is passed through.
"""

from __future__ import annotations

import numpy as np

from .blur.video_motion import DEFAULT_EXPOSURE_SHARE, LOCAL_GRID, grid_points, local_motion_kernels
from .deconv import BOUNDARY_ITERATIONS, blind_nsr, check_boundary, wiener_deconvolve
from .images import as_float_image, like_input

#: Smallest weight of the gradient regulariser, for frames without noise (chosen on GoPro-style
#: videos of the photographs that the test videos do not show:
#: ``benchmarks/video_motion_deblur.py``).
MIN_WEIGHT = 0.02
#: How the frame's boundary is treated (:func:`blurloc.deconv.wiener_deconvolve`): the image
#: beyond the frame unknown, so that the light a pan carries into the frame is explained
#: (compared with mirror boundaries by ``benchmarks/video_motion_deblur.py``).
BOUNDARY = "unknown"
#: Frames whose image moves less than this during the exposure (px) are passed through.
MIN_PATH_PX = 1.0


def deblur_video_motion(
    frames: np.ndarray,
    exposure_share: float | None = DEFAULT_EXPOSURE_SHARE,
    min_weight: float = MIN_WEIGHT,
    grid: int = LOCAL_GRID,
    boundary: str = BOUNDARY,
) -> np.ndarray:
    r"""Deblur a video frame by frame with kernels from its own motion.

    .. math::

        \tilde{x}_t = \sum_j w_j \, F^{-1}\left\{ \frac{\overline{F\{c_{t,j}\}}}
        {|F\{c_{t,j}\}|^2 + \lambda_t |D(f)|^2} \, F\{b_t\} \right\}

    with :math:`c_{t,j}` the kernel of frame t's exposure path at grid point j
    (:func:`~blurloc.blur.video_motion.local_motion_kernels`; with ``grid=1`` one point, the
    frame's centre), :math:`w_j` bilinear weights that are 1 at point j and fall
    to 0 at its neighbours (:func:`deblur_by_local_kernels`), and :math:`\lambda_t` = the larger
    of blind deblurring's weight (:func:`~blurloc.deconv.blind_nsr`: GRADIENT_WEIGHT_PER_NOISE
    σ_t) and ``min_weight``. The formula is the mirror boundary's; with ``boundary="unknown"``
    (the default) each term is the least-squares image of
    :func:`~blurloc.deconv.wiener_deconvolve` whose part beyond the frame is unknown.

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
    grid : int
        Points per side of the grid of kernels (>= 1; default LOCAL_GRID; 1: one translation per
        frame pair, one kernel per frame).
    boundary : str
        ``"unknown"`` or ``"mirror"`` (:func:`~blurloc.deconv.wiener_deconvolve`).

    Returns
    -------
    numpy.ndarray
        (T, H, W, 3) uint8 restored frames.

    Raises
    ------
    ValueError
        If ``frames`` is not a (T, H, W, 3) uint8 video of at least two frames,
        ``exposure_share`` or ``min_weight`` is not positive, ``grid`` < 1 or ``boundary`` is
        unknown.
    """
    frames = np.asarray(frames)
    if frames.ndim != 4 or frames.shape[-1] != 3 or frames.dtype != np.uint8 or len(frames) < 2:
        raise ValueError(f"frames must be a (T, H, W, 3) uint8 video with T >= 2, got "
                         f"{frames.shape} {frames.dtype}")  # fmt: skip
    _check_settings(min_weight, boundary)
    motion = local_motion_kernels(frames, exposure_share, grid)
    return deblur_by_local_kernels(frames, motion.kernels, motion.lengths_px, motion.grid,
                                   min_weight, boundary)  # fmt: skip


def deblur_by_kernels(
    frames: np.ndarray,
    kernels: list[np.ndarray],
    lengths_px: np.ndarray,
    min_weight: float = MIN_WEIGHT,
    boundary: str = BOUNDARY,
    iterations: int = BOUNDARY_ITERATIONS,
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
    boundary : str
        ``"unknown"`` or ``"mirror"`` (:func:`~blurloc.deconv.wiener_deconvolve`).
    iterations : int
        Conjugate-gradient steps of the unknown boundary's solve
        (:func:`~blurloc.deconv.wiener_deconvolve`).

    Returns
    -------
    numpy.ndarray
        (T, H, W, 3) uint8 restored frames.

    Raises
    ------
    ValueError
        If the counts of frames, kernels and lengths differ, ``min_weight`` is not positive,
        ``boundary`` is unknown or (once a frame is restored) ``iterations`` is negative.
    """
    return deblur_by_local_kernels(frames, [[kernel] for kernel in kernels],
                                   np.reshape(lengths_px, (-1, 1)), 1, min_weight, boundary,
                                   iterations)  # fmt: skip


def deblur_by_local_kernels(
    frames: np.ndarray,
    kernels: list[list[np.ndarray]],
    lengths_px: np.ndarray,
    grid: int,
    min_weight: float = MIN_WEIGHT,
    boundary: str = BOUNDARY,
    iterations: int = BOUNDARY_ITERATIONS,
) -> np.ndarray:
    r"""Deconvolve each frame by the kernels of a grid of points, blended.

    Frame t is deconvolved with each point's kernel :math:`c_{t,j}` over the whole frame (the
    step of :func:`deblur_by_kernels`), and the results are blended with bilinear weights
    :math:`w_j(x) = \max(0, 1 - |x - x_j| / g_x) \max(0, 1 - |y - y_j| / g_y)` (:math:`g`:
    the grid's spacing; constant beyond the outermost points), which sum to 1 at every pixel:
    the restoration follows a blur that changes smoothly across the frame. A point whose path
    is under MIN_PATH_PX, or whose kernel is larger than the frame, contributes the frame as it
    is; a frame where every point's does is passed through.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W, 3) uint8 frames.
    kernels : list of list of numpy.ndarray
        T lists of ``grid`` squared kernels, at :func:`~blurloc.blur.video_motion.grid_points`
        row by row, each centred on its frame's sharp instant (summing to 1).
    lengths_px : numpy.ndarray
        (T, grid squared) lengths of the paths the kernels were made from, px.
    grid : int
        Points per side, >= 1.
    min_weight : float
        :math:`\lambda_{\min}`, > 0.
    boundary : str
        ``"unknown"`` or ``"mirror"`` (:func:`~blurloc.deconv.wiener_deconvolve`).
    iterations : int
        Conjugate-gradient steps of the unknown boundary's solve
        (:func:`~blurloc.deconv.wiener_deconvolve`).

    Returns
    -------
    numpy.ndarray
        (T, H, W, 3) uint8 restored frames.

    Raises
    ------
    ValueError
        If the counts of frames, kernel lists and lengths differ, a frame's kernels or lengths
        are not ``grid`` squared, ``grid`` < 1, ``min_weight`` is not positive, ``boundary`` is
        unknown or (once a frame is restored) ``iterations`` is negative.
    """
    frames = np.asarray(frames)
    lengths_px = np.asarray(lengths_px, float)
    if (
        not len(frames) == len(kernels) == len(lengths_px)
        or grid < 1
        or any(len(frame_kernels) != grid * grid for frame_kernels in kernels)
        or lengths_px.shape[1:] != (grid * grid,)
    ):
        raise ValueError(f"one kernel and one length per frame and grid point: {len(frames)} "
                         f"frames, {len(kernels)} kernel lists, lengths {lengths_px.shape}, "
                         f"grid {grid}")  # fmt: skip
    _check_settings(min_weight, boundary)
    restored = np.array(frames, copy=True)
    weights = _blend_weights(frames.shape[1], frames.shape[2], grid)
    for index, frame in enumerate(frames):
        usable = [
            length >= MIN_PATH_PX
            and all(kernel.shape[axis] <= frame.shape[axis] for axis in (0, 1))
            for kernel, length in zip(kernels[index], lengths_px[index], strict=True)
        ]
        if not any(usable):
            continue  # no blur to undo, or paths that leave the frame
        weight = max(blind_nsr(frame, "gradient"), min_weight)  # the blind rule, with a floor
        image = as_float_image(frame)
        blend = 0.0
        for point, kernel in enumerate(kernels[index]):
            sharp = (wiener_deconvolve(image, kernel, weight, "gradient", boundary, iterations)
                     if usable[point] else image)  # fmt: skip
            blend = blend + weights[point][..., None] * sharp
        restored[index] = like_input(blend, frame)
    return restored


def _check_settings(min_weight: float, boundary: str) -> None:
    """Refuse a weight floor that is not positive or an unknown boundary, naming it."""
    if not min_weight > 0:
        raise ValueError(f"min_weight must be > 0, got {min_weight}")
    check_boundary(boundary)


def _blend_weights(height: int, width: int, grid: int) -> np.ndarray:
    """(grid squared, H, W) bilinear weights of the points of
    :func:`~blurloc.blur.video_motion.grid_points`, summing to 1 at every pixel."""
    points = grid_points(height, width, grid)
    along = []
    for coordinates, centres in ((np.arange(height) + 0.5, points[::grid, 1]),
                                 (np.arange(width) + 0.5, points[:grid, 0])):  # fmt: skip
        if grid == 1:
            along.append(np.ones((1, len(coordinates))))
            continue
        clipped = np.clip(coordinates, centres[0], centres[-1])
        spacing = centres[1] - centres[0]
        along.append(np.maximum(0.0, 1.0 - np.abs(clipped[None, :] - centres[:, None]) / spacing))
    rows, columns = along
    return np.einsum("iy,jx->ijyx", rows, columns).reshape(grid * grid, height, width)
