"""The pose experiments of notebooks 04-06: the matrix of trainings (per scene and seed, train on
one kind of input frames, blurred, blind-Wiener, network-deblurred or sharp, with one head, test
on the same kind), the mean-pose baseline, the blur at the network's input, a saved model's
per-frame predictions, and the tables built from the matrix's summaries (the overview with its
seed spread, has the regressor learned, Tables I-II beside the paper)."""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation
from tqdm.auto import tqdm

from ..data.scenes import REAL_MEAN_POSE_BASELINE
from ..data.sevenscenes import list_scenes, load_split, read_image
from ..data.stats import read_blur_metadata
from ..inference import load_pose_model, predict_poses
from ..metrics import combined_errors, orientation_errors_deg, pose_summary, position_errors
from ..paper import paper_values
from ..poses import PosePair, to_quaternions
from ..train.config import PoseTrainConfig
from ..train.datasets import FrameCache
from ..train.loop import parallel_map
from ..train.pose import train_pose
from .comparisons import per_scene_mean
from .rows import grouped_values, matching

CONDITIONS = ("blurred", "wiener", "rnn", "sharp")


def condition_roots(
    data_root: str | os.PathLike, results_dir: str | os.PathLike
) -> dict[str, Path]:
    """Where each condition's frames live.

    Parameters
    ----------
    data_root : str or os.PathLike
        The 7-Scenes-layout root (blurred frames; sharp renders for ``sharp``).
    results_dir : str or os.PathLike
        Folder under which notebook 03 writes ``deblurred/wiener`` and ``deblurred/rnn``.

    Returns
    -------
    dict
        ``{condition: root}`` for every name of CONDITIONS.
    """
    results_dir = Path(results_dir)
    return {"blurred": Path(data_root), "wiener": results_dir / "deblurred" / "wiener",
            "rnn": results_dir / "deblurred" / "rnn", "sharp": Path(data_root)}  # fmt: skip


