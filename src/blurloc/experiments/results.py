"""What notebook 05 assembles from the earlier notebooks' outputs: where a saved pose model
lives, the measured rows of Table III, and the frames shown in Fig. 2 (one frame through the
pipeline) and Fig. 5 (input, ground truth and the view at the predicted pose)."""

from __future__ import annotations

import csv
import os
from pathlib import Path

import numpy as np

from ..blur import BLUR_THRESHOLD, detect_blur, estimate_motion_blur, log_power_spectrum, to_gray
from ..data.render import render
from ..data.scenes import make_scene
from ..data.sevenscenes import SequenceFrames, load_split, read_image
from ..deconv import blind_kernel
from ..geometry import intrinsics
from ..images import to_uint8
from ..trajectory import quaternions_to_poses
from .pose import mean_pose_baseline, model_folder, per_scene, predict_test_frames


def model_path(
    results_dir: str | os.PathLike, condition: str, head: str, scene: str, seed: int = 0
) -> Path:
    """The saved best model of one pose training of notebook 04.

    Parameters
    ----------
    results_dir : str or os.PathLike
        Folder under which notebook 04 writes ``pose_models``.
    condition : str
        Frames trained and tested on: ``blurred``, ``wiener``, ``rnn`` or ``sharp``.
    head : str
        Temporal head: ``lstm`` or ``none`` (single frame).
    scene : str
        Scene name.
    seed : int
        The training's seed.

    Returns
    -------
    pathlib.Path
        ``best.pt`` in :func:`blurloc.experiments.pose.model_folder` under
        ``results_dir/pose_models``.
    """
    return model_folder(Path(results_dir) / "pose_models", condition, head, scene, seed) / "best.pt"


def scene_predictions(
    results_dir: str | os.PathLike,
    roots: dict[str, Path],
    condition: str,
    head: str,
    scene: str,
    seed: int = 0,
) -> dict:
    """Every test frame of ``scene`` as predicted by one saved pose model of notebook 04.

    Parameters
    ----------
    results_dir : str or os.PathLike
        Folder under which notebook 04 writes ``pose_models``.
    roots : dict of str to pathlib.Path
        Where each condition's frames live (:func:`blurloc.experiments.pose.condition_roots`).
    condition, head, scene : str
        Which training: frames, temporal head and scene.
    seed : int
        The training's seed.

    Returns
    -------
    dict
        As :func:`blurloc.experiments.pose.predict_test_frames`: frames, predicted and true
        poses, per-frame position (m, eq. 12) and orientation (degrees, eq. 13) errors.
    """
    path = model_path(results_dir, condition, head, scene, seed)
    return predict_test_frames(path, roots[condition], scene)


def measured_pose(
    summary: list[dict], condition: str, head: str, scenes: list[str]
) -> dict[str, tuple[float, float]]:
    """One measured row of Table III: median errors per scene (mean over seeds) and their mean
    over ``scenes``.

    Parameters
    ----------
    summary : list of dict
        Rows of ``pose_summary.csv`` (notebook 04): ``condition``, ``head``, ``scene``,
        ``seed``, ``position_m_median`` (m) and ``orientation_deg_median`` (degrees).
    condition, head : str
        Which training.
    scenes : list of str
        Scenes averaged into ``average`` (each must have a row).

    Returns
    -------
    dict
        ``{scene: (position m, orientation degrees)}``, ``average`` = mean of the scene medians.

    References
    ----------
    Table III of the paper (median errors per scene, eq. 12-13).
    """
    position = per_scene(summary, condition, head, "position_m_median")
    orientation = per_scene(summary, condition, head, "orientation_deg_median")
    rows = {scene: (value, orientation[scene]) for scene, value in position.items()}
    rows["average"] = tuple(np.mean([rows[s] for s in scenes], axis=0))
    return rows


def baseline_pose(root: str | os.PathLike, scenes: list[str]) -> dict[str, tuple[float, float]]:
    """The mean-training-pose baseline as a Table III row.

    Parameters
    ----------
    root : str or os.PathLike
        The 7-Scenes-layout root.
    scenes : list of str
        Scenes, in table order.

    Returns
    -------
    dict
        ``{scene: (median position error m, median orientation error degrees)}`` from
        :func:`blurloc.experiments.pose.mean_pose_baseline`, ``average`` = mean over scenes.
    """
    rows = {}
    for scene in scenes:
        errors = mean_pose_baseline(root, scene)
        rows[scene] = (errors["position_m"]["median"], errors["orientation_deg"]["median"])
    rows["average"] = tuple(np.mean(list(rows.values()), axis=0))
    return rows


