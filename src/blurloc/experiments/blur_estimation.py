"""Blind blur estimation on the stand-in, against the blur it recorded: the length model's fit on
the training split, per-frame estimates and errors on the test split, the summary against the
targets, and the rank correlation with the camera's image-plane motion."""

from __future__ import annotations

import os

import cv2
import numpy as np
import skimage.data
from scipy.stats import spearmanr
from tqdm.auto import tqdm

from ..blur import (
    ANALYSIS_SIDE,
    BLUR_THRESHOLD,
    BLURRED_FROM_PX,
    SHARP_BELOW_PX,
    analysis_length,
    blur_features,
    blur_image,
    estimate_motion_blur,
    shake_path,
    trajectory_kernel,
)
from ..data.camera_model import jpeg, sensor_noise
from ..data.samples import split_frames
from ..data.sevenscenes import SequenceFrames, read_depth, read_image
from ..data.stats import read_blur_metadata
from ..geometry import image_motion_px, intrinsics
from .estimation import angle_error_deg


def recorded_frames(
    root: str | os.PathLike, split: str, budget: int | None = None
) -> list[tuple[dict, SequenceFrames]]:
    """The frames of a stand-in split that a pass reads, each with the blur recorded for it.

    Parameters
    ----------
    root : str or os.PathLike
        Stand-in root (with ``blur.csv`` per sequence).
    split : str
        ``"train"`` or ``"test"``.
    budget : int or None
        About how many frames to read, spread evenly
        (:func:`~blurloc.data.samples.split_frames`); None reads every frame.

    Returns
    -------
    list of tuple
        (blur record of ``blur.csv``: scene, sequence, frame, mean_px, angle_deg, ...;
        the frame's :class:`~blurloc.data.sevenscenes.SequenceFrames`).
    """
    records = {(r["scene"], r["sequence"], r["frame"]): r for r in read_blur_metadata(root)
               if r["split"] == split}  # fmt: skip
    return [(records[(scene, sequence.number, frame)], sequence)
            for scene, sequence, frame in split_frames(root, split, budget)]  # fmt: skip


