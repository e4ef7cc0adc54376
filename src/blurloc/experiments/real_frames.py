"""The blur stages on the real development set (:mod:`blurloc.data.real`): detection on real
photographs, blind length against the camera's own motion on real posed frames, blind Wiener on
real blurred/sharp pairs. Shared by notebooks 01 and 02 and ``benchmarks/bench_real.py``.
"""

from __future__ import annotations

from collections.abc import Callable

import cv2
import numpy as np
from scipy.stats import spearmanr

from ..blur import detect_blur, estimate_motion_blur, video_motion_kernels
from ..data import load_split
from ..data.real import (
    POSED_SCENE,
    load_pairs,
    load_photographs,
    posed_camera,
    posed_frame_table,
    posed_root,
)
from ..deconv import deblur_blind
from ..intervals import Interval
from ..metrics import psnr
from .blur_estimation import TRAINING_PHOTOS, camera_motion_px, variance_of_laplacian

#: File stems of scikit-image photographs whose ``skimage.data`` function has another name.
SKIMAGE_NAMES = {"ihc": "immunohistochemistry", "motorcycle_left": "stereo_motorcycle"}


def photograph_verdicts() -> list[dict]:
    """The detector (:func:`blurloc.blur.detect_blur`, default threshold) on every real sharp
    and blurred photograph of the development set.

    Returns
    -------
    list of dict
        One row per photograph: ``part`` ("sharp" or "blurred"), ``photograph`` (file stem),
        ``score_px``, ``reported`` ("sharp" or "blurred"), ``correct`` (the report matches the
        part) and ``fitted_on`` (whether the length model was fitted on a blurred copy of it:
        one of ``TRAINING_PHOTOS``).
    """
    rows = []
    for part in ("sharp", "blurred"):
        for name, image in load_photographs(part).items():
            flagged, score = detect_blur(image)
            rows.append({
                "part": part,
                "photograph": name,
                "score_px": round(float(score), 2),
                "reported": "blurred" if flagged else "sharp",
                "correct": flagged == (part == "blurred"),
                "fitted_on": SKIMAGE_NAMES.get(name, name) in TRAINING_PHOTOS,
            })  # fmt: skip
    return rows


