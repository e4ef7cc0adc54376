"""Blind blur estimation on the stand-in, against the blur it recorded: the length model's fit on
the training split, per-frame estimates and errors on the test split, the summary against the
targets, and the rank correlation with the camera's image-plane motion."""

from __future__ import annotations

import os

import cv2
import numpy as np
from scipy.spatial.transform import Rotation
from scipy.stats import spearmanr
from tqdm.auto import tqdm

from ..blur import (
    BLUR_THRESHOLD,
    blur_features,
    blur_score,
    estimate_motion_blur,
    fit_length_model,
)
from ..data.sevenscenes import list_scenes, load_split, read_depth, read_image
from ..data.stats import read_blur_metadata
from ..geometry import intrinsics
from ..poses import rotation_angles_deg
from .estimation import angle_error_deg

#: Estimated lengths below this (px) are reported as sharp (the deblurring pipeline's cut).
SHARP_BELOW_PX = 1.5


def _frames(root: str | os.PathLike, split: str, every: int = 1) -> list[tuple[dict, object]]:
    """(blur record, sequence) of every ``every``-th frame of ``split``."""
    records = {(r["scene"], r["sequence"], r["frame"]): r for r in read_blur_metadata(root)
               if r["split"] == split}  # fmt: skip
    return [(records[(scene, sequence.number, frame)], sequence)
            for scene in list_scenes(root) for sequence in load_split(root, scene, split)
            for frame in sequence.frame_ids[::every]]  # fmt: skip


def fit_length_coefficients(
    root: str | os.PathLike, split: str = "train", ridge: float = 1.0, progress: bool = False
) -> tuple[np.ndarray, int]:
    """Fit the length model (:func:`~blurloc.blur.fit_length_model`) on a stand-in split.

    Parameters
    ----------
    root : str or os.PathLike
        Stand-in root (with ``blur.csv`` per sequence).
    split : str
        ``"train"``: never fit on the test split.
    ridge : float
        Ridge penalty.
    progress : bool
        Show a progress bar.

    Returns
    -------
    tuple of np.ndarray and int
        (13,) coefficients for ``blurloc.blur.LENGTH_COEFFICIENTS`` and the number of frames.
    """
    features, extents = [], []
    for record, sequence in tqdm(_frames(root, split), disable=not progress, desc="features"):
        found = blur_features(read_image(sequence.path(record["frame"], "color")))
        features.append(found.values)
        extents.append(record["mean_px"] / found.scale)
    return fit_length_model(np.array(features), np.array(extents), ridge), len(extents)


def estimation_rows(
    root: str | os.PathLike, split: str = "test", every: int = 1, progress: bool = False
) -> list[dict]:
    """Blind estimate of every ``every``-th frame of a stand-in split beside its recorded blur.

    Returns
    -------
    list of dict
        One row per frame: scene, sequence, frame, extent_px (recorded mean path length),
        angle_deg (recorded), estimated_length_px, estimated_angle_deg, length_error_px,
        angle_error_deg, score (:func:`~blurloc.blur.blur_score`), flagged (score above
        BLUR_THRESHOLD), reported_sharp (estimate below SHARP_BELOW_PX).
    """
    rows = []
    for record, sequence in tqdm(_frames(root, split, every), disable=not progress,
                                 desc=f"estimate {split}"):  # fmt: skip
        image = read_image(sequence.path(record["frame"], "color"))
        estimate = estimate_motion_blur(image)
        score = blur_score(image)
        rows.append({
            "scene": record["scene"], "sequence": record["sequence"], "frame": record["frame"],
            "extent_px": record["mean_px"], "angle_deg": record["angle_deg"],
            "estimated_length_px": estimate.length_px, "estimated_angle_deg": estimate.angle_deg,
            "length_error_px": abs(estimate.length_px - record["mean_px"]),
            "angle_error_deg": float(angle_error_deg(estimate.angle_deg, record["angle_deg"])),
            "score": score, "flagged": score > BLUR_THRESHOLD,
            "reported_sharp": estimate.length_px < SHARP_BELOW_PX,
        })  # fmt: skip
    return rows