def length_training_set(
    root: str | os.PathLike,
    split: str = "train",
    sharp_every: int = 4,
    noise_sigma: float = 0.01,
    seed: int = 0,
    budget: int | None = None,
    progress: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Examples for the length model from a stand-in split.

    Every frame read (its recorded extent), and the sharp render of every ``sharp_every``-th
    frame read in each sequence as an example of no blur (extent 0): alternately as stored and
    with the camera's noise (Gaussian, ``noise_sigma`` on [0, 1] intensities, 8 bits), so that
    sharp frames with and without noise are both seen.

    Parameters
    ----------
    root : str or os.PathLike
        Stand-in root (with ``blur.csv`` per sequence).
    split : str
        ``"train"``: never fit on the test split.
    sharp_every : int
        Use the sharp render of every n-th frame read in each sequence.
    noise_sigma : float
        Noise added to every other sharp render.
    seed : int
        Seed of that noise.
    budget : int or None
        About how many frames of the split to read, spread evenly
        (:func:`~blurloc.data.samples.split_frames`); None reads every frame.
    progress : bool
        Show a progress bar.

    Returns
    -------
    tuple of np.ndarray
        (N, k) :func:`~blurloc.blur.blur_features` values and (N,) extents, px at the analysis
        scale.
    """
    rng = np.random.default_rng(seed)
    features, extents, first = [], [], {}
    frames = recorded_frames(root, split, budget)
    for index, (record, sequence) in enumerate(tqdm(frames, disable=not progress,
                                                    desc="features")):  # fmt: skip
        found = blur_features(read_image(sequence.path(record["frame"], "color")))
        features.append(found.values)
        extents.append(record["mean_px"] / found.scale)
        position = index - first.setdefault((record["scene"], record["sequence"]), index)
        if position % sharp_every == 0:
            sharp = read_image(sequence.path(record["frame"], "sharp"))
            if position // sharp_every % 2:
                noisy = sharp / 255.0 + rng.normal(0.0, noise_sigma, sharp.shape)
                sharp = np.round(np.clip(noisy, 0.0, 1.0) * 255.0).astype(np.uint8)
            features.append(blur_features(sharp).values)
            extents.append(0.0)
    return np.array(features), np.array(extents)


#: scikit-image's photographs that :func:`photo_training_set` blurs: none of those the tests,
#: notebooks and benchmarks measure on.
TRAINING_PHOTOS = ("retina", "moon", "page", "cell", "microaneurysms", "text", "stereo_motorcycle",
                   "horse", "logo")  # fmt: skip


def _photo(name: str) -> np.ndarray:
    """A scikit-image photograph as float RGB in [0, 1] (the left view of a stereo pair)."""
    image = getattr(skimage.data, name)()
    image = image[0] if isinstance(image, tuple) else image
    image = image[..., :3] if image.ndim == 3 else np.dstack([image] * 3)
    if image.dtype == bool:
        return image.astype(np.float64)
    return image.astype(np.float64) / (255.0 if image.max() > 1 else 1.0)


def photo_training_set(
    count: int = 1500, seed: int = 0, max_length_px: float = 24.0
) -> tuple[np.ndarray, np.ndarray]:
    """Examples for the length model from photographs, so that it does not learn the stand-in's
    textures only.

    Each example: one of TRAINING_PHOTOS, area-resized to a short side of 120-480 px; blurred
    (a quarter of them not at all) along a slightly bent path of 0.5 to ``max_length_px`` px at
    the analysis scale in a random direction (:func:`~blurloc.blur.trajectory_kernel`);
    Gaussian noise of σ 0.003 or 0.01; 8 bits.

    Parameters
    ----------
    count : int
        Number of examples.
    seed : int
        Seed of the sizes, paths and noise.
    max_length_px : float
        Longest path, px at the analysis scale: 24 covers the blur the estimator is for (up to
        15 px at 160x120 and 40 px at 640x480, 20 px at the analysis scale), so that the
        length model does not underestimate long blur.

    Returns
    -------
    tuple of np.ndarray
        (count, k) :func:`~blurloc.blur.blur_features` values and (count,) path lengths, px at
        the analysis scale.
    """
    rng = np.random.default_rng(seed)
    photos = [_photo(name) for name in TRAINING_PHOTOS]
    features, extents = [], []
    for index in range(count):
        photo = photos[index % len(photos)]
        short = min(photo.shape[:2])
        side = min(short, int(rng.choice([120, 120, 160, 240, 360, 480])))
        size = tuple(max(16, round(n * side / short)) for n in photo.shape[1::-1])
        image = cv2.resize(photo, size, interpolation=cv2.INTER_AREA)
        scale = max(1.0, side / ANALYSIS_SIDE)
        extent = 0.0
        if rng.random() >= 0.25:
            image, extent = _blur_along_random_path(image, rng, max_length_px, scale)
        found = blur_features(_as_camera_frame(image, rng))
        features.append(found.values)
        extents.append(extent / found.scale)
    return np.array(features), np.array(extents)


def _blur_along_random_path(
    image: np.ndarray, rng: np.random.Generator, max_length_px: float, scale: float
) -> tuple[np.ndarray, float]:
    """Blur ``image`` along a random path of 0.5 to ``max_length_px`` px at the analysis scale
    (``scale`` image px each): three times in four a slightly bent line (its length as the
    extent), else a hand-shake path (:func:`~blurloc.blur.shake_path`, its bounding box's longer
    side as the extent); returns the image and the extent in image px."""
    length = rng.uniform(0.5, max_length_px) * scale
    if rng.random() < 0.75:
        angle = rng.uniform(0, np.pi)
        t = np.linspace(-0.5, 0.5, 20)
        bend = rng.normal(0.0, 0.1)
        path = length * np.column_stack([t * np.cos(angle), -t * np.sin(angle) + bend * t**2])
        extent = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
    else:
        path, extent = shake_path(length, rng), length
    return blur_image(image, trajectory_kernel(path)), extent


def _as_camera_frame(image: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """An RGB image in [0, 1] as a camera stores it: signal-dependent noise
    (:func:`~blurloc.data.camera_model.sensor_noise`: read σ 0.003 or 0.01, shot variance 0,
    1e-4 or 4e-4 per unit intensity), 8 bits, and half of the time JPEG at a quality of 70 to
    95 (:func:`~blurloc.data.camera_model.jpeg`)."""
    read, shot = rng.choice([0.003, 0.01]), rng.choice([0.0, 1e-4, 4e-4])
    noisy = image + sensor_noise(image, shot, read, rng)
    frame = np.round(np.clip(noisy, 0, 1) * 255).astype(np.uint8)
    if rng.random() < 0.5:
        frame = jpeg(frame, int(rng.integers(70, 96)))
    return frame


def estimation_rows(
    root: str | os.PathLike,
    split: str = "test",
    budget: int | None = None,
    sharp_renders: bool = True,
    progress: bool = False,
) -> list[dict]:
    """Blind estimate of a stand-in split's frames beside their recorded blur.

    Parameters
    ----------
    root : str or os.PathLike
        Stand-in root (with ``blur.csv`` per sequence).
    split : str
        Split to measure on.
    budget : int or None
        About how many frames of the split to read, spread evenly
        (:func:`~blurloc.data.samples.split_frames`); None reads every frame.
    sharp_renders : bool
        Add a row for each frame's sharp render (as stored, extent 0): the class of sharp
        frames the detector must pass.
    progress : bool
        Show a progress bar.

    Returns
    -------
    list of dict
        One row per image: kind (``color`` or ``sharp``), scene, sequence, frame, extent_px
        (recorded mean path length; 0 for sharp renders), angle_deg (recorded), estimated_length_px,
        estimated_angle_deg, length_error_px, angle_error_deg, score
        (:func:`~blurloc.blur.blur_score`: the coarse length at the analysis scale), flagged
        (score above BLUR_THRESHOLD; the deblurring pipeline's cut), reported_sharp (estimated
        length at the analysis scale at most BLUR_THRESHOLD).
    """
    rows = []
    kinds = ("color", "sharp") if sharp_renders else ("color",)
    for record, sequence in tqdm(recorded_frames(root, split, budget), disable=not progress,
                                 desc=f"estimate {split}"):  # fmt: skip
        for kind in kinds:
            image = read_image(sequence.path(record["frame"], kind))
            features = blur_features(image)
            estimate = estimate_motion_blur(image, features=features)
            score = analysis_length(features)
            extent = record["mean_px"] if kind == "color" else 0.0
            rows.append({
                "kind": kind, "scene": record["scene"], "sequence": record["sequence"],
                "frame": record["frame"], "extent_px": extent, "angle_deg": record["angle_deg"],
                "estimated_length_px": estimate.length_px,
                "estimated_angle_deg": estimate.angle_deg,
                "length_error_px": abs(estimate.length_px - extent),
                "angle_error_deg": float(angle_error_deg(estimate.angle_deg, record["angle_deg"])),
                "score": score, "flagged": score > BLUR_THRESHOLD,
                "reported_sharp": estimate.length_px / features.scale <= BLUR_THRESHOLD,
            })  # fmt: skip
    return rows


def estimation_summary(rows: list[dict]) -> list[dict]:
    """The estimator's and detector's measures over :func:`estimation_rows`, each beside its
    target: one row per measure with ``measure``, ``value``, ``target``, ``frames``, ``met``.
    Length and angle are measured on the camera frames (kind ``color``); the sharp class of the
    detector is the frames under 1 px and the sharp renders."""
    color = np.array([r["kind"] == "color" for r in rows])
    extent = np.array([r["extent_px"] for r in rows])
    length = np.array([r["estimated_length_px"] for r in rows])
    length_error = np.array([r["length_error_px"] for r in rows])
    angle_error = np.array([r["angle_error_deg"] for r in rows])
    flagged = np.array([r["flagged"] for r in rows])
    sharp = np.array([r["reported_sharp"] for r in rows])

    def row(measure: str, values: np.ndarray, statistic, target: str, met) -> dict:
        value = float(statistic(values)) if values.size else float("nan")
        return {"measure": measure, "value": round(value, 3), "target": target,
                "frames": int(values.size), "met": bool(values.size and met(value))}  # fmt: skip

    def spearman(values: np.ndarray) -> float:
        return spearmanr(values, extent[color]).statistic

    return [
        row("Spearman(estimated length, recorded extent)", length[color], spearman, ">= 0.8",
            lambda v: v >= 0.8),
        row("median length error (px), extent >= 2 px", length_error[color & (extent >= 2)],
            np.median, "<= 1", lambda v: v <= 1),
        row("median angle error (deg), extent >= 4 px", angle_error[color & (extent >= 4)],
            np.median, "<= 10", lambda v: v <= 10),
        row(f"reported sharp, frames with extent < {SHARP_BELOW_PX:g} px",
            sharp[color & (extent < SHARP_BELOW_PX)],
            np.mean, "high", lambda v: v >= 0.9),
        row("reported sharp, sharp renders", sharp[~color], np.mean, "high",
            lambda v: v >= 0.9),
        row(f"flagged, extent >= {BLURRED_FROM_PX:g} px",
            flagged[color & (extent >= BLURRED_FROM_PX)], np.mean, ">= 0.9", lambda v: v >= 0.9),
        row("passed, extent < 1 px and sharp renders", ~flagged[extent < 1], np.mean, ">= 0.9",
            lambda v: v >= 0.9),
    ]  # fmt: skip


def variance_of_laplacian(image: np.ndarray) -> float:
    """The common sharpness score: variance of the gray image's Laplacian (larger = sharper).

    References
    ----------
    Pech-Pacheco et al., "Diatom autofocusing in brightfield microscopy", ICPR 2000.
    """
    gray = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY) if image.ndim == 3 else image
    return float(cv2.Laplacian(np.float32(gray), cv2.CV_32F).var())


def camera_motion_px(
    poses: np.ndarray,
    distances_m: np.ndarray,
    camera: np.ndarray,
    image_size: tuple[int, int],
    indices: np.ndarray | None = None,
) -> np.ndarray:
    """How far the image moves per frame interval, from poses and depth only.

    For each frame (or each of ``indices``), half the image motion between its neighbours
    (frame - 1 to frame + 1; one-sided at the ends), by :func:`~blurloc.geometry.image_motion_px`
    at the frame's median depth. Needs nothing but what 7-Scenes (or TUM RGB-D) provides, so the
    same check runs on real frames.

    Parameters
    ----------
    poses : np.ndarray
        (N, 4, 4) camera-to-world poses of consecutive frames, metres.
    distances_m : np.ndarray
        (M,) median scene depth of each frame evaluated, metres.
    camera : np.ndarray
        (3, 3) camera matrix of the frames, pixels.
    image_size : tuple of int
        (width, height) of the frames, pixels.
    indices : np.ndarray or None
        (M,) positions in ``poses`` of the frames to evaluate; None evaluates all (M = N).

    Returns
    -------
    np.ndarray
        (M,) image motion per frame interval, px.
    """
    poses = np.asarray(poses, float)
    indices = np.arange(len(poses)) if indices is None else np.asarray(indices)
    after = np.minimum(indices + 1, len(poses) - 1)
    before = np.maximum(indices - 1, 0)
    steps = np.maximum(after - before, 1)
    depths = np.asarray(distances_m, float)
    moved = [image_motion_px(poses[b], poses[a], camera, image_size, float(d))
             for b, a, d in zip(before, after, depths, strict=True)]  # fmt: skip
    return np.array(moved) / steps


def motion_rank_correlation(
    root: str | os.PathLike,
    split: str = "test",
    budget: int | None = None,
    progress: bool = False,
) -> list[dict]:
    """Rank correlation with the camera's motion: Spearman of the estimated blur length, and of
    the (negated) variance of the Laplacian, against :func:`camera_motion_px`, per sequence and
    over all frames read.

    Parameters
    ----------
    root : str or os.PathLike
        A 7-Scenes-layout root with depth images.
    split : str
        Split to measure on.
    budget : int or None
        About how many frames of the split to read, spread evenly
        (:func:`~blurloc.data.samples.split_frames`); None reads every frame.
    progress : bool
        Show a progress bar.

    Returns
    -------
    list of dict
        One row per sequence (scene, sequence, frames, estimate_spearman, laplacian_spearman)
        and a last row with scene ``all``.
    """
    chosen: dict[tuple[str, int], tuple[SequenceFrames, list[int]]] = {}
    for scene, sequence, frame in split_frames(root, split, budget):
        chosen.setdefault((scene, sequence.number), (sequence, []))[1].append(frame)
    rows, everything = [], []
    for (scene, number), (sequence, ids) in chosen.items():
        depths = [read_depth(sequence.path(frame, "depth")) for frame in ids]
        distances = [float(np.median(d[d > 0])) if (d > 0).any() else 1.0 for d in depths]
        size = (depths[0].shape[1], depths[0].shape[0])
        indices = np.searchsorted(sequence.frame_ids, ids)
        motion = camera_motion_px(sequence.poses(), np.array(distances), intrinsics(*size), size,
                                  indices)  # fmt: skip
        values = []
        for frame, moved in tqdm(zip(ids, motion, strict=True), total=len(ids),
                                 disable=not progress, desc=f"{scene} {number}"):  # fmt: skip
            image = read_image(sequence.path(frame, "color"))
            values.append((moved, estimate_motion_blur(image).length_px,
                           -variance_of_laplacian(image)))  # fmt: skip
        everything += values
        rows.append(_rank_row(scene, number, np.array(values)))
    rows.append(_rank_row("all", 0, np.array(everything)))
    return rows


def _rank_row(scene: str, sequence: int, values: np.ndarray) -> dict:
    estimate, laplacian = (spearmanr(values[:, 0], values[:, c]).statistic for c in (1, 2))
    return {"scene": scene, "sequence": sequence, "frames": len(values),
            "estimate_spearman": round(float(estimate), 3),
            "laplacian_spearman": round(float(laplacian), 3)}  # fmt: skip
