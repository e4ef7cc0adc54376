"""The pose experiments of notebooks 04-05: what the matrix and the mean-pose baseline return."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import blurloc.experiments.pose as pose_experiments
from blurloc.data import load_split
from blurloc.data.stats import read_blur_metadata
from blurloc.experiments.pose import (
    baseline_beside_real,
    blur_at_input,
    condition_roots,
    learning_check,
    mean_pose_baseline,
    median_step,
    nearest_view_baseline,
    paper_table_rows,
    per_scene,
    pose_overview,
    run_pose_matrix,
    scene_mean,
    seed_spread,
)
from blurloc.metrics import ACCURACY_THRESHOLDS
from blurloc.models.pose import PoseConfig
from blurloc.paper import paper_values
from blurloc.poses import PosePair
from blurloc.train.config import PoseTrainConfig


def test_mean_pose_baseline_against_a_hand_computation(quick_root: Path) -> None:
    train = np.concatenate([s.poses() for s in load_split(quick_root, "chess", "train")])
    test = np.concatenate([s.poses() for s in load_split(quick_root, "chess", "test")])
    # the chordal L2 mean of the training rotations: the rotation nearest to their sum
    u, _, vt = np.linalg.svd(train[:, :3, :3].sum(axis=0))
    mean_rotation = u @ np.diag([1.0, 1.0, np.linalg.det(u @ vt)]) @ vt
    position = np.linalg.norm(test[:, :3, 3] - train[:, :3, 3].mean(axis=0), axis=1)
    trace = np.einsum("ij,nij->n", mean_rotation, test[:, :3, :3])
    orientation = np.degrees(np.arccos(np.clip((trace - 1.0) / 2.0, -1.0, 1.0)))
    summary = mean_pose_baseline(quick_root, "chess")
    assert summary["frames"] == len(test)
    assert summary["position_m"]["median"] == pytest.approx(np.median(position), abs=1e-9)
    assert summary["position_m"]["mean"] == pytest.approx(np.mean(position), abs=1e-9)
    assert summary["orientation_deg"]["median"] == pytest.approx(np.median(orientation), abs=1e-5)
    assert summary["orientation_deg"]["mean"] > 0


def test_nearest_view_baseline_picks_the_nearest_training_pose(quick_root: Path) -> None:
    train = np.concatenate([s.poses() for s in load_split(quick_root, "chess", "train")])
    test = np.concatenate([s.poses() for s in load_split(quick_root, "chess", "test")])
    train_rotations = Rotation.from_matrix(train[:, :3, :3])
    degrees = np.stack([np.degrees((Rotation.from_matrix(pose[:3, :3]).inv()
                                    * train_rotations).magnitude()) for pose in test])  # fmt: skip
    metres = np.linalg.norm(test[:, None, :3, 3] - train[None, :, :3, 3], axis=2)
    nearest = np.argmin(metres + degrees / pose_experiments.DEGREES_PER_METRE, axis=1)
    rows = np.arange(len(test))
    summary = nearest_view_baseline(quick_root, "chess")
    assert summary["position_m"]["median"] == pytest.approx(np.median(metres[rows, nearest]))
    assert summary["orientation_deg"]["median"] == pytest.approx(
        np.median(degrees[rows, nearest]), abs=1e-4
    )
    # weighing position only, it finds the nearest training position
    by_position = nearest_view_baseline(quick_root, "chess", degrees_per_metre=1e9)
    assert by_position["position_m"]["median"] == pytest.approx(np.median(metres.min(axis=1)))
    # weighing orientation only, it finds the best orientation of any training frame
    by_angle = nearest_view_baseline(quick_root, "chess", degrees_per_metre=1e-9)
    assert by_angle["orientation_deg"]["median"] == pytest.approx(
        np.median(degrees.min(axis=1)), abs=1e-4
    )
    with pytest.raises(ValueError, match="degrees_per_metre"):
        nearest_view_baseline(quick_root, "chess", degrees_per_metre=0)


def test_baseline_table_holds_the_real_baseline_and_the_oracle(quick_root: Path) -> None:
    rows = {row["scene"]: row for row in baseline_beside_real(quick_root)}
    assert set(rows) == set(pose_experiments.list_scenes(quick_root))
    chess = rows["chess"]
    assert chess["position_m"] == round(mean_pose_baseline(quick_root, "chess")["position_m"][
        "median"], 3)  # fmt: skip
    assert (chess["real_position_m"], chess["real_orientation_deg"]) == (0.82, 23.0)
    nearest = nearest_view_baseline(quick_root, "chess")["position_m"]["median"]
    assert chess["nearest_position_m"] == round(nearest, 3)
    assert chess["nearest_ratio"] == pytest.approx(nearest / chess["position_m"], abs=0.006)


def test_condition_roots(tmp_path: Path) -> None:
    roots = condition_roots(tmp_path / "data", tmp_path / "results")
    assert list(roots) == list(pose_experiments.CONDITIONS)
    assert roots["blurred"] == roots["sharp"] == tmp_path / "data"
    assert roots["rnn"] == tmp_path / "results" / "deblurred" / "rnn"


def test_pose_matrix_rows(
    quick_root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The matrix trains one model per (condition, head, scene) on the right frames and turns
    its test predictions into one summary row and one row per test frame."""
    trained = []
    truth = np.concatenate([s.poses() for s in load_split(quick_root, "chess", "test")])
    count = len(truth)
    true_q = Rotation.from_matrix(truth[:, :3, :3]).as_quat(canonical=True, scalar_first=True)
    shift = np.array([0.3, 0.0, 0.4])  # every prediction 0.5 m off, orientation exact

    def fake_train(root, scene, folder, config, progress, cache):
        trained.append((root, scene, Path(folder), config.image, config.model.head, config.seed,
                        cache))  # fmt: skip
        return {"seconds": [12.34]}

    def fake_predict(model, sequences, config, cache):
        return PosePair(truth[:, :3, 3], true_q, truth[:, :3, 3] + shift, true_q)

    monkeypatch.setattr(pose_experiments, "train_pose", fake_train)
    monkeypatch.setattr(pose_experiments, "load_pose_model", lambda path: (None, None))
    monkeypatch.setattr(pose_experiments, "predict_poses", fake_predict)
    roots = {"blurred": quick_root, "sharp": quick_root}
    runs = [("blurred", "lstm"), ("sharp", "none")]
    summaries, frames = run_pose_matrix(roots, ["chess"], runs, PoseTrainConfig(), tmp_path,
                                        seeds=(3, 7))  # fmt: skip
    assert [(t[2], t[3], t[4], t[5]) for t in trained] == [
        (tmp_path / "blurred" / "lstm" / "chess" / "seed-3", "color", "lstm", 3),
        (tmp_path / "blurred" / "lstm" / "chess" / "seed-7", "color", "lstm", 7),
        (tmp_path / "sharp" / "none" / "chess" / "seed-3", "sharp", "none", 3),
        (tmp_path / "sharp" / "none" / "chess" / "seed-7", "sharp", "none", 7),
    ]
    assert len({id(t[6]) for t in trained}) == 1  # one frame cache for all the scene's runs
    assert [(r["condition"], r["head"], r["seed"]) for r in summaries] == [
        (c, h, seed) for c, h in runs for seed in (3, 7)
    ]
    row = summaries[0]
    assert row["scene"] == "chess" and row["train_seconds"] == 12.3
    assert row["frames"] == count
    assert row["position_m_median"] == pytest.approx(0.5)
    assert row["orientation_deg_rmse"] == pytest.approx(0.0, abs=1e-6)
    assert row["combined"] == pytest.approx(0.5)
    assert row["mae"] == pytest.approx((0.3 + 0.4) / 7)
    # 0.5 m off: outside the 0.25 m threshold, inside the 5 m one (0.5 m itself is a tie)
    for (metres, degrees), share in zip(ACCURACY_THRESHOLDS[::2], (0.0, 1.0), strict=True):
        assert row[f"within_{metres:g}m_{degrees:g}deg"] == share
    assert len(frames) == 4 * count
    assert [f["index"] for f in frames[:count]] == list(range(count))
    assert {f["seed"] for f in frames} == {3, 7}
    assert all(f["position_m"] == pytest.approx(0.5) for f in frames)


