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
    r"""Peak signal-to-noise ratio (eq. 5-6), the MSE over all pixels and channels.

    .. math::

        \mathrm{MSE} = \frac{1}{MN} \sum_{x=1}^{M} \sum_{y=1}^{N}
        \bigl(f(x, y) - \tilde{f}(x, y)\bigr)^2, \qquad
        \mathrm{PSNR} = 10 \log_{10} \frac{R^2}{\mathrm{MSE}}

    (the mean also runs over the channels of an RGB image).

    Parameters
    ----------
    reference, estimate : numpy.ndarray
        Images f and :math:`\tilde{f}` of one shape, (H, W) or (H, W, 3), uint8 or float.
    data_range : float
        R: 255 for uint8, 1 for [0, 1] floats (eq. 6 uses 255).

    Returns
    -------
    float
        dB; ``inf`` for identical images.

    Raises
    ------
    ValueError
        If ``data_range`` is not > 0 or the shapes differ.

    References
    ----------
    Gonzalez and Woods, *Digital Image Processing*, 4th ed., Pearson, 2018, Section 8.1
    (fidelity criteria). Eq. 5-6 of the paper.
    """
    if data_range <= 0:
        raise ValueError("data_range must be > 0")
    reference, estimate = _pair(reference, estimate)
    mse = float(np.mean((reference - estimate) ** 2))
    return float("inf") if mse == 0 else float(10.0 * np.log10(data_range**2 / mse))


def ssim(reference: np.ndarray, estimate: np.ndarray, data_range: float) -> float:
    r"""Structural similarity (eq. 7) through scikit-image, with Wang et al.'s settings.

    .. math::

        \mathrm{SSIM}(f, \tilde{f}) =
        \frac{(2 \mu_f \mu_{\tilde{f}} + C_1)(2 \sigma_{f\tilde{f}} + C_2)}
        {(\mu_f^2 + \mu_{\tilde{f}}^2 + C_1)(\sigma_f^2 + \sigma_{\tilde{f}}^2 + C_2)},
        \qquad C_1 = (K_1 R)^2,\; C_2 = (K_2 R)^2

    computed in Gaussian windows (σ = 1.5, 11x11) and averaged over the image; K1 = 0.01,
    K2 = 0.03, population covariances; RGB is the mean of the per-channel SSIMs. (The paper's
    eq. 7 prints a + between the numerator's factors; Wang et al.'s product is used.)

    Parameters
    ----------
    reference, estimate : numpy.ndarray
        Images f and :math:`\tilde{f}` of one shape, (H, W) or (H, W, 3), uint8 or float.
    data_range : float
        R: 255 for uint8, 1 for [0, 1] floats.

    Returns
    -------
    float
        SSIM, at most 1.

    Raises
    ------
    ValueError
        If ``data_range`` is not > 0 or the shapes differ.

    References
    ----------
    Wang, Bovik, Sheikh and Simoncelli, "Image quality assessment: from error visibility to
    structural similarity", IEEE Trans. Image Process. 13(4), 2004. Eq. 7 of the paper.
    """
    if data_range <= 0:
        raise ValueError("data_range must be > 0")
    reference, estimate = _pair(reference, estimate)
    return float(structural_similarity(
        reference, estimate, data_range=data_range, gaussian_weights=True, sigma=1.5,
        use_sample_covariance=False, channel_axis=2 if reference.ndim == 3 else None,
    ))  # fmt: skip


def mean_frame_psnr(pairs: list[tuple[np.ndarray, np.ndarray]]) -> float:
    r"""Mean PSNR (eq. 6, data range 255) over every frame of several videos.

    .. math::

        \overline{\mathrm{PSNR}} = \frac{1}{\sum_v T_v} \sum_{v} \sum_{t=1}^{T_v}
        \mathrm{PSNR}(S_{v,t}, L_{v,t})

    Parameters
    ----------
    pairs : list of (video, reference video)
        uint8 (T, H, W, 3) arrays of the same shape per pair (restored or blurred first, sharp
        second).

    Returns
    -------
    float
        The mean over all frames of all pairs, dB.

    References
    ----------
    Eq. 5-6 of the paper (per frame).
    """
    return float(np.mean([psnr(truth, frame, 255.0) for video, sharp in pairs
                          for frame, truth in zip(video, sharp, strict=True)]))  # fmt: skip


#: Edges (cycles per pixel) of the radial frequency bands of :func:`band_squared_error`: octaves
#: up to a quarter of the sampling rate, then everything up to the corners of the spectrum.
FREQUENCY_BAND_EDGES = (0.0, 1 / 32, 1 / 16, 1 / 8, 1 / 4, np.inf)