def estimation_summary(rows: list[dict]) -> list[dict]:
    """The estimator's and detector's measures over :func:`estimation_rows`, each beside its
    target: one row per measure with ``measure``, ``value``, ``target``, ``frames``, ``met``."""
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

    return [
        row("Spearman(estimated length, recorded extent)", length,
            lambda v: spearmanr(v, extent).statistic, ">= 0.8", lambda v: v >= 0.8),
        row("median length error (px), extent >= 2 px", length_error[extent >= 2], np.median,
            "<= 1", lambda v: v <= 1),
        row("median angle error (deg), extent >= 4 px", angle_error[extent >= 4], np.median,
            "<= 10", lambda v: v <= 10),
        row("reported sharp, extent < 1.5 px", sharp[extent < 1.5], np.mean, "high",
            lambda v: v >= 0.9),
        row("flagged, extent >= 3 px", flagged[extent >= 3], np.mean, ">= 0.9",
            lambda v: v >= 0.9),
        row("passed, extent < 1 px", ~flagged[extent < 1], np.mean, ">= 0.9",
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


def camera_motion_px(poses: np.ndarray, distances_m: np.ndarray, focal_px: float) -> np.ndarray:
    """How far the image moves per frame interval, from poses and depth only.

    For each frame, half the image-plane motion between its neighbours (frame - 1 to frame + 1;
    one-sided at the ends): the rotation angle times the focal length plus the translation times
    the focal length over the frame's median depth. Needs nothing but what 7-Scenes provides, so
    the same check runs on real frames.

    Parameters
    ----------
    poses : np.ndarray
        (N, 4, 4) camera-to-world poses of consecutive frames, metres.
    distances_m : np.ndarray
        (N,) median scene depth of each frame, metres.
    focal_px : float
        Focal length in px at the frames' size.

    Returns
    -------
    np.ndarray
        (N,) image motion per frame interval, px.
    """
    poses = np.asarray(poses, float)
    after = np.minimum(np.arange(len(poses)) + 1, len(poses) - 1)
    before = np.maximum(np.arange(len(poses)) - 1, 0)
    turn = np.radians(rotation_angles_deg(Rotation.from_matrix(poses[before, :3, :3]),
                                          Rotation.from_matrix(poses[after, :3, :3])))
    shift = np.linalg.norm(poses[after, :3, 3] - poses[before, :3, 3], axis=1)
    steps = np.maximum(after - before, 1)
    return focal_px * (turn + shift / np.asarray(distances_m, float)) / steps


def motion_rank_correlation(
    root: str | os.PathLike, split: str = "test", every: int = 1, progress: bool = False
) -> list[dict]:
    """Rank correlation with the camera's motion: Spearman of the estimated blur length, and of
    the (negated) variance of the Laplacian, against :func:`camera_motion_px`, per sequence and
    over all frames. One row per sequence (scene, sequence, frames, estimate_spearman,
    laplacian_spearman) and a last row with scene ``all``."""
    rows, everything = [], []
    for scene in list_scenes(root):
        for sequence in load_split(root, scene, split):
            ids = sequence.frame_ids
            depths = [read_depth(sequence.path(frame, "depth")) for frame in ids]
            distances = [float(np.median(d[d > 0])) if (d > 0).any() else 1.0 for d in depths]
            focal = intrinsics(depths[0].shape[1], depths[0].shape[0])[0, 0]
            motion = camera_motion_px(sequence.poses(), np.array(distances), focal)
            values = []
            for index in tqdm(range(0, len(ids), every), disable=not progress, desc=scene):
                image = read_image(sequence.path(ids[index], "color"))
                values.append((motion[index], estimate_motion_blur(image).length_px,
                               -variance_of_laplacian(image)))  # fmt: skip
            everything += values
            rows.append(_rank_row(scene, sequence.number, np.array(values)))
    rows.append(_rank_row("all", 0, np.array(everything)))
    return rows


def _rank_row(scene: str, sequence: int, values: np.ndarray) -> dict:
    estimate, laplacian = (spearmanr(values[:, 0], values[:, c]).statistic for c in (1, 2))
    return {"scene": scene, "sequence": sequence, "frames": len(values),
            "estimate_spearman": round(float(estimate), 3),
            "laplacian_spearman": round(float(laplacian), 3)}  # fmt: skip
