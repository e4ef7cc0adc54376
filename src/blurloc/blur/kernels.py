"""Motion-blur kernels (PSFs) and the blur model of the paper's eq. 1, b = c * x + η.

Conventions: images are float arrays in [0, 1] (or uint8), rows downwards. Angles are degrees in
[0, 180), counter-clockwise from the image's horizontal axis as displayed (y up); lengths are
pixels of the image given. A kernel is a 2-D array summing to 1 with its centre at
``(rows // 2, cols // 2)``.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import cv2
import numpy as np
import scipy.fft

from ..images import as_float_image

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
    r"""Linear motion PSF: a segment of ``length_px`` pixels at ``angle_deg``, anti-aliased.

    The kernel of a camera moving at constant speed along a straight line during the exposure,
    the c of eq. 1:

    .. math::

        c(x, y) = \frac{1}{L} \int_{-L/2}^{L/2}
        \delta(x - t \cos\theta,\; y + t \sin\theta)\, dt

    The segment is centred on the kernel centre and sampled 16 times per pixel with bilinear
    weights, so sub-pixel lengths and any angle are represented; the kernel sums to 1.

    Parameters
    ----------
    length_px : float
        Length L of the segment, px (> 0).
    angle_deg : float
        Direction :math:`\theta`, degrees counter-clockwise from the horizontal (y up).
    size : int, optional
        Odd side of the kernel; default the smallest odd size that holds the segment.

    Returns
    -------
    numpy.ndarray
        (size, size) float64 kernel summing to 1.

    Raises
    ------
    ValueError
        If the length is not > 0, or ``size`` is even or too small for the segment.

    References
    ----------
    Gonzalez and Woods, *Digital Image Processing*, 4th ed., Pearson, 2018, Section 5.6
    (estimating the degradation function: motion blur). The paper's eq. 1.
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
    r"""PSF of a camera-shake path: the time average of a point moving along the path.

    .. math::

        c(x, y) = \frac{1}{T} \int_0^T \delta(x - p_x(t),\; y - p_y(t))\, dt

    for image positions :math:`p(t)` at equal time steps over the exposure, linearly interpolated
    between them and sampled 16 times per pixel with bilinear weights (each step gets equal time).

    Parameters
    ----------
    trajectory_px : numpy.ndarray
        (N, 2) finite image positions (x right, y down, px) at equal time steps; one position
        gives a sharp (delta) kernel.
    size : int, optional
        Side of the kernel; default the smallest odd size that holds the path.
    origin : numpy.ndarray, optional
        (2,) position placed at the kernel centre (default the path's mean). Pass the
        mid-exposure position to get the kernel that maps a mid-exposure sharp frame to the
        blurred one without a shift.

    Returns
    -------
    numpy.ndarray
        (size, size) float64 kernel summing to 1.

    Raises
    ------
    ValueError
        If the path is not a finite (N, 2) array with N >= 1.

    References
    ----------
    Levin, Weiss, Durand and Freeman, "Understanding and evaluating blind deconvolution
    algorithms", CVPR 2009 (camera-shake kernels as the image path of a point). The paper's eq. 1.
    """
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
    r"""A random hand-shake path over one exposure, for kernels like those of real camera shake.

    Boracchi and Foi's model: a point moves at constant speed; at each step its velocity is
    pushed by a Gaussian term and pulled back towards the start (a centripetal term), both
    scaled by a random "anxiety", and now and then reversed by an abrupt shake:

    .. math::

        v_{k+1} \propto v_k + a\,(g\, n_k - c\, p_k)\, s + \text{(abrupt turn)}, \qquad
        p_{k+1} = p_k + v_{k+1}

    with :math:`|v_{k+1}| = s`, :math:`n_k` complex Gaussian noise and the shape parameters
    a (anxiety), g, c drawn per path from ``rng``. The path is then scaled so that the longer side
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

    Raises
    ------
    ValueError
        If ``extent_px`` is not > 0 or ``steps`` < 2.

    References
    ----------
    Boracchi and Foi, "Modeling the performance of image restoration from motion blur", IEEE
    Trans. Image Process. 21(8), 2012 (their random trajectory generator).
    Not in the paper, whose blur (eq. 1) is a linear motion; used to blur photographs with
    camera-shake kernels (Section III.A.1's c, of any shape).
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


def centred_on_one_grid(kernels: Sequence[np.ndarray]) -> list[np.ndarray]:
    """Kernels with odd sides zero-padded about their centre pixels to one shape, the largest
    side of any along each axis, so that they can be compared or averaged pixel by pixel.

    Parameters
    ----------
    kernels : sequence of numpy.ndarray
        2-D kernels with odd sides.

    Returns
    -------
    list of numpy.ndarray
        The kernels, float64, each of the common shape.

    Raises
    ------
    ValueError
        If no kernel is given, or a kernel is not 2-D with odd sides.
    """
    shapes = [np.shape(kernel) for kernel in kernels]
    if len(shapes) == 0 or any(len(shape) != 2 or shape[0] % 2 == 0 or shape[1] % 2 == 0
                               for shape in shapes):  # fmt: skip
        raise ValueError(f"kernels must be 2-D with odd sides, got shapes {shapes}")
    size = np.max(shapes, axis=0)
    return [np.pad(np.asarray(kernel, float),
                   [((side - own) // 2,) * 2 for side, own in zip(size, shape, strict=True)])
            for kernel, shape in zip(kernels, shapes, strict=True)]  # fmt: skip


def check_kernel(kernel: np.ndarray, image_shape: tuple[int, ...] | None = None) -> np.ndarray:
    r"""A kernel as float64 normalised to sum 1, or a ValueError saying what is wrong.

    .. math::

        c \leftarrow c / \textstyle\sum_{m,n} c(m, n)

    so that the blur of eq. 1 keeps the image's mean brightness.

    Parameters
    ----------
    kernel : numpy.ndarray
        Non-empty, finite 2-D array whose sum is not 0.
    image_shape : tuple of int, optional
        Shape of the image it will be applied to; the kernel may not be larger.

    Returns
    -------
    numpy.ndarray
        The normalised kernel, float64.

    Raises
    ------
    ValueError
        If the kernel is not 2-D, is empty, holds NaN or inf, sums to 0, or exceeds the image.

    References
    ----------
    The paper's eq. 1 (c is a PSF).
    """
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


def kernel_to_otf(
    kernel: np.ndarray, shape: tuple[int, int], dtype: type = np.float32
) -> np.ndarray:
    r"""Optical transfer function of a kernel: its DFT on a grid of ``shape``, centred at (0, 0).

    The kernel is zero-padded to ``shape`` and rolled so that its centre pixel
    ``(rows // 2, cols // 2)`` lies at the origin, so that filtering by it does not shift the
    image (MATLAB's ``psf2otf``): a product with an image's ``rfft2`` convolves the image with the
    kernel circularly, which is :func:`blur_image` wherever the kernel does not reach across the
    border.

    .. math::

        C(u, v) = \sum_{m, n} c(m, n)\, e^{-2\pi i (u m / M + v n / N)}

    Parameters
    ----------
    kernel : numpy.ndarray
        (h, w) point spread function c of eq. 1, smaller than ``shape`` (not normalised here).
    shape : tuple of int
        (M, N) size of the transform.
    dtype : type
        Precision of the padded kernel (float32, the deconvolution's; float64 for comparisons
        that must match a float64 convolution).

    Returns
    -------
    numpy.ndarray
        (M, N // 2 + 1) complex: the ``rfft2`` half of C, the F{c} of eq. 2-4.

    Raises
    ------
    ValueError
        If the kernel is larger than ``shape`` along either axis.

    References
    ----------
    Gonzalez and Woods, *Digital Image Processing*, 4th ed., Pearson, 2018, Sections 5.7-5.8
    (inverse and minimum mean square error filtering).
    """
    if kernel.shape[0] > shape[0] or kernel.shape[1] > shape[1]:
        raise ValueError(f"kernel {kernel.shape} is larger than the transform {tuple(shape)}")
    padded = np.zeros(shape, dtype)
    rows = (np.arange(kernel.shape[0]) - kernel.shape[0] // 2) % shape[0]
    columns = (np.arange(kernel.shape[1]) - kernel.shape[1] // 2) % shape[1]
    padded[np.ix_(rows, columns)] = kernel
    return scipy.fft.rfft2(padded)


def blur_image(
    image: np.ndarray,
    kernel: np.ndarray,
    noise_sigma: float = 0.0,
    boundary: str = "reflect",
    rng: np.random.Generator | None = None,
) -> np.ndarray:
    r"""The blur model of eq. 1: convolve with ``kernel`` and add Gaussian noise.

    .. math::

        b = c * x + \eta, \qquad \eta \sim \mathcal{N}(0, \sigma^2)

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) sharp image x, uint8 (scaled to [0, 1] first) or float.
    kernel : numpy.ndarray
        PSF c (normalised to sum 1 here), no larger than the image.
    noise_sigma : float
        :math:`\sigma` of the signal-independent noise :math:`\eta` (>= 0).
    boundary : str
        How the image continues beyond its border: ``reflect`` (mirror, without repeating the
        edge pixel), ``wrap`` (periodic, the model the DFT assumes) or ``constant`` (zeros).
    rng : numpy.random.Generator, optional
        Source of the noise (default a fresh generator).

    Returns
    -------
    numpy.ndarray
        The blurred image b, float64, same shape (noise is not clipped).

    Raises
    ------
    ValueError
        On an unknown ``boundary``, a negative ``noise_sigma`` or an invalid kernel.

    References
    ----------
    Gonzalez and Woods, *Digital Image Processing*, 4th ed., Pearson, 2018, Section 5.6
    (estimating the degradation function: motion blur). The paper's eq. 1.
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