def band_squared_error(
    reference: np.ndarray, estimate: np.ndarray, edges: tuple[float, ...] = FREQUENCY_BAND_EDGES
) -> np.ndarray:
    r"""Summed squared error of ``estimate`` split by spatial frequency (Parseval's theorem).

    .. math::

        \sum_{x, y} e(x, y)^2 = \frac{1}{HW} \sum_{u, v} |E(u, v)|^2, \qquad
        \mathrm{SE}_k = \frac{1}{HW} \sum_{\rho(u, v) \in [\rho_k, \rho_{k+1})} |E(u, v)|^2

    for the DFT E of each error image e (estimate minus reference, per frame and channel) and the
    radius :math:`\rho = \sqrt{f_x^2 + f_y^2}` of each frequency (cycles per pixel). The bands
    together give the summed squared error exactly, so eq. 5's MSE, and a PSNR gain, split into
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

    References
    ----------
    Gonzalez and Woods, *Digital Image Processing*, 4th ed., Pearson, 2018, Section 4.6
    (Parseval's theorem). Eq. 5 of the paper.
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
    r"""Position error of every frame (eq. 12).

    .. math::

        P_{\text{error}} = \lVert C_{\text{est}} - C_{\text{gt}} \rVert_2

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
    Kendall, Grimes and Cipolla, "PoseNet: a convolutional network for real-time 6-DOF
    camera relocalization", ICCV 2015. Eq. 12 of the paper.
    """
    return np.linalg.norm(pair.estimate_positions - pair.reference_positions, axis=-1)


def orientation_errors_deg(pair: PosePair) -> np.ndarray:
    r"""Orientation error of every frame (eq. 13): the angle of the rotation between the two.

    .. math::

        2 \cos |\alpha| = \operatorname{trace}(R_{\text{gt}}^{-1} R_{\text{est}}) - 1
        \iff |\alpha| = 2 \arccos |\langle q_{\text{gt}}, q_{\text{est}} \rangle|

    (the paper prints eq. 13 without the - 1, which the angle of a rotation matrix needs).

    Parameters
    ----------
    pair : PosePair
        Reference and estimated poses of N frames.

    Returns
    -------
    numpy.ndarray
        Shape (N,), degrees in [0, 180].

    References
    ----------
    Kendall, Grimes and Cipolla, "PoseNet: a convolutional network for real-time 6-DOF
    camera relocalization", ICCV 2015. Eq. 13 of the paper (see
    :func:`blurloc.poses.rotation_angles_deg`).
    """
    return rotation_angles_deg(pair.reference_rotations, pair.estimate_rotations)


#: Thresholds of the accuracy shares: (metres, degrees). The paper printed the last as "0.5cm".
ACCURACY_THRESHOLDS = ((0.25, 2.0), (0.5, 5.0), (5.0, 10.0))


def error_statistics(values: np.ndarray) -> dict[str, float]:
    r"""Median, mean and root-mean-square of per-frame errors.

    .. math::

        \mathrm{RMSE} = \sqrt{\frac{1}{n} \sum_{i=1}^{n} e_i^2}

    Parameters
    ----------
    values : numpy.ndarray
        Shape (N,), any unit.

    Returns
    -------
    dict
        ``{"median", "mean", "rmse"}`` as floats, in the unit of ``values``.

    References
    ----------
    Eq. 17 of the paper (the RMSE of the errors). Kendall, Grimes and Cipolla, "PoseNet: a
    convolutional network for real-time 6-DOF camera relocalization", ICCV 2015 (median errors,
    as 7-Scenes results are reported).
    """
    values = np.asarray(values, float)
    return {"median": float(np.median(values)), "mean": float(np.mean(values)),
            "rmse": float(np.sqrt(np.mean(values**2)))}  # fmt: skip


def combined_errors(pair: PosePair, beta: float = 0.8) -> np.ndarray:
    r"""Per-frame value of eq. 14, the package's definition of the paper's "combined" error.

    .. math::

        \ell = \lVert C_{\text{est}} - C_{\text{gt}} \rVert_2
        + \beta \lVert q_{\text{est}} - q_{\text{gt}} \rVert_2

    Both quaternions are unit with ``w >= 0`` (the convention of :mod:`blurloc.poses`), so the
    paper's normalisation :math:`R_{gt} / \lVert R_{gt} \rVert` is already done.

    Parameters
    ----------
    pair : PosePair
        Reference and estimated poses of N frames.
    beta : float
        :math:`\beta`, the weight of the quaternion distance (the paper's 0.8).

    Returns
    -------
    numpy.ndarray
        Shape (N,), metres plus ``beta`` times unit-quaternion distance.

    References
    ----------
    Kendall, Grimes and Cipolla, "PoseNet: a convolutional network for real-time 6-DOF
    camera relocalization", ICCV 2015. Eq. 14 of the paper.
    """
    rotation = np.linalg.norm(pair.estimate_quaternions - pair.reference_quaternions, axis=1)
    return position_errors(pair) + beta * rotation


def pose_summary(pair: PosePair, beta: float = 0.8) -> dict:
    r"""Every pose metric of one set of frames (eq. 12-17).

    .. math::

        \mathrm{MAE} = \frac{1}{n} \sum_{i=1}^{n} |y_i - x_i|, \quad
        \mathrm{MSE} = \frac{1}{n} \sum_{i=1}^{n} (y_i - x_i)^2, \quad
        \mathrm{RMSE} = \sqrt{\mathrm{MSE}}

    over the n = 7N components of the pose vectors (reference y, estimate x).

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
    Shotton, Glocker, Zach, Izadi, Criminisi and Fitzgibbon, "Scene coordinate regression
    forests for camera relocalization in RGB-D images", CVPR 2013 (7-Scenes and its
    thresholds).
    Kendall, Grimes and Cipolla, "PoseNet: a convolutional network for real-time 6-DOF
    camera relocalization", ICCV 2015. Eq. 12-17 of the paper.
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