def run_pose_matrix(
    roots: dict[str, Path],
    scenes: list[str],
    runs: list[tuple[str, str]],
    config: PoseTrainConfig,
    out_dir: str | os.PathLike,
    seeds: tuple[int, ...] = (0,),
    progress: bool = False,
    workers: int = 1,
) -> tuple[list[dict], list[dict]]:
    """Train and test every (condition, head) of ``runs`` on every scene, once per seed.

    The same seeds serve every condition and head, so that runs can be paired by scene and
    seed (:func:`blurloc.experiments.comparisons.comparison_table`). Each process decodes a
    scene's frames and reads its poses once for all the runs of that scene it makes (one
    :class:`~blurloc.train.datasets.FrameCache` per scene), and all seeds of one (condition,
    head) run in the same process, so each condition's frames are read by one process only.
    Finished trainings are not re-run (:func:`~blurloc.train.pose.train_pose` resumes).

    With ``workers > 1`` the runs are spread over that many processes
    (:func:`~blurloc.train.loop.parallel_map`), each training with ``config.threads // workers``
    threads (at least 1); the numbers then match a serial run made with that many threads.

    Parameters
    ----------
    roots : dict
        ``{condition: root}`` (:func:`condition_roots`).
    scenes : list of str
        Scene names.
    runs : list of (str, str)
        (condition, head) pairs; ``sharp`` trains and tests on the sharp renders.
    config : PoseTrainConfig
        Training settings shared by every run (the head and the seed are replaced per run).
    out_dir : str or os.PathLike
        Models go to ``out_dir/<condition>/<head>/<scene>/seed-<seed>``.
    seeds : tuple of int
        Training seeds.
    progress : bool
        Show a progress bar over the runs.
    workers : int
        Processes that train at once (1: in this process).

    Returns
    -------
    summaries : list of dict
        One row per run, scene and seed, in the order scene, run, seed: scene, seed,
        condition, head, train_seconds and :func:`~blurloc.metrics.pose_summary` flattened
        (``position_m_median``, ...).
    frames : list of dict
        One row per test frame: scene, seed, condition, head, index, position_m (eq. 12),
        orientation_deg (eq. 13) and combined (eq. 14).

    Raises
    ------
    ValueError
        If ``workers`` is not positive.

    References
    ----------
    Eq. 12-17 of the paper; Tables I-II (blurred and deblurred inputs).
    """
    threads = config.threads if workers <= 1 else max(1, config.threads // workers)
    jobs = [(roots[condition], scene, condition, head,
             replace(config, seed=seed, threads=threads,
                     image="sharp" if condition == "sharp" else "color",
                     model=replace(config.model, head=head)),
             model_folder(out_dir, condition, head, scene, seed))
            for scene in scenes for condition, head in runs for seed in seeds]  # fmt: skip
    _SCENE_CACHES.clear()
    results = parallel_map(_run_one, jobs, workers, chunksize=len(seeds))
    return _collect(tqdm(results, total=len(jobs), disable=not progress, desc="pose runs"))


#: The frames of the scene this process works on (a new scene lets the previous one's go).
_SCENE_CACHES: dict[str, FrameCache] = {}


def _run_one(job: tuple) -> tuple[dict, list[dict]]:
    """Train (or resume) and test one run of :func:`run_pose_matrix`."""
    root, scene, condition, head, config, folder = job
    if scene not in _SCENE_CACHES:
        _SCENE_CACHES.clear()
        _SCENE_CACHES[scene] = FrameCache()
    cache = _SCENE_CACHES[scene]
    history = train_pose(root, scene, folder, config, progress=False, cache=cache)
    model, _ = load_pose_model(folder / "best.pt")
    pair = predict_poses(model, load_split(root, scene, "test"), config, cache=cache)
    labels = {"scene": scene, "seed": config.seed, "condition": condition, "head": head}
    row = {**labels, "train_seconds": round(history["seconds"][-1], 1)}
    for key, value in pose_summary(pair, config.beta).items():
        if isinstance(value, dict):
            row.update({f"{key}_{stat}": v for stat, v in value.items()})
        else:
            row[key] = value
    position, orientation = position_errors(pair), orientation_errors_deg(pair)
    combined = combined_errors(pair, config.beta)
    frames = [{**labels, "index": index, "position_m": float(position[index]),
               "orientation_deg": float(orientation[index]),
               "combined": float(combined[index])} for index in range(len(position))]  # fmt: skip
    return row, frames


def _collect(results) -> tuple[list[dict], list[dict]]:
    """The summaries and frame rows of :func:`run_pose_matrix`'s runs, in run order."""
    summaries, frames = [], []
    for row, frame_rows in results:
        summaries.append(row)
        frames += frame_rows
    return summaries, frames


def model_folder(
    out_dir: str | os.PathLike, condition: str, head: str, scene: str, seed: int
) -> Path:
    """Where :func:`run_pose_matrix` keeps one run's model.

    Parameters
    ----------
    out_dir : str or os.PathLike
        The matrix's folder.
    condition, head, scene : str
        The run.
    seed : int
        Its training seed.

    Returns
    -------
    pathlib.Path
        ``out_dir/<condition>/<head>/<scene>/seed-<seed>`` (``best.pt``, ``history.json``).
    """
    return Path(out_dir) / condition / head / scene / f"seed-{seed}"


def _split_poses(root: str | os.PathLike, scene: str) -> tuple[np.ndarray, np.ndarray]:
    """Camera-to-world poses (N, 4, 4) of a scene's training and of its test split."""
    return tuple(np.concatenate([s.poses() for s in load_split(root, scene, split)])
                 for split in ("train", "test"))  # fmt: skip


def mean_pose_baseline(root: str | os.PathLike, scene: str) -> dict:
    """Errors of predicting one pose, the mean of the training poses, for every test frame.

    The mean position and the mean rotation (:meth:`scipy.spatial.transform.Rotation.mean`,
    the quaternion average) of the training split: what a regressor must beat to have
    learned anything.

    Parameters
    ----------
    root : str or os.PathLike
        The 7-Scenes-layout root.
    scene : str
        Scene name.

    Returns
    -------
    dict
        :func:`~blurloc.metrics.pose_summary` of the test frames against that constant pose.
    """
    train, test = _split_poses(root, scene)
    reference = Rotation.from_matrix(test[:, :3, :3])
    mean_q = to_quaternions(Rotation.from_matrix(train[:, :3, :3]).mean())
    pair = PosePair(test[:, :3, 3], to_quaternions(reference),
                    np.tile(train[:, :3, 3].mean(axis=0), (len(test), 1)),
                    np.tile(mean_q, (len(test), 1)))  # fmt: skip
    return pose_summary(pair)


#: Degrees of orientation error that :func:`nearest_view_baseline` weighs like one metre of
#: position error: the ratio of the real 7-Scenes mean-pose baselines averaged over the scenes
#: (0.8 m to 32°; per scene 26-53 °/m).
DEGREES_PER_METRE = 40.0


def nearest_view_baseline(
    root: str | os.PathLike, scene: str, degrees_per_metre: float = DEGREES_PER_METRE
) -> dict:
    """Errors of predicting, for every test frame, the pose of the training frame nearest to it.

    Nearest in pose: the smallest position error (m) plus orientation error (degrees) divided by
    ``degrees_per_metre``. An oracle (it reads the test poses to choose), so not a method: it
    says how far the test views lie from any view the training split holds. A regressor that
    only interpolates between training views can hardly beat it; a test split that leaves the
    region its training split covers shows a large value here, whatever the network.

    Parameters
    ----------
    root : str or os.PathLike
        The 7-Scenes-layout root.
    scene : str
        Scene name.
    degrees_per_metre : float
        Orientation error equivalent to one metre of position error (> 0).

    Returns
    -------
    dict
        :func:`~blurloc.metrics.pose_summary` of the test frames against their nearest training
        poses.

    Raises
    ------
    ValueError
        If ``degrees_per_metre`` is not positive.
    """
    if not degrees_per_metre > 0:
        raise ValueError(f"degrees_per_metre must be > 0, got {degrees_per_metre}")
    train, test = _split_poses(root, scene)
    train_q = to_quaternions(Rotation.from_matrix(train[:, :3, :3]))
    test_q = to_quaternions(Rotation.from_matrix(test[:, :3, :3]))
    nearest = np.empty(len(test), int)
    for start in range(0, len(test), 256):  # 256 test frames at a time: bounded memory
        part = slice(start, start + 256)
        metres = np.linalg.norm(test[part, None, :3, 3] - train[None, :, :3, 3], axis=2)
        cosine = np.clip(np.abs(test_q[part] @ train_q.T), 0.0, 1.0)
        degrees = np.degrees(2.0 * np.arccos(cosine))
        nearest[part] = np.argmin(metres + degrees / degrees_per_metre, axis=1)
    pair = PosePair(test[:, :3, 3], test_q, train[nearest, :3, 3], train_q[nearest])
    return pose_summary(pair)


def baseline_beside_real(root: str | os.PathLike) -> list[dict]:
    """The mean-pose baseline of every scene under ``root`` beside the real 7-Scenes one.

    Parameters
    ----------
    root : str or os.PathLike
        The 7-Scenes-layout root (stand-in or real).

    Returns
    -------
    list of dict
        Per scene: ``position_m`` and ``orientation_deg`` (median errors of predicting the mean
        training pose, :func:`mean_pose_baseline`), ``real_position_m`` /
        ``real_orientation_deg`` (the same measure on the published 7-Scenes poses,
        :data:`blurloc.data.scenes.REAL_MEAN_POSE_BASELINE`; empty for other scene names), and
        the nearest-view oracle's position error (:func:`nearest_view_baseline`) in metres and
        as a share of ``position_m`` (``nearest_position_m``, ``nearest_ratio``).
    """
    rows = []
    for scene in list_scenes(root):
        summary = mean_pose_baseline(root, scene)
        position = summary["position_m"]["median"]
        nearest = nearest_view_baseline(root, scene)["position_m"]["median"]
        real = REAL_MEAN_POSE_BASELINE.get(scene, ("", ""))
        rows.append({"scene": scene, "position_m": round(position, 3),
                     "orientation_deg": round(summary["orientation_deg"]["median"], 1),
                     "real_position_m": real[0], "real_orientation_deg": real[1],
                     "nearest_position_m": round(nearest, 3),
                     "nearest_ratio": round(nearest / position, 2)})  # fmt: skip
    return rows


def predict_test_frames(model_path: str | os.PathLike, root: str | os.PathLike, scene: str) -> dict:
    """A saved pose model's predictions for every test frame of ``scene``.

    Parameters
    ----------
    model_path : str or os.PathLike
        A pose checkpoint (``best.pt``).
    root : str or os.PathLike
        The 7-Scenes-layout root the model is tested on.
    scene : str
        Scene name.

    Returns
    -------
    dict
        ``frames``: [(sequence, frame id)] in sequence, then frame order; ``position`` (N, 3)
        and ``quaternion`` (N, 4, w first) predicted, ``true_position``/``true_quaternion``,
        and per frame ``position_error`` (metres, eq. 12) and ``orientation_error`` (degrees,
        eq. 13).
    """
    model, config = load_pose_model(model_path, scene=scene)
    sequences = load_split(root, scene, "test")
    pair = predict_poses(model, sequences, config)
    return {"frames": [(s, frame) for s in sequences for frame in s.frame_ids],
            "position": pair.estimate_positions, "quaternion": pair.estimate_quaternions,
            "true_position": pair.reference_positions,
            "true_quaternion": pair.reference_quaternions,
            "position_error": position_errors(pair),
            "orientation_error": orientation_errors_deg(pair)}  # fmt: skip


def per_scene(summaries: list[dict], condition: str, head: str, key: str) -> dict[str, float]:
    """One column of the matrix's summaries, per scene, for one (condition, head) run: the
    mean over seeds (:func:`~blurloc.experiments.comparisons.per_scene_mean`).

    Parameters
    ----------
    summaries : list of dict
        Rows of :func:`run_pose_matrix` (``scene``, ``seed``, ``condition``, ``head`` and the
        metrics), or the same rows read back from ``pose_summary.csv``.
    condition, head : str
        The run, e.g. ``("blurred", "lstm")``.
    key : str
        The column, e.g. ``position_m_median`` (eq. 12, metres), ``orientation_deg_median``
        (eq. 13, degrees), ``mae``/``mse``/``rmse`` (eq. 15-17) or ``combined`` (eq. 14).

    Returns
    -------
    dict
        ``{scene: mean over seeds}`` in the rows' order.
    """
    return per_scene_mean(summaries, key, {"condition": condition, "head": head})


def scene_mean(summaries: list[dict], condition: str, head: str, key: str) -> float:
    """The mean over scenes of one column of one run (:func:`per_scene`).

    Parameters
    ----------
    summaries : list of dict
        Rows of :func:`run_pose_matrix`.
    condition, head : str
        The run.
    key : str
        The column (see :func:`per_scene`).

    Returns
    -------
    float
        Mean of the per-scene values (NaN when the run has no rows).
    """
    values = list(per_scene(summaries, condition, head, key).values())
    return float(np.mean(values)) if values else float("nan")


def seed_spread(summaries: list[dict], condition: str, head: str, key: str) -> float:
    """How much the scene-mean of one column moves from seed to seed.

    Parameters
    ----------
    summaries : list of dict
        Rows of :func:`run_pose_matrix`.
    condition, head, key : str
        As in :func:`scene_mean`.

    Returns
    -------
    float
        Sample standard deviation (ddof 1) over seeds of the mean over scenes; 0 with one seed.
    """
    by_seed = grouped_values(summaries, "seed", key, {"condition": condition, "head": head})
    means = [float(np.mean(values)) for values in by_seed.values()]
    return float(np.std(means, ddof=1)) if len(means) > 1 else 0.0


def pose_overview(
    summaries: list[dict], runs: list[tuple[str, str]], baseline: dict[str, dict]
) -> list[dict]:
    """The overview table: per run, the median errors averaged over scenes and seeds with their
    seed spread, then the mean training pose as the last row.

    Parameters
    ----------
    summaries : list of dict
        Rows of :func:`run_pose_matrix`.
    runs : list of (str, str)
        (condition, head) pairs, in the table's order.
    baseline : dict
        ``{scene: mean_pose_baseline(...)}`` (:func:`mean_pose_baseline`).

    Returns
    -------
    list of dict
        ``condition``, ``head``, ``seeds``, ``position_m`` (median eq. 12, metres, 3 decimals),
        ``orientation_deg`` (median eq. 13, degrees, 2 decimals) and ``combined`` (mean eq. 14,
        4 decimals), each the mean over scenes of the mean over seeds, and each with its seed
        spread (``*_sd``: standard deviation over seeds of the mean over scenes).

    References
    ----------
    Eq. 12-14 of the paper.
    """
    columns = {
        "position_m": ("position_m_median", 3),
        "orientation_deg": ("orientation_deg_median", 2),
        "combined": ("combined", 4),
    }
    rows = []
    for condition, head in runs:
        seeds = {r["seed"] for r in matching(summaries, {"condition": condition, "head": head})}
        row = {"condition": condition, "head": head, "seeds": len(seeds)}
        for name, (key, digits) in columns.items():
            row[name] = round(scene_mean(summaries, condition, head, key), digits)
            row[f"{name}_sd"] = round(seed_spread(summaries, condition, head, key), digits)
        rows.append(row)
    last = {"condition": "mean training pose", "head": "-", "seeds": ""}
    for name, (_, digits) in columns.items():
        values = [
            b[name]["median"] if isinstance(b[name], dict) else b[name] for b in baseline.values()
        ]
        last |= {name: round(float(np.mean(values)), digits), f"{name}_sd": ""}
    rows.append(last)
    return rows


def learning_check(
    summaries: list[dict], baseline: dict[str, dict], condition: str = "sharp", head: str = "lstm"
) -> list[dict]:
    """Per scene: has the regressor learned? Its errors against the mean training pose's.

    Parameters
    ----------
    summaries : list of dict
        Rows of :func:`run_pose_matrix`.
    baseline : dict
        ``{scene: mean_pose_baseline(...)}``.
    condition, head : str
        The run checked (default: LSTM on sharp frames, the best case).

    Returns
    -------
    list of dict
        Per scene: ``position_m`` and ``orientation_deg`` (median errors, mean over seeds),
        ``baseline_position_m``/``baseline_orientation_deg`` (the mean training pose's), and
        ``position_ratio``/``orientation_ratio`` (regressor over baseline; below 1: learned).
    """
    position = per_scene(summaries, condition, head, "position_m_median")
    orientation = per_scene(summaries, condition, head, "orientation_deg_median")
    rows = []
    for scene, value in position.items():
        base_position = baseline[scene]["position_m"]["median"]
        base_orientation = baseline[scene]["orientation_deg"]["median"]
        rows.append(
            {
                "scene": scene,
                "position_m": round(value, 3),
                "baseline_position_m": round(base_position, 3),
                "position_ratio": round(value / base_position, 2),
                "orientation_deg": round(orientation[scene], 2),
                "baseline_orientation_deg": round(base_orientation, 2),
                "orientation_ratio": round(orientation[scene] / base_orientation, 2),
            }
        )
    return rows


def blur_at_input(root: str | os.PathLike, config: PoseTrainConfig) -> dict:
    """How long the stand-in's recorded blur is once frames are resized for the pose network.

    The regressor resizes every frame so its short side is ``config.resize`` px: a blur of L px
    in a frame of short side S becomes L * resize / S px at the network's input.

    Parameters
    ----------
    root : str or os.PathLike
        A stand-in root (with ``blur.csv`` per sequence).
    config : PoseTrainConfig
        The regressor's settings (``resize``, ``crop``).

    Returns
    -------
    dict
        ``frames``, ``frame_short_side_px``, ``input_short_side_px``, and the median and
        90th percentile of the recorded mean blur extent, in frame pixels
        (``frame_median_px``, ``frame_p90_px``) and at the network's input (``input_median_px``,
        ``input_p90_px``).
    """
    records = read_blur_metadata(root)
    extents = np.array([r["mean_px"] for r in records])
    scene = records[0]["scene"]
    first = load_split(root, scene, "train")[0]
    short_side = min(read_image(first.path(first.frame_ids[0])).shape[:2])
    scale = config.resize / short_side
    median, p90 = np.percentile(extents, [50, 90])
    return {"frames": int(extents.size), "frame_short_side_px": int(short_side),
            "input_short_side_px": config.resize, "frame_median_px": round(float(median), 2),
            "frame_p90_px": round(float(p90), 2),
            "input_median_px": round(float(median * scale), 2),
            "input_p90_px": round(float(p90 * scale), 2)}  # fmt: skip


def paper_table_rows(
    summaries: list[dict], scenes: list[str], item: str, method: str, condition: str
) -> list[dict]:
    """A table in the paper's columns: per scene, the measured LSTM row beside the printed one.

    Parameters
    ----------
    summaries : list of dict
        Rows of :func:`run_pose_matrix`.
    scenes : list of str
        Scene names, in the table's order.
    item : str
        The printed table, ``table1`` or ``table2``.
    method : str
        The printed method, e.g. ``proposed_blurred``.
    condition : str
        The measured condition (LSTM head) set beside it, e.g. ``blurred`` or ``rnn``.

    Returns
    -------
    list of dict
        Two rows per scene (``source`` ``measured`` then ``paper``) with ``mae``, ``mse``,
        ``rmse`` (eq. 15-17 over the pose vector) and ``combined`` (eq. 14, beta 0.8); measured
        values rounded to 4 decimals, printed ones as printed (None where not printed).

    References
    ----------
    Tables I-II and eq. 14-17 of the paper.
    """
    metrics = ("mae", "mse", "rmse", "combined")
    measured = {metric: per_scene(summaries, condition, "lstm", metric) for metric in metrics}
    printed = {metric: paper_values(item, metric, method) for metric in metrics}
    rows = []
    for scene in scenes:
        measured_row = {metric: round(measured[metric][scene], 4) for metric in metrics}
        rows.append({"scene": scene, "source": "measured"} | measured_row)
        rows.append({"scene": scene, "source": "paper"}
                    | {metric: printed[metric].get(scene) for metric in metrics})  # fmt: skip
    return rows


def median_step(positions: np.ndarray) -> float:
    """The median distance between consecutive camera positions: how smooth a path is.

    Parameters
    ----------
    positions : numpy.ndarray
        Camera positions (N, 3), metres, in frame order.

    Returns
    -------
    float
        Median of the N - 1 step lengths, metres.
    """
    return float(np.median(np.linalg.norm(np.diff(positions, axis=0), axis=1)))
