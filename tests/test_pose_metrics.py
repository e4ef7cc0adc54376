"""Pose errors of eq. 12-17 on a PosePair, TUM trajectories, their association and pose-error."""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from blurloc.cli import main
from blurloc.data import DataError
from blurloc.geometry import frame_to_frame_motion, rotation_defect, rotation_to_quaternion
from blurloc.metrics import combined_errors, orientation_errors_deg, pose_summary, position_errors
from blurloc.poses import PosePair
from blurloc.trajectory import associate, compare_trajectories, read_tum, write_tum


def _random_pair(count: int, seed: int) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    true_p, est_p = rng.normal(size=(count, 3)), rng.normal(size=(count, 3))
    true_q = rng.normal(size=(count, 4)) * rng.uniform(0.5, 2.0, (count, 1))  # any norm and sign
    est_q = rng.normal(size=(count, 4))
    return true_p, true_q, est_p, est_q


def _old_pose_summary(true_p, true_q, est_p, est_q, beta):  # the formulas before PosePair
    def hemisphere(q):
        q = q / np.linalg.norm(q, axis=-1, keepdims=True)
        return q * np.where(q[:, :1] < 0, -1.0, 1.0)

    position = np.linalg.norm(est_p - true_p, axis=-1)
    dot = np.abs(np.sum(true_q * est_q, axis=-1)) / (
        np.linalg.norm(true_q, axis=-1) * np.linalg.norm(est_q, axis=-1)
    )
    orientation = np.degrees(2.0 * np.arccos(np.clip(dot, 0.0, 1.0)))
    residual = np.concatenate([est_p - true_p, hemisphere(est_q) - hemisphere(true_q)], axis=1)
    combined = position + beta * np.linalg.norm(hemisphere(est_q) - hemisphere(true_q), axis=1)
    return position, orientation, residual, combined


def test_pose_summary_equals_the_former_formulas_on_random_poses() -> None:
    true_p, true_q, est_p, est_q = _random_pair(500, seed=4)
    position, orientation, residual, combined = _old_pose_summary(true_p, true_q, est_p, est_q,
                                                                  0.8)  # fmt: skip
    pair = PosePair(true_p, true_q, est_p, est_q)
    summary = pose_summary(pair, beta=0.8)
    np.testing.assert_allclose(orientation_errors_deg(pair), orientation, atol=1e-9)
    np.testing.assert_allclose(combined_errors(pair, 0.8), combined, atol=1e-9)
    expected = {"mae": np.mean(np.abs(residual)), "mse": np.mean(residual**2),
                "rmse": np.sqrt(np.mean(residual**2)), "combined": np.mean(combined)}  # fmt: skip
    for key, value in expected.items():
        assert summary[key] == pytest.approx(value, abs=1e-9), key
    for key, values in (("position_m", position), ("orientation_deg", orientation)):
        assert summary[key]["median"] == pytest.approx(np.median(values), abs=1e-9)
        assert summary[key]["rmse"] == pytest.approx(np.sqrt(np.mean(values**2)), abs=1e-9)


def test_orientation_error_is_the_angle_of_eq_13() -> None:
    a = Rotation.random(50, random_state=1)
    b = Rotation.random(50, random_state=2)
    trace = np.einsum("nji,nji->n", a.as_matrix(), b.as_matrix())
    from_trace = np.degrees(np.arccos(np.clip((trace - 1.0) / 2.0, -1.0, 1.0)))
    pair = PosePair(
        np.zeros((50, 3)),
        rotation_to_quaternion(a.as_matrix()),
        np.zeros((50, 3)),
        -rotation_to_quaternion(b.as_matrix()),
    )  # q and -q: the same rotation
    np.testing.assert_allclose(orientation_errors_deg(pair), from_trace, atol=1e-6)
    turn = Rotation.from_rotvec([0, 0, np.radians(7.0)])
    poses = np.tile(np.eye(4), (2, 1, 1))
    poses[1, :3, :3] = (a[0] * turn).as_matrix()
    poses[0, :3, :3] = a[0].as_matrix()
    poses[1, :3, 3] = [3.0, 4.0, 0.0]
    steps, angles = frame_to_frame_motion(poses)
    assert steps[0] == pytest.approx(5.0) and angles[0] == pytest.approx(7.0)


