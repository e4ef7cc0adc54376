"""Image-quality metrics, PSNR (eq. 5-6) and SSIM (eq. 7), and pose errors (eq. 12-17) of a
:class:`~blurloc.poses.PosePair`."""

from __future__ import annotations

import numpy as np
from skimage.metrics import structural_similarity

from .images import check_image
from .poses import PosePair, rotation_angles_deg


def _pair(reference: np.ndarray, estimate: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    reference, estimate = check_image(reference), check_image(estimate)
    if reference.shape != estimate.shape:
        raise ValueError(f"images differ in shape: {reference.shape} vs {estimate.shape}")
    return reference.astype(np.float64), estimate.astype(np.float64)


def psnr(reference: np.ndarray, estimate: np.ndarray, data_range: float) -> float:
    """Peak signal-to-noise ratio, ``10 log10(R^2 / MSE)``, MSE over all pixels and channels.

    Parameters
    ----------
    reference, estimate : numpy.ndarray
        Images of one shape, (H, W) or (H, W, 3), uint8 or float.
    data_range : float
        R: 255 for uint8, 1 for [0, 1] floats (eq. 6 uses 255).

    Returns
    -------
    float
        dB; ``inf`` for identical images.

    References
    ----------
    Eq. 5-6 of the paper.
    """
    if data_range <= 0:
        raise ValueError("data_range must be > 0")
    reference, estimate = _pair(reference, estimate)
    mse = float(np.mean((reference - estimate) ** 2))
    return float("inf") if mse == 0 else float(10.0 * np.log10(data_range**2 / mse))


def ssim(reference: np.ndarray, estimate: np.ndarray, data_range: float) -> float:
    """Structural similarity through scikit-image with the settings of Wang et al. (2004).

    Gaussian window σ = 1.5 (11x11), K1 = 0.01, K2 = 0.03, population covariances; RGB is the
    mean of the per-channel SSIMs.

    Parameters
    ----------
    reference, estimate : numpy.ndarray
        Images of one shape, (H, W) or (H, W, 3), uint8 or float.
    data_range : float
        255 for uint8, 1 for [0, 1] floats.

    Returns
    -------
    float
        SSIM, at most 1.

    References
    ----------
    Eq. 7 of the paper.
    """
    if data_range <= 0:
        raise ValueError("data_range must be > 0")
    reference, estimate = _pair(reference, estimate)
    return float(structural_similarity(
        reference, estimate, data_range=data_range, gaussian_weights=True, sigma=1.5,
        use_sample_covariance=False, channel_axis=2 if reference.ndim == 3 else None,
    ))  # fmt: skip


def mean_frame_psnr(pairs: list[tuple[np.ndarray, np.ndarray]]) -> float:
    """Mean PSNR (eq. 6, data range 255) over every frame of several videos.

    Parameters
    ----------
    pairs : list of (video, reference video)
        uint8 (T, H, W, 3) arrays of the same shape per pair (restored or blurred first, sharp
        second).

    Returns
    -------
    float
        The mean over all frames of all pairs, dB.
    """
    return float(np.mean([psnr(truth, frame, 255.0) for video, sharp in pairs
                          for frame, truth in zip(video, sharp, strict=True)]))  # fmt: skip


#: Edges (cycles per pixel) of the radial frequency bands of :func:`band_squared_error`: octaves
#: up to a quarter of the sampling rate, then everything up to the corners of the spectrum.
FREQUENCY_BAND_EDGES = (0.0, 1 / 32, 1 / 16, 1 / 8, 1 / 4, np.inf)


def band_squared_error(
    reference: np.ndarray, estimate: np.ndarray, edges: tuple[float, ...] = FREQUENCY_BAND_EDGES
) -> np.ndarray:
    """Summed squared error of ``estimate`` split by spatial frequency (Parseval's theorem).

    The 2-D DFT of each error image (estimate minus reference, per frame and channel), its
    energy divided by the pixel count, summed over the frequencies whose radius
    ``sqrt(fx^2 + fy^2)`` (cycles per pixel) lies in ``[edges[k], edges[k + 1])``. The bands
    together give the summed squared error exactly, so eq. 6's MSE, and a PSNR gain, split into
    the bands' shares.

    Parameters
    ----------
    reference, estimate : numpy.ndarray
        Frames of one shape, (H, W, C) or (T, H, W, C) (channels last), uint8 or float.
    edges : tuple of float
        Increasing band edges from 0; the last must exceed 0.5·√2 (e.g. ``inf``) so that every
        frequency falls in a band.

    Returns
    -------
    numpy.ndarray
        (len(edges) - 1,) squared error per band, summed over frames, channels and pixels (the
        units of the images, squared).

    Raises
    ------
    ValueError
        If the shapes differ or are not (H, W, C) / (T, H, W, C), or the edges do not start
        at 0, increase and cover the spectrum.
    """
    reference, estimate = np.asarray(reference), np.asarray(estimate)
    if reference.shape != estimate.shape or reference.ndim not in (3, 4):
        raise ValueError(f"frames must be two (H, W, C) or (T, H, W, C) arrays of one shape, "
                         f"got {reference.shape} and {estimate.shape}")  # fmt: skip
    edges_array = np.asarray(edges, dtype=np.float64)
    if (len(edges_array) < 2 or edges_array[0] != 0 or np.any(np.diff(edges_array) <= 0)
            or edges_array[-1] <= 0.5 * np.sqrt(2)):  # fmt: skip
        raise ValueError(f"edges must start at 0, increase and end above 0.5*sqrt(2), got {edges}")
    height, width = reference.shape[-3:-1]
    error = estimate.astype(np.float64) - reference.astype(np.float64)
    energy = np.abs(np.fft.fft2(error, axes=(-3, -2))) ** 2 / (height * width)
    energy = energy.reshape(-1, height, width, reference.shape[-1]).sum(axis=(0, 3))
    radius = np.hypot(*np.meshgrid(np.fft.fftfreq(height), np.fft.fftfreq(width), indexing="ij"))
    band = np.searchsorted(edges_array, radius, side="right") - 1
    return np.bincount(band.ravel(), weights=energy.ravel(), minlength=len(edges_array) - 1)


def position_errors(pair: PosePair) -> np.ndarray:
    """Position error of every frame, ``||c_est - c_ref||_2``.

    Parameters
    ----------
    pair : PosePair
        Reference and estimated poses of N frames.

    Returns
    -------
    numpy.ndarray
        Shape (N,), metres.

    References
    ----------
    Eq. 12 of the paper.
    """
    return np.linalg.norm(pair.estimate_positions - pair.reference_positions, axis=-1)


def orientation_errors_deg(pair: PosePair) -> np.ndarray:
    """Orientation error of every frame: the angle of ``R_ref^T R_est``.

    Parameters
    ----------
    pair : PosePair
        Reference and estimated poses of N frames.

    Returns
    -------
    numpy.ndarray
        Shape (N,), degrees in [0, 180]; ``2 arccos |<q_ref, q_est>|``.

    References
    ----------
    Eq. 13 of the paper (see :func:`blurloc.poses.rotation_angles_deg`).
    """
    return rotation_angles_deg(pair.reference_rotations, pair.estimate_rotations)


#: Thresholds of the accuracy shares: (metres, degrees). The paper printed the last as "0.5cm".
ACCURACY_THRESHOLDS = ((0.25, 2.0), (0.5, 5.0), (5.0, 10.0))


def error_statistics(values: np.ndarray) -> dict[str, float]:
    """Median, mean and root-mean-square of per-frame errors.

    Parameters
    ----------
    values : numpy.ndarray
        Shape (N,), any unit.

    Returns
    -------
    dict
        ``{"median", "mean", "rmse"}`` as floats, in the unit of ``values``.
    """
    values = np.asarray(values, float)
    return {"median": float(np.median(values)), "mean": float(np.mean(values)),
            "rmse": float(np.sqrt(np.mean(values**2)))}  # fmt: skip


def combined_errors(pair: PosePair, beta: float = 0.8) -> np.ndarray:
    """Per-frame value of eq. 14, ``||c - c^|| + beta ||q - q^||``.

    This is the package's definition of the paper's undefined "combined" error; both
    quaternions are unit with ``w >= 0`` (the convention of :mod:`blurloc.poses`).

    Parameters
    ----------
    pair : PosePair
        Reference and estimated poses of N frames.
    beta : float
        Weight of the quaternion distance (the paper's 0.8).

    Returns
    -------
    numpy.ndarray
        Shape (N,), metres plus ``beta`` times unit-quaternion distance.

    References
    ----------
    Eq. 14 of the paper.
    """
    rotation = np.linalg.norm(pair.estimate_quaternions - pair.reference_quaternions, axis=1)
    return position_errors(pair) + beta * rotation


def pose_summary(pair: PosePair, beta: float = 0.8) -> dict:
    """Every pose metric of one set of frames.

    Parameters
    ----------
    pair : PosePair
        Reference and estimated poses of N frames.
    beta : float
        Weight of the quaternion term of eq. 14.

    Returns
    -------
    dict
        - ``frames``: N;
        - ``position_m`` / ``orientation_deg``: median, mean and RMSE of eq. 12 (metres) and
          eq. 13 (degrees);
        - ``mae`` / ``mse`` / ``rmse`` (eq. 15-17) over the pose vector
          ``y = (t_x, t_y, t_z, q_w, q_x, q_y, q_z)`` (metres and unit-quaternion components,
          ``w >= 0``), all components of all frames;
        - ``combined``: the mean per-frame value of eq. 14 (:func:`combined_errors`);
        - ``within_<m>m_<deg>deg``: share of frames within each of ACCURACY_THRESHOLDS.

    References
    ----------
    Eq. 12-17 of the paper.
    """
    position = position_errors(pair)
    orientation = orientation_errors_deg(pair)
    residual = np.concatenate([pair.estimate_positions - pair.reference_positions,
                               pair.estimate_quaternions - pair.reference_quaternions],
                              axis=1)  # fmt: skip
    summary = {"frames": int(position.size), "position_m": error_statistics(position),
               "orientation_deg": error_statistics(orientation)}  # fmt: skip
    summary["mae"] = float(np.mean(np.abs(residual)))
    summary["mse"] = float(np.mean(residual**2))
    summary["rmse"] = float(np.sqrt(summary["mse"]))
    summary["combined"] = float(np.mean(combined_errors(pair, beta)))
    for metres, degrees in ACCURACY_THRESHOLDS:
        summary[f"within_{metres:g}m_{degrees:g}deg"] = float(
            np.mean((position <= metres) & (orientation <= degrees))
        )
    return summary
