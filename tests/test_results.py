"""What notebook 05 assembles: model paths, Table III rows, the Fig. 2 frame and panels, the
Fig. 5 views, and the measured/printed summaries of the comparison table."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from blurloc.blur import detect_blur
from blurloc.data import load_split, read_image
from blurloc.experiments import results
from blurloc.experiments.pose import mean_pose_baseline
from blurloc.reproduction import proposed_measured_vs_printed, ratios_by_item


def test_model_path_follows_notebook_04_layout(tmp_path: Path) -> None:
    path = results.model_path(tmp_path, "wiener", "lstm", "fire", seed=3)
    assert path == tmp_path / "pose_models" / "wiener" / "lstm" / "fire" / "seed-3" / "best.pt"


def test_scene_predictions_loads_the_condition_model_on_its_frames(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    calls = []
    monkeypatch.setattr(results, "predict_test_frames", lambda *args: calls.append(args) or {})
    roots = {"rnn": tmp_path / "rnn", "blurred": tmp_path / "blurred"}
    results.scene_predictions(tmp_path, roots, "rnn", "none", "heads")
    assert calls == [(results.model_path(tmp_path, "rnn", "none", "heads"), roots["rnn"], "heads")]


def test_measured_pose_picks_its_training_and_averages_the_scene_medians() -> None:
    summary = [
        {"scene": s, "condition": c, "head": h, "position_m_median": str(p),
         "orientation_deg_median": str(o)}
        for s, c, h, p, o in (("chess", "rnn", "lstm", 0.2, 4.0), ("fire", "rnn", "lstm", 0.4, 8.0),
                              ("chess", "rnn", "none", 9.0, 90.0),
                              ("chess", "wiener", "lstm", 7.0, 70.0))
    ]  # fmt: skip
    rows = results.measured_pose(summary, "rnn", "lstm", ["chess", "fire"])
    assert rows["chess"] == (0.2, 4.0)
    assert rows["fire"] == (0.4, 8.0)
    assert rows["average"] == pytest.approx((0.3, 6.0))
    assert set(rows) == {"chess", "fire", "average"}


def test_baseline_pose_holds_the_mean_pose_medians(quick_root: Path) -> None:
    rows = results.baseline_pose(quick_root, ["chess", "stairs"])
    chess = mean_pose_baseline(quick_root, "chess")
    assert rows["chess"] == (chess["position_m"]["median"], chess["orientation_deg"]["median"])
    assert rows["average"] == pytest.approx(tuple(np.mean([rows["chess"], rows["stairs"]], 0)))


def test_pipeline_frame_is_a_flagged_frame_of_the_most_blurred(quick_root: Path) -> None:
    sequence = load_split(quick_root, "chess", "test")[0]
    frame_id, extents = results.pipeline_frame(sequence, is_standin=True)
    assert set(extents) == set(sequence.frame_ids)
    candidates = sorted(sequence.frame_ids, key=lambda i: -extents[i])[:10]
    flagged = [i for i in candidates if detect_blur(read_image(sequence.path(i)))[0]]
    assert frame_id == (flagged[0] if flagged else candidates[0])
    real_id, real_extents = results.pipeline_frame(sequence, is_standin=False)
    assert real_extents == {}
    assert real_id in sequence.frame_ids


def test_pipeline_panels_show_the_frame_and_the_sharp_render_on_the_standin(
    quick_root: Path,
) -> None:
    sequence = load_split(quick_root, "chess", "test")[0]
    frame_id = sequence.frame_ids[2]
    deblurred = {"wiener": sequence, "rnn": sequence}
    panels = results.pipeline_panels("chess", sequence, frame_id, {frame_id: 3.25}, deblurred,
                                     is_standin=True)  # fmt: skip
    assert len(panels) == 6
    np.testing.assert_array_equal(panels[0]["image"], read_image(sequence.path(frame_id)))
    assert f"frame {frame_id}, blur 3.2 px" in panels[0]["title"]
    np.testing.assert_array_equal(panels[-1]["image"], read_image(sequence.path(frame_id, "sharp")))
    real = results.pipeline_panels("chess", sequence, frame_id, {}, deblurred, is_standin=False)
    assert len(real) == 5
    assert "blur" not in real[0]["title"]


def _fake_result(root: Path, scene: str) -> dict:
    sequences = load_split(root, scene, "test")
    poses = np.concatenate([s.poses() for s in sequences])
    n = len(poses)
    return {"frames": [(s, i) for s in sequences for i in s.frame_ids],
            "position": poses[:, :3, 3].copy(), "quaternion": np.tile([1.0, 0, 0, 0], (n, 1)),
            "position_error": np.arange(n, dtype=float)[::-1],
            "orientation_error": np.arange(n, dtype=float) * 2.0}  # fmt: skip


def test_median_error_views_pick_the_median_frame(quick_root: Path) -> None:
    result = _fake_result(quick_root, "chess")
    n = len(result["frames"])
    k = int(np.argsort(result["position_error"])[n // 2])
    sequence, frame = result["frames"][k]
    views, caption = results.median_error_views(quick_root, "chess", result, is_standin=True)
    assert list(views) == ["input (blurred)", "deblurred (network)", "ground truth",
                           "rendered at prediction"]  # fmt: skip
    np.testing.assert_array_equal(views["ground truth"], read_image(sequence.path(frame, "sharp")))
    assert views["rendered at prediction"].shape == views["ground truth"].shape
    assert views["rendered at prediction"].dtype == np.uint8
    assert caption == f"{result['position_error'][k]:.2f} m, {result['orientation_error'][k]:.1f}°"


def test_median_error_views_on_real_data_show_the_nearest_training_frame(
    quick_root: Path,
) -> None:
    result = _fake_result(quick_root, "stairs")
    k = int(np.argsort(result["position_error"])[len(result["frames"]) // 2])
    train = load_split(quick_root, "stairs", "train")[0]
    result["position"][k] = train.poses()[3, :3, 3]
    views, _ = results.median_error_views(quick_root, "stairs", result, is_standin=False)
    assert "nearest training frame" in views
    np.testing.assert_array_equal(views["nearest training frame"],
                                  read_image(train.path(train.frame_ids[3])))  # fmt: skip
    np.testing.assert_array_equal(views["ground truth"], views["input (blurred)"])


def _row(
    item: str,
    metric: str,
    scene: str,
    measured: float | str,
    ratio: float | str,
    method: str = "Proposed",
    printed: float = 1.0,
) -> dict:
    return {"item": item, "metric": metric, "scene": scene, "method": method,
            "measured": measured, "ratio": ratio, "printed": printed}  # fmt: skip


def test_ratios_by_item_groups_only_measured_rows_in_first_appearance_order() -> None:
    comparison = [_row("table3", "position_m", "chess", 0.5, 2.0),
                  _row("fig6", "psnr_db", "chess", 30.0, 1.1),
                  _row("table3", "position_m", "fire", 0.25, 1.5),
                  _row("table3", "position_m", "heads", "", "", method="PoseNet")]  # fmt: skip
    groups = ratios_by_item(comparison)
    assert list(groups) == ["table3 · position_m", "fig6 · psnr_db"]
    assert groups["table3 · position_m"] == [2.0, 1.5]


def test_proposed_measured_vs_printed_reads_the_proposed_row() -> None:
    comparison = [_row("table3", "position_m", "average", 9.0, 1.0, method="PoseNet"),
                  _row("table3", "position_m", "average", 0.456, 2.0, printed=0.19),
                  _row("table3", "position_m", "chess", 0.1, 1.0, printed=0.14)]  # fmt: skip
    assert proposed_measured_vs_printed(comparison, "table3", "position_m") == "0.46 (printed 0.19)"
    assert proposed_measured_vs_printed(comparison, "table3", "position_m", "chess") == (
        "0.10 (printed 0.14)"
    )