def _summary(scene: str, condition: str, head: str, scale: float, seed: int = 0) -> dict:
    """A made-up row of run_pose_matrix, every error proportional to ``scale``."""
    return {"scene": scene, "seed": seed, "condition": condition, "head": head,
            "train_seconds": 1.0,
            "position_m_median": 0.1 * scale, "orientation_deg_median": 2.0 * scale,
            "mae": 0.01 * scale, "mse": 0.001 * scale, "rmse": 0.03 * scale,
            "combined": 0.123456 * scale}  # fmt: skip


SUMMARIES = [_summary("chess", "blurred", "lstm", 1.0), _summary("fire", "blurred", "lstm", 3.0),
             _summary("chess", "rnn", "lstm", 0.5), _summary("fire", "rnn", "lstm", 1.5),
             _summary("chess", "blurred", "none", 10.0)]  # fmt: skip
BASELINE = {scene: {"position_m": {"median": value}, "orientation_deg": {"median": 10 * value},
                    "combined": value / 2}
            for scene, value in (("chess", 1.0), ("fire", 2.0))}  # fmt: skip


def test_per_scene_and_scene_mean_select_one_run() -> None:
    assert per_scene(SUMMARIES, "blurred", "lstm", "combined") == pytest.approx(
        {"chess": 0.123456, "fire": 0.370368}
    )
    assert per_scene(SUMMARIES, "blurred", "none", "mae") == {"chess": pytest.approx(0.1)}
    assert per_scene(SUMMARIES, "sharp", "lstm", "mae") == {}
    assert scene_mean(SUMMARIES, "rnn", "lstm", "position_m_median") == pytest.approx(0.1)
    assert np.isnan(scene_mean(SUMMARIES, "sharp", "lstm", "mae"))