def pipeline_frame(sequence: SequenceFrames, is_standin: bool) -> tuple[int, dict[int, float]]:
    """The frame Fig. 2 follows through the pipeline: of ten candidates, the first the detector
    flags as blurred (the first candidate when it flags none).

    On the stand-in the candidates are the ten frames with the largest blur extent the
    renderer recorded (``blur.csv``); on real data, ten frames spread over the sequence.

    Parameters
    ----------
    sequence : SequenceFrames
        A test sequence.
    is_standin : bool
        Whether the data is the rendered stand-in (has ``blur.csv``).

    Returns
    -------
    frame_id : int
        The chosen frame.
    extents : dict of int to float
        Mean blur extent (pixels) per frame id; empty on real data.
    """
    extents: dict[int, float] = {}
    if is_standin:
        with open(sequence.folder / "blur.csv", newline="") as handle:
            extents = {int(r["frame"]): float(r["mean_px"]) for r in csv.DictReader(handle)}
        candidates = sorted(sequence.frame_ids, key=lambda i: -extents[i])[:10]
    else:
        ids = sequence.frame_ids
        candidates = list(ids[:: max(1, len(ids) // 10)])
    flagged = [i for i in candidates if detect_blur(read_image(sequence.path(i)))[0]]
    return (flagged[0] if flagged else candidates[0]), extents


def pipeline_panels(
    scene: str,
    sequence: SequenceFrames,
    frame_id: int,
    extents: dict[int, float],
    deblurred: dict[str, SequenceFrames],
    is_standin: bool,
) -> list[dict]:
    """The image panels of Fig. 2: one frame, its spectrum and the detector's verdict, the
    estimated kernel, the two deblurred versions and (stand-in only) the sharp render.

    Parameters
    ----------
    scene : str
        Scene name (for the title).
    sequence : SequenceFrames
        The blurred test sequence holding the frame.
    frame_id : int
        The frame (:func:`pipeline_frame`).
    extents : dict of int to float
        Blur extent per frame id in pixels; empty to leave it out of the title.
    deblurred : dict of str to SequenceFrames
        The same sequence deblurred: ``wiener`` (eq. 4) and ``rnn`` (eq. 8-11).
    is_standin : bool
        Whether a sharp render exists (adds the last panel).

    Returns
    -------
    list of dict
        Panels for :func:`blurloc.plots.plot_pipeline`: ``image``, ``title``, optional ``cmap``.

    References
    ----------
    Fig. 2 of the paper; eq. 4 (Wiener) and eq. 8-11 (recurrent network).
    """
    blurred = read_image(sequence.path(frame_id))
    is_blurred, score = detect_blur(blurred)
    kernel = blind_kernel(blurred)
    estimate = estimate_motion_blur(blurred)
    blur_note = f", blur {extents[frame_id]:.1f} px" if extents else ""
    verdict = "blurred" if is_blurred else "sharp"
    panels = [
        {"image": blurred,
         "title": f"B_t: {scene} {sequence.folder.name}\nframe {frame_id}{blur_note}"},
        {"image": log_power_spectrum(to_gray(blurred)), "cmap": "viridis",
         "title": f"log spectrum: L ≈ {score:.1f} px\n{'>' if is_blurred else '≤'} "
                  f"{BLUR_THRESHOLD:.2f} → {verdict}"},
        {"image": kernel if kernel is not None else np.zeros((9, 9)), "cmap": "magma",
         "title": f"estimated PSF: L {estimate.length_px:.1f} px\nat {estimate.angle_deg:.0f}°"
                  if kernel is not None else "no kernel (judged sharp)"},
        {"image": read_image(deblurred["wiener"].path(frame_id)), "title": "blind Wiener (eq. 4)"},
        {"image": read_image(deblurred["rnn"].path(frame_id)),
         "title": "recurrent network\n(eq. 8-11)"},
    ]  # fmt: skip
    if is_standin:
        panels.append({"image": read_image(sequence.path(frame_id, "sharp")),
                       "title": "sharp (truth)"})  # fmt: skip
    return panels


def median_error_views(
    root: str | os.PathLike, scene: str, result: dict, is_standin: bool
) -> tuple[dict[str, np.ndarray], str]:
    """Fig. 5 for one scene: the test frame whose position error is the scene's median, shown
    as input, deblurred, ground truth and the view at the predicted pose.

    On the stand-in the scene is rendered at the predicted pose; on real data (no renderer)
    the training frame nearest to the predicted position stands in, and the ground truth is
    the input frame itself.

    Parameters
    ----------
    root : str or os.PathLike
        The 7-Scenes-layout root of the blurred frames.
    scene : str
        Scene name.
    result : dict
        Predictions on the deblurred test frames (:func:`scene_predictions`).
    is_standin : bool
        Whether the data is the rendered stand-in.

    Returns
    -------
    views : dict of str to numpy.ndarray
        Four (H, W, 3) uint8 images by row label.
    caption : str
        The frame's position (m) and orientation (degrees) error.
    """
    k = int(np.argsort(result["position_error"])[len(result["position_error"]) // 2])
    sequence, frame = result["frames"][k]
    source = load_split(root, scene, "test")
    original = next(s for s in source if s.folder.name == sequence.folder.name)
    image = read_image(original.path(frame))
    if is_standin:
        truth = read_image(original.path(frame, "sharp"))
        pose = quaternions_to_poses(result["position"][k][None], result["quaternion"][k][None])[0]
        size = (truth.shape[1], truth.shape[0])
        linear, _ = render(make_scene(scene), pose, intrinsics(*size), *size)
        predicted_view = to_uint8(linear)
    else:
        truth = image
        train_sequences = load_split(root, scene, "train")
        train = [(s, i) for s in train_sequences for i in s.frame_ids]
        positions = np.concatenate([s.poses()[:, :3, 3] for s in train_sequences])
        nearest = int(np.argmin(np.linalg.norm(positions - result["position"][k], axis=1)))
        predicted_view = read_image(train[nearest][0].path(train[nearest][1]))
    views = {"input (blurred)": image,
             "deblurred (network)": read_image(sequence.path(frame)),
             "ground truth": truth,
             "rendered at prediction" if is_standin else "nearest training frame":
                 predicted_view}  # fmt: skip
    caption = f"{result['position_error'][k]:.2f} m, {result['orientation_error'][k]:.1f}°"
    return views, caption