def posed_frames_with_motion(step: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """The real posed TUM RGB-D frames (640x480, consecutive) and the camera's image motion
    during each, from the recorded poses and depth alone.

    The motion of frame i is half the image motion between frames i - 1 and i + 1 at the frame's
    median depth (:func:`~blurloc.experiments.blur_estimation.camera_motion_px`): px per frame
    interval. The exposure is a fixed share of the interval, so it ranks frames as the motion
    during the exposure does.

    Parameters
    ----------
    step : int
        Keep every ``step``-th frame (the motion is computed from all poses first).

    Returns
    -------
    images : numpy.ndarray
        (N, 480, 640, 3) uint8 RGB frames.
    motion_px : numpy.ndarray
        (N,) image motion per frame interval, px.
    """
    if step < 1:
        raise ValueError(f"step must be >= 1, got {step}")
    root = posed_root()
    sequences = [s for split in ("train", "test") for s in load_split(root, POSED_SCENE, split)]
    poses = np.concatenate([s.poses() for s in sequences])
    images = np.concatenate([s.images() for s in sequences])
    depths = np.array([float(row["depth_median_m"]) for row in posed_frame_table()])
    size = (images.shape[2], images.shape[1])
    motion = camera_motion_px(poses, depths, posed_camera(), size)
    return images[::step], motion[::step]


def blur_measures(images: np.ndarray, scale: int = 1) -> dict[str, np.ndarray]:
    """Three measures of each frame's blur, larger for more blur: the blind length
    (:func:`blurloc.blur.estimate_motion_blur`), the detector's score and the negated variance of
    the Laplacian (a one-line baseline).

    Parameters
    ----------
    images : numpy.ndarray
        (N, H, W, 3) frames.
    scale : int
        Area-average each frame by this factor first (2: 640x480 frames measured at 320x240).

    Returns
    -------
    dict of str to numpy.ndarray
        ``{"blind length (px)", "detector score (px)", "negated variance of the Laplacian"}``,
        each (N,), in px of the measured size where a length.
    """
    frames = resized_frames(images, scale)
    measure: dict[str, Callable[[np.ndarray], float]] = {
        "blind length (px)": lambda frame: estimate_motion_blur(frame).length_px,
        "detector score (px)": lambda frame: detect_blur(frame)[1],
        "negated variance of the Laplacian": lambda frame: -variance_of_laplacian(frame),
    }
    return {name: np.array([function(frame) for frame in frames])
            for name, function in measure.items()}  # fmt: skip


def resized_frames(images: np.ndarray, scale: int) -> list[np.ndarray]:
    """Each frame area-averaged by ``scale`` (1: as it is).

    Parameters
    ----------
    images : numpy.ndarray
        (N, H, W[, 3]) frames.
    scale : int
        Integer factor by which each side shrinks (2: 640x480 to 320x240).

    Returns
    -------
    list of numpy.ndarray
        The frames, resized with ``cv2.INTER_AREA``.
    """
    return [cv2.resize(image, None, fx=1 / scale, fy=1 / scale, interpolation=cv2.INTER_AREA)
            if scale > 1 else image for image in images]  # fmt: skip


def video_motion_lengths(images: np.ndarray, scale: int = 1) -> np.ndarray:
    """Each frame's blur length read from the video's own motion: the length of its exposure
    path (:func:`blurloc.blur.video_motion_kernels`, default exposure share), in px of the
    measured size.

    Parameters
    ----------
    images : numpy.ndarray
        (N, H, W, 3) consecutive frames, N >= 2.
    scale : int
        Area-average each frame by this factor first.

    Returns
    -------
    numpy.ndarray
        (N,) path lengths, px.
    """
    return video_motion_kernels(np.stack(resized_frames(images, scale))).lengths_px


def motion_agreement(measures: dict[str, np.ndarray], motion_px: np.ndarray) -> list[dict]:
    r"""Spearman rank correlation of each blur measure with the camera's image motion.

    .. math::

        \rho = \operatorname{corr}\big(\operatorname{rank}(m), \operatorname{rank}(u)\big)

    for a measure m and the motion u over the same frames.

    Parameters
    ----------
    measures : dict of str to numpy.ndarray
        (N,) values per measure (:func:`blur_measures`).
    motion_px : numpy.ndarray
        (N,) image motion of the same frames.

    Returns
    -------
    list of dict
        One row per measure: ``measure``, ``frames``, ``spearman``.
    """
    return [{"measure": name, "frames": len(values),
             "spearman": round(float(spearmanr(values, motion_px).statistic), 3)}
            for name, values in measures.items()]  # fmt: skip


def spearman_difference(
    first: np.ndarray,
    second: np.ndarray,
    motion_px: np.ndarray,
    block: int = 10,
    resamples: int = 2000,
    level: float = 0.95,
    seed: int = 0,
) -> Interval:
    r"""How much better one blur measure ranks frames by the camera's motion than another: the
    difference of their Spearman ρ, with a moving-block bootstrap interval.

    .. math::

        \Delta = \rho(m_1, u) - \rho(m_2, u)

    Consecutive frames share their motion, so frames are resampled in runs of ``block``
    consecutive frames (Künsch's moving-block bootstrap), both measures on the same draw.

    Parameters
    ----------
    first, second : numpy.ndarray
        (N,) values of the two measures, frames in recording order.
    motion_px : numpy.ndarray
        (N,) image motion of the same frames.
    block : int
        Frames per resampled run.
    resamples : int
        Bootstrap resamples.
    level : float
        Confidence level.
    seed : int
        Seed of the resampling.

    Returns
    -------
    Interval
        ``mean``: Δ on all frames; ``low``, ``high``: percentile bounds; ``pairs``: frames.

    Raises
    ------
    ValueError
        If the arrays differ in length or hold fewer than two blocks of frames.

    References
    ----------
    Künsch, "The jackknife and the bootstrap for general stationary observations", Annals of
    Statistics 17(3), 1989.
    """
    first, second, motion_px = (np.asarray(a, float) for a in (first, second, motion_px))
    frames = len(motion_px)
    if not len(first) == len(second) == frames:
        raise ValueError(f"measures and motion differ in length: {len(first)}, {len(second)}, "
                         f"{frames}")  # fmt: skip
    if frames < 2 * block:
        raise ValueError(f"{frames} frames: need at least two blocks of {block}")

    def difference(index: np.ndarray) -> float:
        return float(spearmanr(first[index], motion_px[index]).statistic
                     - spearmanr(second[index], motion_px[index]).statistic)  # fmt: skip

    rng = np.random.default_rng(seed)
    runs = -(-frames // block)  # enough runs to cover the frames; the last is cut

    def resample() -> np.ndarray:
        starts = rng.integers(0, frames - block + 1, runs)
        return (starts[:, None] + np.arange(block)).ravel()[:frames]

    draws = [difference(resample()) for _ in range(resamples)]
    tail = 100 * (1 - level) / 2
    low, high = np.percentile(draws, [tail, 100 - tail])
    return Interval(mean=difference(np.arange(frames)), low=float(low), high=float(high),
                    pairs=frames, level=level, method="bootstrap")  # fmt: skip


def pair_restorations() -> list[dict]:
    """Blind Wiener deblurring (:func:`blurloc.deconv.deblur_blind`) on the real blurred/sharp
    pairs: PSNR against the sharp frame before and after.

    Returns
    -------
    list of dict
        One row per pair: ``pair``, ``blurred_psnr_db``, ``deblurred_psnr_db``, ``change_db``.
    """
    rows = []
    for name, blurred, sharp in load_pairs():
        before = psnr(sharp, blurred, data_range=255)
        after = psnr(sharp, deblur_blind(blurred), data_range=255)
        rows.append({"pair": name, "blurred_psnr_db": round(before, 2),
                     "deblurred_psnr_db": round(after, 2),
                     "change_db": round(after - before, 2)})  # fmt: skip
    return rows