def test_seeds_are_averaged_per_scene_and_their_spread_reported() -> None:
    rows = [*SUMMARIES, _summary("chess", "blurred", "lstm", 3.0, seed=1),
            _summary("fire", "blurred", "lstm", 5.0, seed=1)]  # fmt: skip
    # chess: seeds 1.0 and 3.0 -> 2.0; fire: 3.0 and 5.0 -> 4.0 (times 0.1 m)
    assert per_scene(rows, "blurred", "lstm", "position_m_median") == pytest.approx(
        {"chess": 0.2, "fire": 0.4}
    )
    # the scene mean per seed: 0.2 (seed 0), 0.4 (seed 1): spread 0.1414
    assert seed_spread(rows, "blurred", "lstm", "position_m_median") == pytest.approx(
        np.std([0.2, 0.4], ddof=1)
    )
    assert seed_spread(SUMMARIES, "blurred", "lstm", "position_m_median") == 0.0
    as_text = [{k: str(v) for k, v in r.items()} for r in rows]  # as read back from CSV
    assert per_scene(as_text, "blurred", "lstm", "position_m_median") == pytest.approx(
        {"chess": 0.2, "fire": 0.4}
    )


def test_pose_overview_averages_scenes_and_ends_with_the_baseline() -> None:
    rows = pose_overview(SUMMARIES, [("blurred", "lstm"), ("rnn", "lstm")], BASELINE)
    assert [(r["condition"], r["head"]) for r in rows] == [
        ("blurred", "lstm"),
        ("rnn", "lstm"),
        ("mean training pose", "-"),
    ]
    assert rows[0] == {"condition": "blurred", "head": "lstm", "seeds": 1, "position_m": 0.2,
                       "position_m_sd": 0.0, "orientation_deg": 4.0, "orientation_deg_sd": 0.0,
                       "combined": 0.2469, "combined_sd": 0.0}  # fmt: skip
    assert rows[-1] == {"condition": "mean training pose", "head": "-", "seeds": "",
                        "position_m": 1.5, "position_m_sd": "", "orientation_deg": 15.0,
                        "orientation_deg_sd": "", "combined": 0.75, "combined_sd": ""}  # fmt: skip


