"""The pose experiments of notebooks 04-05: what the matrix and the mean-pose baseline return."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import blurloc.experiments.pose as pose_experiments
from blurloc.data import load_split
from blurloc.experiments.pose import condition_roots, mean_pose_baseline, run_pose_matrix
from blurloc.metrics import ACCURACY_THRESHOLDS
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

    def fake_train(root, scene, folder, config, progress):
        trained.append((root, scene, Path(folder), config.image, config.model.head))
        return {"seconds": [12.34]}

    def fake_predict(model, sequences, config):
        return PosePair(truth[:, :3, 3], true_q, truth[:, :3, 3] + shift, true_q)

    monkeypatch.setattr(pose_experiments, "train_pose", fake_train)
    monkeypatch.setattr(pose_experiments, "load_pose_model", lambda path: (None, None))
    monkeypatch.setattr(pose_experiments, "predict_poses", fake_predict)
    roots = {"blurred": quick_root, "sharp": quick_root}
    runs = [("blurred", "lstm"), ("sharp", "none")]
    summaries, frames = run_pose_matrix(roots, ["chess"], runs, PoseTrainConfig(), tmp_path)
    assert [(t[2], t[3], t[4]) for t in trained] == [
        (tmp_path / "blurred" / "lstm" / "chess", "color", "lstm"),
        (tmp_path / "sharp" / "none" / "chess", "sharp", "none"),
    ]
    assert [(r["condition"], r["head"]) for r in summaries] == runs
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
    assert len(frames) == 2 * count
    assert [f["index"] for f in frames[:count]] == list(range(count))
    assert all(f["position_m"] == pytest.approx(0.5) for f in frames)