def test_pose_summary_on_a_known_residual() -> None:
    true_q = np.tile([1.0, 0, 0, 0], (4, 1))
    est_p = np.array([[0.1, 0, 0], [0.3, 0, 0], [1.0, 0, 0], [6.0, 0, 0]])
    est_q = rotation_to_quaternion(Rotation.from_rotvec(
        np.radians([[1, 0, 0], [4, 0, 0], [8, 0, 0], [1, 0, 0]])).as_matrix())  # fmt: skip
    pair = PosePair(np.zeros((4, 3)), true_q, est_p, est_q)
    summary = pose_summary(pair, beta=0.8)
    np.testing.assert_allclose(position_errors(pair), [0.1, 0.3, 1.0, 6.0])
    assert summary["position_m"]["median"] == pytest.approx(0.65)
    assert summary["orientation_deg"]["mean"] == pytest.approx(3.5)
    assert summary["within_0.25m_2deg"] == 0.25
    assert summary["within_0.5m_5deg"] == 0.5


def test_a_mirror_is_named_as_not_a_rotation() -> None:
    assert rotation_defect(np.eye(3)) is None
    assert rotation_defect(np.diag([1.0, 1.0, -1.0])) == "not a rotation: determinant -1"
    assert rotation_defect(np.eye(3) * 1.1).startswith("not orthonormal")


def test_tum_round_trip_and_association(tmp_path: Path) -> None:
    poses = np.tile(np.eye(4), (3, 1, 1))
    poses[:, :3, :3] = Rotation.random(3, random_state=3).as_matrix()
    poses[:, :3, 3] = [[0, 0, 0], [1, 2, 3], [-1, 0.5, 2]]
    write_tum(tmp_path / "a.txt", np.array([0.0, 0.1, 0.2]), poses)
    stamps, positions, quaternions = read_tum(tmp_path / "a.txt")
    np.testing.assert_allclose(stamps, [0.0, 0.1, 0.2])
    np.testing.assert_allclose(positions, poses[:, :3, 3], atol=1e-6)
    np.testing.assert_allclose(quaternions, rotation_to_quaternion(poses[:, :3, :3]), atol=1e-7)
    assert np.all(quaternions[:, 0] >= 0)
    # greedy, closest first, each used once: 0.104 goes to 0.1, so 0.095 is left unmatched
    assert associate([0.0, 0.1, 0.2], [0.104, 0.095, 0.2049], 0.01) == [(1, 0), (2, 2)]
    shifted = poses.copy()
    shifted[:, 0, 3] += 0.5
    write_tum(tmp_path / "b.txt", np.array([0.001, 0.1, 0.205]), shifted)
    result = compare_trajectories(tmp_path / "a.txt", tmp_path / "b.txt")
    assert result["frames"] == 3
    assert result["position_m"]["median"] == pytest.approx(0.5, abs=1e-5)
    assert result["orientation_deg"]["rmse"] == pytest.approx(0.0, abs=1e-3)


def _greedy_by_table(a: np.ndarray, b: np.ndarray, limit: float) -> list[tuple[int, int]]:
    difference = np.abs(a[:, None] - b[None, :])  # the N x M rule of TUM's associate.py
    candidates = np.argwhere(difference < limit)
    order = np.argsort(difference[candidates[:, 0], candidates[:, 1]], kind="stable")
    used_a, used_b, pairs = set(), set(), []
    for i, j in candidates[order].tolist():
        if i not in used_a and j not in used_b:
            used_a.add(i)
            used_b.add(j)
            pairs.append((i, j))
    return sorted(pairs)


def test_association_by_sorted_search_is_the_greedy_rule_and_scales() -> None:
    rng = np.random.default_rng(5)
    for _ in range(200):
        a, b = rng.random(rng.integers(0, 25)) * 3, rng.random(rng.integers(0, 25)) * 3
        limit = float(rng.choice([0.01, 0.05, 0.3, 5.0]))
        assert associate(a, b, limit) == _greedy_by_table(a, b, limit)
    stamps = np.arange(30_000) / 30.0
    start = time.perf_counter()
    pairs = associate(stamps, stamps + rng.normal(0, 0.003, stamps.size), 0.01)
    assert time.perf_counter() - start < 1.0  # the N x M table took 38 s and 14 GB
    assert len(pairs) > 29_000
    with pytest.raises(ValueError, match="distinct"):
        associate([0.0, 0.0], [0.0], 0.01)