def test_learning_check_divides_by_the_mean_pose() -> None:
    rows = learning_check(SUMMARIES, BASELINE, "rnn", "lstm")
    assert rows[1] == {"scene": "fire", "position_m": 0.15, "baseline_position_m": 2.0,
                       "position_ratio": pytest.approx(0.075, abs=0.006), "orientation_deg": 3.0,
                       "baseline_orientation_deg": 20.0, "orientation_ratio": 0.15}  # fmt: skip


def test_blur_at_input_scales_the_recorded_blur(quick_root: Path) -> None:
    config = PoseTrainConfig(resize=32, crop=28)
    blur = blur_at_input(quick_root, config)
    extents = [r["mean_px"] for r in read_blur_metadata(quick_root)]
    assert blur["frames"] == len(extents)
    assert blur["frame_median_px"] == pytest.approx(np.median(extents), abs=0.01)
    scale = 32 / blur["frame_short_side_px"]
    assert blur["input_median_px"] == pytest.approx(np.median(extents) * scale, abs=0.01)
    assert blur["input_p90_px"] > blur["input_median_px"]


def test_paper_table_rows_set_measured_beside_printed() -> None:
    rows = paper_table_rows(SUMMARIES, ["chess", "fire"], "table2", "proposed_deblurred", "rnn")
    assert [(r["scene"], r["source"]) for r in rows] == [
        ("chess", "measured"),
        ("chess", "paper"),
        ("fire", "measured"),
        ("fire", "paper"),
    ]
    assert rows[0] == {"scene": "chess", "source": "measured", "mae": 0.005, "mse": 0.0005,
                       "rmse": 0.015, "combined": 0.0617}  # fmt: skip
    assert rows[3]["combined"] == paper_values("table2", "combined", "proposed_deblurred")["fire"]
    assert list(rows[1]) == ["scene", "source", "mae", "mse", "rmse", "combined"]


def test_median_step() -> None:
    path = np.array([[0.0, 0, 0], [3, 4, 0], [3, 4, 1], [3, 4, 3]])
    assert median_step(path) == pytest.approx(2.0)


def test_matrix_in_two_processes_matches_the_serial_run(quick_root: Path, tmp_path: Path) -> None:
    """Spreading the runs over worker processes changes where they run, not what they give:
    with one thread per run either way, every summary and every per-frame error is the same,
    in the same order."""
    config = PoseTrainConfig(epochs=1, windows_per_epoch=4, resize=32, crop=28, window=2, batch=2,
                             threads=1, model=PoseConfig(hidden=8))  # fmt: skip
    runs = [("blurred", "lstm"), ("blurred", "none")]
    matrix = {workers: run_pose_matrix({"blurred": quick_root}, ["chess"], runs, config,
                                       tmp_path / f"workers-{workers}", (0, 1), workers=workers)
              for workers in (1, 2)}  # fmt: skip
    (serial, serial_frames), (parallel, parallel_frames) = matrix[1], matrix[2]
    drop = {"train_seconds"}
    assert [{k: v for k, v in r.items() if k not in drop} for r in parallel] == [
        {k: v for k, v in r.items() if k not in drop} for r in serial
    ]
    assert parallel_frames == serial_frames
    with pytest.raises(ValueError, match="workers"):
        run_pose_matrix({"blurred": quick_root}, ["chess"], runs, config, tmp_path, workers=0)
