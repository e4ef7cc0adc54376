"""Image-quality metrics: PSNR (eq. 5-6) and SSIM (eq. 7)."""

from __future__ import annotations

import numpy as np
from skimage.metrics import structural_similarity

from .images import check_image


def _pair(reference: np.ndarray, estimate: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    reference, estimate = check_image(reference), check_image(estimate)
    if reference.shape != estimate.shape:
        raise ValueError(f"images differ in shape: {reference.shape} vs {estimate.shape}")
    return reference.astype(np.float64), estimate.astype(np.float64)


def psnr(reference: np.ndarray, estimate: np.ndarray, data_range: float) -> float:
    """Peak signal-to-noise ratio in dB: 10 log10(R^2 / MSE) (eq. 5-6), MSE over all pixels and
    channels. ``data_range`` R is explicit: 255 for uint8, 1 for [0, 1] floats (eq. 6 uses 255).
    Identical images give inf."""
    if data_range <= 0:
        raise ValueError("data_range must be > 0")
    reference, estimate = _pair(reference, estimate)
    mse = float(np.mean((reference - estimate) ** 2))
    return float("inf") if mse == 0 else float(10.0 * np.log10(data_range**2 / mse))


def ssim(reference: np.ndarray, estimate: np.ndarray, data_range: float) -> float:
    """Structural similarity (eq. 7) through scikit-image with the settings of Wang et al. (2004):
    Gaussian window σ = 1.5 (11x11), K1 = 0.01, K2 = 0.03, population covariances; RGB is the
    mean of the per-channel SSIMs."""
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


def position_errors(true_positions: np.ndarray, estimated_positions: np.ndarray) -> np.ndarray:
    """Eq. 12: Euclidean distance ||C_est - C_gt||_2 per frame (metres). Arrays (N, 3)."""
    true_positions = np.asarray(true_positions, float)
    estimated_positions = np.asarray(estimated_positions, float)
    if true_positions.shape != estimated_positions.shape or true_positions.shape[-1] != 3:
        raise ValueError(f"positions must both be (N, 3), got {true_positions.shape} and "
                         f"{estimated_positions.shape}")  # fmt: skip
    return np.linalg.norm(estimated_positions - true_positions, axis=-1)


def rotation_errors_deg(true_rotations: np.ndarray, estimated_rotations: np.ndarray) -> np.ndarray:
    """Eq. 13: the smallest angle |α| aligning R_est with R_gt, 2 cos|α| + 1 = trace(R_gt^T
    R_est) (the paper prints the trace without the +1 of the identity), per frame, degrees.
    Arrays (N, 3, 3). Equal to 2 arccos|<q_gt, q_est>| for unit quaternions."""
    true_rotations = np.asarray(true_rotations, float)
    estimated_rotations = np.asarray(estimated_rotations, float)
    trace = np.einsum("nji,nji->n", true_rotations, estimated_rotations)
    return np.degrees(np.arccos(np.clip((trace - 1.0) / 2.0, -1.0, 1.0)))


def quaternion_errors_deg(
    true_quaternions: np.ndarray, estimated_quaternions: np.ndarray
) -> np.ndarray:
    """2 arccos |<q_gt, q_est>| per frame in degrees (the PoseNet/AtLoc orientation error), for
    quaternions (N, 4); they are normalised first, and q and -q are the same rotation."""
    q1 = np.asarray(true_quaternions, float)
    q2 = np.asarray(estimated_quaternions, float)
    norms = np.linalg.norm(q1, axis=-1) * np.linalg.norm(q2, axis=-1)
    if q1.shape != q2.shape or q1.shape[-1] != 4 or np.any(norms < 1e-12):
        raise ValueError("quaternions must be non-zero (N, 4) arrays of the same shape")
    dot = np.abs(np.sum(q1 * q2, axis=-1)) / norms
    return np.degrees(2.0 * np.arccos(np.clip(dot, 0.0, 1.0)))


#: Thresholds of the accuracy shares: (metres, degrees). The paper printed the last as "0.5cm".
ACCURACY_THRESHOLDS = ((0.25, 2.0), (0.5, 5.0), (5.0, 10.0))


def error_statistics(values: np.ndarray) -> dict[str, float]:
    """Median, mean and RMSE of per-frame errors."""
    values = np.asarray(values, float)
    return {"median": float(np.median(values)), "mean": float(np.mean(values)),
            "rmse": float(np.sqrt(np.mean(values**2)))}  # fmt: skip


def _hemisphere(quaternions: np.ndarray) -> np.ndarray:
    """Unit quaternions with w >= 0."""
    q = np.asarray(quaternions, float) / np.linalg.norm(quaternions, axis=-1, keepdims=True)
    return q * np.where(q[:, :1] < 0, -1.0, 1.0)


def combined_errors(
    true_positions: np.ndarray,
    true_quaternions: np.ndarray,
    estimated_positions: np.ndarray,
    estimated_quaternions: np.ndarray,
    beta: float = 0.8,
) -> np.ndarray:
    """Per-frame value of eq. 14, ||c - c^|| + beta ||q - q^||, both quaternions unit with
    w >= 0: this package's definition of the paper's undefined "combined" error."""
    position = position_errors(true_positions, estimated_positions)
    rotation = np.linalg.norm(_hemisphere(estimated_quaternions) - _hemisphere(true_quaternions),
                              axis=1)  # fmt: skip
    return position + beta * rotation


def pose_summary(
    true_positions: np.ndarray,
    true_quaternions: np.ndarray,
    estimated_positions: np.ndarray,
    estimated_quaternions: np.ndarray,
    beta: float = 0.8,
) -> dict:
    """Every pose metric of one set of frames.

    - position_m / orientation_deg: median, mean and RMSE of eq. 12 and eq. 13;
    - mae / mse / rmse (eq. 15-17) over the pose vector y = (t_x, t_y, t_z, q_w, q_x, q_y, q_z)
      (metres and unit-quaternion components, w >= 0), all components of all frames;
    - combined: the paper never defines its "combined" error; here it is the mean per-frame
      value of eq. 14, ||c - c^|| + beta ||q - q^||, with the paper's beta = 0.8;
    - within_*: share of frames within each of ACCURACY_THRESHOLDS.
    """
    position = position_errors(true_positions, estimated_positions)
    orientation = quaternion_errors_deg(true_quaternions, estimated_quaternions)

    q_true, q_est = _hemisphere(true_quaternions), _hemisphere(estimated_quaternions)
    residual = np.concatenate([np.asarray(estimated_positions) - np.asarray(true_positions),
                               q_est - q_true], axis=1)  # fmt: skip
    summary = {"frames": int(position.size), "position_m": error_statistics(position),
               "orientation_deg": error_statistics(orientation)}  # fmt: skip
    summary["mae"] = float(np.mean(np.abs(residual)))
    summary["mse"] = float(np.mean(residual**2))
    summary["rmse"] = float(np.sqrt(summary["mse"]))
    summary["combined"] = float(np.mean(combined_errors(
        true_positions, true_quaternions, estimated_positions, estimated_quaternions, beta)))
    for metres, degrees in ACCURACY_THRESHOLDS:
        summary[f"within_{metres:g}m_{degrees:g}deg"] = float(
            np.mean((position <= metres) & (orientation <= degrees))
        )
    return summary