def test_a_repeated_stamp_keeps_its_first_pose_and_is_said_once(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    # as TUM RGB-D's fr2/desk ground truth: one stamp on two lines with slightly other poses
    (tmp_path / "truth.txt").write_text(
        "# timestamp tx ty tz qx qy qz qw\n"
        "1311868229.5460 0.10 0.20 0.30 0 0 0 1\n"
        "1311868229.5760 0.11 0.20 0.30 0 0 0 1\n"
        "1311868229.5760 0.12 0.20 0.30 0 0 0 1\n"
        "1311868229.6060 0.13 0.20 0.30 0 0 0 1\n"
    )
    with pytest.warns(UserWarning, match=r"1 line\(s\) repeat .*first: 1311868229\.576\)"):
        stamps, positions, _ = read_tum(tmp_path / "truth.txt")
    np.testing.assert_array_equal(stamps, [1311868229.546, 1311868229.576, 1311868229.606])
    np.testing.assert_allclose(positions[:, 0], [0.10, 0.11, 0.13])  # the first line is kept
    assert main(["pose-error", str(tmp_path / "truth.txt"), str(tmp_path / "truth.txt")]) == 0
    warned = [line for line in capsys.readouterr().err.splitlines() if "repeat" in line]
    assert len(warned) == 2  # once per file read (here the same file twice)
    write_tum(tmp_path / "copy.txt", stamps, np.tile(np.eye(4), (3, 1, 1)))
    assert (tmp_path / "copy.txt").read_text().split()[0] == "1311868229.546"  # not 1.31187e+09
    np.testing.assert_array_equal(read_tum(tmp_path / "copy.txt")[0], stamps)


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("0 0 0 0 0 0 0 0\n", "norm 0.0000 is not 1"),
        ("0 0 0 0 0 0 0 2\n", "is not 1"),
        ("0 0 0 0 0 0 1\n", "8 finite values"),
        ("0 0 0 nan 0 0 0 1\n", "8 finite values"),
        ("# only a comment\n", "no poses"),
    ],
)
def test_bad_trajectory_files(tmp_path: Path, content: str, message: str) -> None:
    (tmp_path / "t.txt").write_text(content)
    with pytest.raises(DataError, match=message):
        read_tum(tmp_path / "t.txt")


def test_trajectories_without_matching_stamps(tmp_path: Path) -> None:
    write_tum(tmp_path / "a.txt", np.array([0.0, 1.0]), np.tile(np.eye(4), (2, 1, 1)))
    write_tum(tmp_path / "b.txt", np.array([0.5, 1.5]), np.tile(np.eye(4), (2, 1, 1)))
    with pytest.raises(DataError, match="no timestamp matches"):
        compare_trajectories(tmp_path / "a.txt", tmp_path / "b.txt")


def test_pose_error_names_the_file_or_option_on_bad_input(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    good = write_tum(tmp_path / "a.txt", np.array([0.0, 1.0]), np.tile(np.eye(4), (2, 1, 1)))
    (tmp_path / "binary.txt").write_bytes(bytes(range(256)))
    (tmp_path / "folder").mkdir()
    cases = [
        ([str(tmp_path / "folder"), str(good)], "folder: a folder, but not a 7-Scenes sequence"),
        ([str(good), str(tmp_path / "binary.txt")], "binary.txt: not a text file"),
        ([str(good), str(good), "--max-difference", "0"], "--max-difference must be a positive"),
        ([str(good), str(good), "--max-difference", "nan"], "--max-difference must be a positive"),
    ]
    for argv, message in cases:
        assert main(["pose-error", *argv]) == 1
        error = capsys.readouterr().err
        assert message in error and len(error.strip().splitlines()) == 1, error
    assert main(["pose-error", str(good), str(good)]) == 0
    assert json.loads(capsys.readouterr().out)["frames"] == 2
