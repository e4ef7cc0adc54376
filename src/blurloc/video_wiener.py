"""Video deblurring by Wiener deconvolution with each frame's kernel from the video's motion.

The blind estimate of one frame (:func:`blurloc.deconv.deblur_blind`) reads a straight line off
the frame's spectrum; a video also shows where the image went between frames, and so the path
it took during each exposure (:mod:`blurloc.blur.video_motion`). Each frame is deconvolved with
that path's kernel by Wiener's filter with the gradient regulariser, its weight set by the
frame's noise, the image beyond the frame solved for as unknown
(:func:`blurloc.deconv.wiener_deconvolve`); where the image moves differently in different
parts of the frame (a turn about the optical axis, a move along it), with the kernels of a grid
of points, each restoring its own part of the frame, blended; a frame whose grid kernels agree
(a pan) is restored once, whole, with one of them. A frame whose path is under MIN_PATH_PX, or
whose kernel is larger than the frame, is passed through.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
from scipy.spatial.distance import pdist

from .blur import centred_on_one_grid, estimate_noise_sigma
from .blur.video_motion import DEFAULT_EXPOSURE_SHARE, LOCAL_GRID, grid_points, local_motion_kernels
from .deconv import BOUNDARY_ITERATIONS, check_boundary, wiener_deconvolve
from .images import as_float_image, like_input

#: Weight of the gradient regulariser per unit of the frame's estimated noise σ (Immerkær's;
#: blind deblurring's is GRADIENT_WEIGHT_PER_NOISE, for kernels read off one frame), and its
#: floor, for frames without noise: both chosen together on GoPro-style videos of the
#: photographs that the test videos do not show, with and without noise
#: (``benchmarks/video_motion_deblur.py``).
WEIGHT_PER_NOISE = 10.0
MIN_WEIGHT = 0.03
#: How the frame's boundary is treated (:func:`blurloc.deconv.wiener_deconvolve`): the image
#: beyond the frame unknown, so that the light a pan carries into the frame is explained
#: (compared with mirror boundaries by ``benchmarks/video_motion_deblur.py``).
BOUNDARY = "unknown"
#: Frames whose image moves less than this during the exposure (px) are passed through.
MIN_PATH_PX = 1.0
#: With unknown boundaries, each grid point's kernel restores only the part of the frame its
#: blend weight covers, widened by the kernel's size and this margin (px) on every side.
TILE_MARGIN_PX = 8
#: A frame whose grid kernels all lie within this L1 distance of one another
#: (:func:`kernel_disagreement`: 0 for equal kernels, 2 for kernels that share no pixel) is
#: deconvolved once, whole, with the kernel of the grid's middle point: a pan blurs the frame
#: alike everywhere, and one restoration takes a fraction of the grid's tiles' time. Chosen on
#: GoPro-style videos of the photographs that the test videos do not show, panning, turning and
#: moving forward (``benchmarks/choose_kernel_agreement.py``).
AGREEMENT_L1 = 0.5
#: Frames restored at once, each on its own thread (the transforms and array arithmetic release
#: Python's lock): the two cores the package is measured on. The result does not depend on it.
THREADS = 2


def deblur_video_motion(
    frames: np.ndarray,
    exposure_share: float | None = DEFAULT_EXPOSURE_SHARE,
    min_weight: float = MIN_WEIGHT,
    grid: int = LOCAL_GRID,
    boundary: str = BOUNDARY,
    weight_per_noise: float = WEIGHT_PER_NOISE,
    agreement_l1: float | None = AGREEMENT_L1,
    threads: int = THREADS,
) -> np.ndarray:
    r"""Deblur a video frame by frame with kernels from its own motion.

    .. math::

        \tilde{x}_t = \sum_j w_j \, F^{-1}\left\{ \frac{\overline{F\{c_{t,j}\}}}
        {|F\{c_{t,j}\}|^2 + \lambda_t |D(f)|^2} \, F\{b_t\} \right\}

    with :math:`c_{t,j}` the kernel of frame t's exposure path at grid point j
    (:func:`~blurloc.blur.video_motion.local_motion_kernels`; with ``grid=1`` one point, the
    frame's centre), :math:`w_j` bilinear weights that are 1 at point j and fall
    to 0 at its neighbours (:func:`deblur_by_local_kernels`), and :math:`\lambda_t` = the larger
    of ``weight_per_noise`` :math:`\hat\sigma_t` (the frame's noise by Immerkær's estimate,
    :func:`~blurloc.blur.estimate_noise_sigma`) and ``min_weight``. A frame whose kernels agree
    within ``agreement_l1`` takes one kernel, :math:`w_j = 1` for the grid's middle point
    (:func:`deblur_by_local_kernels`). The formula is the mirror
    boundary's; with ``boundary="unknown"`` (the default) each term is the least-squares image
    of :func:`~blurloc.deconv.wiener_deconvolve` whose part beyond the frame (or beyond the
    point's tile, :func:`deblur_by_local_kernels`) is unknown.

    Parameters
    ----------
    frames : numpy.ndarray
        (T, H, W, 3) uint8 consecutive frames, T >= 2.
    exposure_share : float or None
        Exposure time over frame interval, the camera's setting (default
        DEFAULT_EXPOSURE_SHARE, as for frames averaged the GoPro way); None calibrates it on
        the frames (:func:`~blurloc.blur.video_motion.calibrate_exposure_share`).
    min_weight : float
        :math:`\lambda_{\min}`, > 0.
    grid : int
        Points per side of the grid of kernels (>= 1; default LOCAL_GRID; 1: one translation per
        frame pair, one kernel per frame).
    boundary : str
        ``"unknown"`` or ``"mirror"`` (:func:`~blurloc.deconv.wiener_deconvolve`).
    weight_per_noise : float
        The regulariser's weight per unit of estimated noise, > 0.
    agreement_l1 : float or None
        Largest :func:`kernel_disagreement` of a frame's grid kernels at which the frame is
        restored with one kernel (>= 0; default AGREEMENT_L1; None: every frame by its grid).
    threads : int
        Frames restored at once (>= 1; default THREADS); the result is the same for any.

    Returns
    -------
    numpy.ndarray
        (T, H, W, 3) uint8 restored frames.

    Raises
    ------
    ValueError
        If ``frames`` is not a (T, H, W, 3) uint8 video of at least two frames,
        ``exposure_share``, ``min_weight`` or ``weight_per_noise`` is not positive, ``grid`` < 1,
        ``boundary`` is unknown, ``agreement_l1`` is negative or ``threads`` < 1.
    """
    frames = np.asarray(frames)
    if frames.ndim != 4 or frames.shape[-1] != 3 or frames.dtype != np.uint8 or len(frames) < 2:
        raise ValueError(f"frames must be a (T, H, W, 3) uint8 video with T >= 2, got "
                         f"{frames.shape} {frames.dtype}")  # fmt: skip
    _check_settings(min_weight, boundary, weight_per_noise, agreement_l1, threads)
    motion = local_motion_kernels(frames, exposure_share, grid)
    return deblur_by_local_kernels(frames, motion.kernels, motion.lengths_px, motion.grid,
                                   min_weight, boundary, weight_per_noise=weight_per_noise,
                                   agreement_l1=agreement_l1, threads=threads)  # fmt: skip


def deblur_by_kernels(
    frames: np.ndarray,
    kernels: list[np.ndarray],
    lengths_px: np.ndarray,
    min_weight: float = MIN_WEIGHT,
    boundary: str = BOUNDARY,
    iterations: int = BOUNDARY_ITERATIONS,
    weight_per_noise: float = WEIGHT_PER_NOISE,
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
    weight_per_noise : float
        The regulariser's weight per unit of estimated noise (:func:`deblur_video_motion`), > 0.

    Returns
    -------
    numpy.ndarray
        (T, H, W, 3) uint8 restored frames.

    Raises
    ------
    ValueError
        If the counts of frames, kernels and lengths differ, ``min_weight`` or
        ``weight_per_noise`` is not positive, ``boundary`` is unknown or (once a frame is
        restored) ``iterations`` is negative.
    """
    return deblur_by_local_kernels(frames, [[kernel] for kernel in kernels],
                                   np.reshape(lengths_px, (-1, 1)), 1, min_weight, boundary,
                                   iterations, weight_per_noise)  # fmt: skip


def deblur_by_local_kernels(
    frames: np.ndarray,
    kernels: list[list[np.ndarray]],
    lengths_px: np.ndarray,
    grid: int,
    min_weight: float = MIN_WEIGHT,
    boundary: str = BOUNDARY,
    iterations: int = BOUNDARY_ITERATIONS,
    weight_per_noise: float = WEIGHT_PER_NOISE,
    agreement_l1: float | None = AGREEMENT_L1,
    threads: int = THREADS,
) -> np.ndarray:
    r"""Deconvolve each frame by the kernels of a grid of points, blended.

    Frame t is deconvolved with each point's kernel :math:`c_{t,j}` (the step of
    :func:`deblur_by_kernels`), and the results are blended with bilinear weights
    :math:`w_j(x) = \max(0, 1 - |x - x_j| / g_x) \max(0, 1 - |y - y_j| / g_y)` (:math:`g`:
    the grid's spacing; constant beyond the outermost points), which sum to 1 at every pixel:
    the restoration follows a blur that changes smoothly across the frame. With mirror
    boundaries each kernel restores the whole frame (a mirror at a tile's inner edge would make
    up content). With unknown boundaries each kernel restores only its tile: the part of the
    frame where its weight is above 0 (with one point, all of it), widened by the kernel's size
    and TILE_MARGIN_PX; beyond the tile the image is unknown, as beyond the frame, so the tile's
    restoration solves the frame's problem there (the same at convergence but for the margin's
    reach; on a 3 x 3 grid a quarter to under half of the frame per point, before the margin).
    A frame whose kernels all lie within ``agreement_l1`` of one another
    (:func:`kernel_disagreement`) is restored as with one point, by the kernel of the middle
    point (row and column ``grid // 2``: the centre on an odd grid) over the whole frame, and
    passed through when that point's path is under MIN_PATH_PX. A point whose path is under
    MIN_PATH_PX, or whose kernel is larger than the frame, contributes the frame as it is; a
    frame where every point's does is passed through.

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
    weight_per_noise : float
        The regulariser's weight per unit of estimated noise (:func:`deblur_video_motion`), > 0.
    agreement_l1 : float or None
        Largest disagreement of a frame's kernels at which it takes one kernel (>= 0; default
        AGREEMENT_L1; None: every frame by its grid).
    threads : int
        Frames restored at once, each on its own thread (>= 1; default THREADS); the result is
        the same for any.

    Returns
    -------
    numpy.ndarray
        (T, H, W, 3) uint8 restored frames.

    Raises
    ------
    ValueError
        If the counts of frames, kernel lists and lengths differ, a frame's kernels or lengths
        are not ``grid`` squared, ``grid`` < 1, ``min_weight`` or ``weight_per_noise`` is not
        positive, ``boundary`` is unknown, ``agreement_l1`` is negative, ``threads`` < 1, a
        kernel is not 2-D with odd sides or does not sum to more than 0 (``grid`` > 1 and
        ``agreement_l1`` set: :func:`kernel_disagreement`) or (once a frame is restored)
        ``iterations`` is negative.
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
    _check_settings(min_weight, boundary, weight_per_noise, agreement_l1, threads)
    restored = np.array(frames, copy=True)
    height, width = frames.shape[1:3]
    blends = {}  # points per side: the blend weights and the part of the frame each covers
    for points in {grid, 1}:
        blend_weights = _blend_weights(height, width, points)
        blends[points] = blend_weights, [_covered(weight) for weight in blend_weights]

    def restore(index: int) -> None:
        frame = frames[index]
        frame_kernels, frame_lengths = kernels[index], lengths_px[index]
        frame_weights, covers = blends[grid]
        if (grid > 1 and agreement_l1 is not None
                and kernel_disagreement(frame_kernels) <= agreement_l1):  # fmt: skip
            middle = (grid // 2) * grid + grid // 2
            frame_kernels = [frame_kernels[middle]]
            frame_lengths = frame_lengths[middle : middle + 1]
            frame_weights, covers = blends[1]
        usable = [
            length >= MIN_PATH_PX
            and all(kernel.shape[axis] <= frame.shape[axis] for axis in (0, 1))
            for kernel, length in zip(frame_kernels, frame_lengths, strict=True)
        ]
        if not any(usable):
            return  # no blur to undo, or paths that leave the frame
        weight = max(weight_per_noise * estimate_noise_sigma(frame), min_weight)
        image = as_float_image(frame)
        blend = np.zeros_like(image)
        for point, kernel in enumerate(frame_kernels):
            if not usable[point]:
                blend += frame_weights[point][..., None] * image
                continue
            tile = np.s_[:, :]
            if boundary == "unknown":
                tile = _widened(covers[point], max(kernel.shape) + TILE_MARGIN_PX, frame.shape)
            sharp = wiener_deconvolve(image[tile], kernel, weight, "gradient", boundary,
                                      iterations)  # fmt: skip
            blend[tile] += frame_weights[point][tile][..., None] * sharp
        restored[index] = like_input(blend, frame)

    with ThreadPoolExecutor(threads) as pool:
        list(pool.map(restore, range(len(frames))))
    return restored


def kernel_disagreement(kernels: list[np.ndarray]) -> float:
    r"""How far the kernels of one frame's grid points differ: the largest L1 distance of two.

    .. math::

        d = \max_{j, k} \sum_x |c_j(x) - c_k(x)|

    with the kernels centred on one another (each is centred on the frame's sharp instant) and
    each divided by its sum: 0 for equal kernels, 2 for kernels that share no pixel. A pan moves
    the image alike at every point; a turn about the optical axis or a move along it does not.

    Parameters
    ----------
    kernels : sequence of numpy.ndarray
        2-D kernels with odd sides, each summing to more than 0.

    Returns
    -------
    float
        The largest pairwise L1 distance (0 for one kernel).

    Raises
    ------
    ValueError
        If no kernel is given, or a kernel is not 2-D with odd sides or does not sum to more
        than 0.
    """
    padded = centred_on_one_grid(kernels)
    sums = [float(np.sum(kernel)) for kernel in padded]
    if not all(total > 0 for total in sums):
        raise ValueError(f"kernels must sum to more than 0, got sums {sums}")
    flat = np.stack([(kernel / total).ravel() for kernel, total in zip(padded, sums, strict=True)])
    return float(pdist(flat, "cityblock").max()) if len(flat) > 1 else 0.0


def _covered(weight: np.ndarray) -> tuple[slice, slice]:
    """The rows and columns where a blend weight is above 0."""
    rows, columns = np.nonzero(weight.any(axis=1))[0], np.nonzero(weight.any(axis=0))[0]
    return slice(rows[0], rows[-1] + 1), slice(columns[0], columns[-1] + 1)


def _widened(cover: tuple[slice, slice], margin: int, shape: tuple[int, ...]) -> tuple:
    """``cover`` widened by ``margin`` px on every side, within a frame of ``shape``."""
    return tuple(slice(max(0, part.start - margin), min(size, part.stop + margin))
                 for part, size in zip(cover, shape[:2], strict=True))  # fmt: skip


def _check_settings(
    min_weight: float,
    boundary: str,
    weight_per_noise: float,
    agreement_l1: float | None = None,
    threads: int = 1,
) -> None:
    """Refuse a weight floor or weight per noise that is not positive, an unknown boundary, a
    negative agreement tolerance or fewer than one thread, naming it."""
    if threads < 1:
        raise ValueError(f"threads must be >= 1, got {threads}")
    for name, value in (("min_weight", min_weight), ("weight_per_noise", weight_per_noise)):
        if not value > 0:
            raise ValueError(f"{name} must be > 0, got {value}")
    if agreement_l1 is not None and not agreement_l1 >= 0:
        raise ValueError(f"agreement_l1 must be >= 0 or None, got {agreement_l1}")
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
