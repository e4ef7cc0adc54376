"""The pose experiments of notebooks 04-05: the matrix of trainings (per scene, train on one kind
of input frames, blurred, blind-Wiener, network-deblurred or sharp, with one head, test on the
same kind), the mean-pose baseline, a saved model's per-frame predictions, and the tables built
from the matrix's summaries (the overview, Tables I-II beside the paper, the long sequences)."""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation
from tqdm.auto import tqdm

from ..data.scenes import REAL_MEAN_POSE_BASELINE
from ..data.sevenscenes import list_scenes, load_split
from ..inference import load_pose_model, predict_poses
from ..metrics import combined_errors, orientation_errors_deg, pose_summary, position_errors
from ..paper import paper_values
from ..poses import PosePair, to_quaternions
from ..train.config import PoseTrainConfig
from ..train.pose import train_pose

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
    progress: bool = False,
) -> tuple[list[dict], list[dict]]:
    """Train and test every (condition, head) of ``runs`` on every scene.

    Parameters
    ----------
    roots : dict
        ``{condition: root}`` (:func:`condition_roots`).
    scenes : list of str
        Scene names.
    runs : list of (str, str)
        (condition, head) pairs; ``sharp`` trains and tests on the sharp renders.
    config : PoseTrainConfig
        Training settings shared by every run (the head is replaced per run).
    out_dir : str or os.PathLike
        Models go to ``out_dir/<condition>/<head>/<scene>``.
    progress : bool
        Show a progress bar over the runs.

    Returns
    -------
    summaries : list of dict
        One row per run and scene: scene, condition, head, train_seconds and
        :func:`~blurloc.metrics.pose_summary` flattened (``position_m_median``, ...).
    frames : list of dict
        One row per test frame: scene, condition, head, index, position_m (eq. 12),
        orientation_deg (eq. 13) and combined (eq. 14).

    References
    ----------
    Eq. 12-17 of the paper; Tables I-II (blurred and deblurred inputs).
    """
    summaries, frames = [], []
    jobs = [(condition, head, scene) for condition, head in runs for scene in scenes]
    for condition, head, scene in tqdm(jobs, disable=not progress, desc="pose runs"):
        run_config = replace(config, image="sharp" if condition == "sharp" else "color",
                             model=replace(config.model, head=head))  # fmt: skip
        folder = Path(out_dir) / condition / head / scene
        history = train_pose(roots[condition], scene, folder, run_config, progress=False)
        model, _ = load_pose_model(folder / "best.pt")
        test = load_split(roots[condition], scene, "test")
        pair = predict_poses(model, test, run_config)
        summary = pose_summary(pair, config.beta)
        row = {"scene": scene, "condition": condition, "head": head,
               "train_seconds": round(history["seconds"][-1], 1)}  # fmt: skip
        for key, value in summary.items():
            if isinstance(value, dict):
                row.update({f"{key}_{stat}": v for stat, v in value.items()})
            else:
                row[key] = value
        summaries.append(row)
        position, orientation = position_errors(pair), orientation_errors_deg(pair)
        combined = combined_errors(pair, config.beta)
        for index in range(len(position)):
            frames.append({"scene": scene, "condition": condition, "head": head,
                           "index": index, "position_m": float(position[index]),
                           "orientation_deg": float(orientation[index]),
                           "combined": float(combined[index])})  # fmt: skip
    return summaries, frames


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
    train = np.concatenate([s.poses() for s in load_split(root, scene, "train")])
    test = np.concatenate([s.poses() for s in load_split(root, scene, "test")])
    reference = Rotation.from_matrix(test[:, :3, :3])
    mean_q = to_quaternions(Rotation.from_matrix(train[:, :3, :3]).mean())
    pair = PosePair(test[:, :3, 3], to_quaternions(reference),
                    np.tile(train[:, :3, 3].mean(axis=0), (len(test), 1)),
                    np.tile(mean_q, (len(test), 1)))  # fmt: skip
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
        training pose, :func:`mean_pose_baseline`) and ``real_position_m`` /
        ``real_orientation_deg`` (the same measure on the published 7-Scenes poses,
        :data:`blurloc.data.scenes.REAL_MEAN_POSE_BASELINE`; empty for other scene names).
    """
    rows = []
    for scene in list_scenes(root):
        summary = mean_pose_baseline(root, scene)
        real = REAL_MEAN_POSE_BASELINE.get(scene, ("", ""))
        rows.append({"scene": scene,
                     "position_m": round(summary["position_m"]["median"], 3),
                     "orientation_deg": round(summary["orientation_deg"]["median"], 1),
                     "real_position_m": real[0], "real_orientation_deg": real[1]})  # fmt: skip
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
    """One column of the matrix's summaries, per scene, for one (condition, head) run.

    Parameters
    ----------
    summaries : list of dict
        Rows of :func:`run_pose_matrix` (``scene``, ``condition``, ``head`` and the metrics).
    condition, head : str
        The run, e.g. ``("blurred", "lstm")``.
    key : str
        The column, e.g. ``position_m_median`` (eq. 12, metres), ``orientation_deg_median``
        (eq. 13, degrees), ``mae``/``mse``/``rmse`` (eq. 15-17) or ``combined`` (eq. 14).

    Returns
    -------
    dict
        ``{scene: value}`` in the rows' order.
    """
    return {row["scene"]: row[key] for row in summaries
            if row["condition"] == condition and row["head"] == head}  # fmt: skip


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


def pose_overview(
    summaries: list[dict], runs: list[tuple[str, str]], baseline: dict[str, dict]
) -> list[dict]:
    """The overview table: per run, the median errors averaged over scenes, then the mean
    training pose as the last row.

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
        ``condition``, ``head``, ``position_m`` (median eq. 12, metres, 3 decimals),
        ``orientation_deg`` (median eq. 13, degrees, 2 decimals) and ``combined`` (mean eq. 14,
        4 decimals), each averaged over the scenes.

    References
    ----------
    Eq. 12-14 of the paper.
    """
    rows = [{"condition": condition, "head": head,
             "position_m": round(scene_mean(summaries, condition, head, "position_m_median"), 3),
             "orientation_deg": round(scene_mean(summaries, condition, head,
                                                 "orientation_deg_median"), 2),
             "combined": round(scene_mean(summaries, condition, head, "combined"), 4)}
            for condition, head in runs]  # fmt: skip
    rows.append({"condition": "mean training pose", "head": "-",
                 "position_m": round(float(np.mean([b["position_m"]["median"]
                                                    for b in baseline.values()])), 3),
                 "orientation_deg": round(float(np.mean([b["orientation_deg"]["median"]
                                                         for b in baseline.values()])), 2),
                 "combined": round(float(np.mean([b["combined"]
                                                  for b in baseline.values()])), 4)})  # fmt: skip
    return rows


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


def long_sequence_rows(
    summaries: list[dict], baseline: dict[str, dict], train_frames: dict[str, int]
) -> list[dict]:
    """The table of the runs on longer sequences: one row per run and scene, then the mean
    training pose per scene.

    Parameters
    ----------
    summaries : list of dict
        Rows of :func:`run_pose_matrix`.
    baseline : dict
        ``{scene: mean_pose_baseline(...)}``.
    train_frames : dict
        ``{scene: number of training frames}``.

    Returns
    -------
    list of dict
        ``scene``, ``condition``, ``head``, ``train_frames``, ``train_seconds``,
        ``position_m`` (median eq. 12, 3 decimals), ``orientation_deg`` (median eq. 13,
        2 decimals), ``combined`` (mean eq. 14, 4 decimals); the baseline rows have empty
        ``train_frames`` and ``train_seconds``.
    """
    rows = [{"scene": r["scene"], "condition": r["condition"], "head": r["head"],
             "train_frames": train_frames[r["scene"]], "train_seconds": r["train_seconds"],
             "position_m": round(r["position_m_median"], 3),
             "orientation_deg": round(r["orientation_deg_median"], 2),
             "combined": round(r["combined"], 4)} for r in summaries]  # fmt: skip
    rows += [{"scene": s, "condition": "mean training pose", "head": "-", "train_frames": "",
              "train_seconds": "", "position_m": round(b["position_m"]["median"], 3),
              "orientation_deg": round(b["orientation_deg"]["median"], 2),
              "combined": round(b["combined"], 4)} for s, b in baseline.items()]  # fmt: skip
    return rows


def errors_text(rows: list[dict], scene: str, condition: str, head: str) -> str:
    """One row's median position / orientation error as text, e.g. ``0.412 m / 9.87°``.

    Parameters
    ----------
    rows : list of dict
        Rows with ``scene``, ``condition``, ``head``, ``position_m`` and ``orientation_deg``
        (:func:`long_sequence_rows`).
    scene, condition, head : str
        The row.

    Returns
    -------
    str
        Metres with 3 decimals, degrees with 2.

    Raises
    ------
    StopIteration
        If no row matches.
    """
    row = next(
        r for r in rows if r["scene"] == scene and r["condition"] == condition and r["head"] == head
    )
    return f"{row['position_m']:.3f} m / {row['orientation_deg']:.2f}°"


def condition_errors_text(summaries: list[dict], condition: str) -> str:
    """One condition's errors as text: the mean over scenes of the median position and
    orientation errors, LSTM then single frame, e.g. ``rnn: 0.412 m / 9.87° (LSTM), ...``.

    Parameters
    ----------
    summaries : list of dict
        Rows of :func:`run_pose_matrix` with the ``lstm`` and ``none`` heads of ``condition``.
    condition : str
        E.g. ``blurred``.

    Returns
    -------
    str
        Metres with 3 decimals (eq. 12), degrees with 2 (eq. 13).
    """
    return "{}: {:.3f} m / {:.2f}° (LSTM), {:.3f} m / {:.2f}° (single frame)".format(
        condition,
        *(scene_mean(summaries, condition, head, key) for head in ("lstm", "none")
          for key in ("position_m_median", "orientation_deg_median")),
    )  # fmt: skip


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


def paper_deblur_drop() -> float:
    """The paper's drop of the combined error from Table I (blurred) to Table II (deblurred).

    Returns
    -------
    float
        Mean over the printed scenes of Table I's combined error minus that of Table II.

    References
    ----------
    Tables I-II and eq. 14 of the paper.
    """
    return float(np.mean(list(paper_values("table1", "combined").values()))
                 - np.mean(list(paper_values("table2", "combined").values())))  # fmt: skip
