"""The Wiener oracle runs on stand-in frames, the NSR rule's fit, and the estimation tables."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from blurloc.blur import blur_image
from blurloc.data import load_split, read_image
from blurloc.data.sevenscenes import read_depth
from blurloc.data.synth import exposure_tracks, sequence_trajectory
from blurloc.deconv import NSR_COEFFICIENT, NSR_EXPONENT
from blurloc.experiments.blur_estimation import (
    estimation_rows,
    estimation_summary,
    length_training_set,
    photo_training_set,
)
from blurloc.experiments.estimation import PHOTOS, crop_photo, photo_crops
from blurloc.experiments.wiener_oracles import (
    MEAN_KEPT,
    SKIMAGE_BALANCES,
    VARIANTS,
    _restore,
    exposure_kernel,
    fit_nsr_rule,
    oracle_rows,
    oracle_scene_table,
    oracle_summary,
    random_kernel,
    skimage_comparison,
    standin_settings,
)
from blurloc.geometry import intrinsics
from blurloc.images import as_float_image, linear_to_srgb, srgb_to_linear
from blurloc.metrics import psnr


def test_nsr_rule_fit_on_photographs() -> None:
    crops = [crop[::2, ::2] for crop in photo_crops(3, 256, seed=1)]
    a, b, rows = fit_nsr_rule(crops, [6.0, 10.0], [0.005, 0.02], seed=0)
    assert len(rows) == 12
    assert all(r["best_psnr_db"] >= r["rule_psnr_db"] - 0.05 for r in rows)  # an oracle
    assert 0.3 < b < 1.2  # more noise, more regularisation
    shipped = NSR_COEFFICIENT * 0.01**NSR_EXPONENT
    assert shipped / 2.5 < a * 0.01**b < shipped * 2.5
    with pytest.raises(ValueError, match="two noise levels"):
        fit_nsr_rule(crops[:1], [6.0], [0.01])


def test_skimage_comparison_scores_both_filters_and_the_oracle_nsr() -> None:
    crops = photo_crops(2, 128, seed=3)
    rows = skimage_comparison(crops, ["line", "camera shake"], 1, np.random.default_rng(0),
                              oracle_nsr=True)  # fmt: skip
    assert [(r["image"], r["kernel"]) for r in rows] == [
        (0, "line"),
        (0, "camera shake"),
        (1, "line"),
        (1, "camera shake"),
    ]
    for row in rows:  # textured photographs: Wiener deblurs; the oracle is at least as good
        assert row["ours_db"] > row["blurred_db"] + 1.0
        assert np.isfinite(row["skimage_best_balance_db"]) and np.isfinite(row["skimage_padded_db"])
        assert {row["skimage_balance"], row["skimage_padded_balance"]} <= set(SKIMAGE_BALANCES)
        assert row["best_nsr_db"] >= row["ours_db"] - 0.05
    with pytest.raises(ValueError, match="kind must be one of"):
        random_kernel("disk", np.random.default_rng(0))


def test_crops_cycle_through_sharp_photographs_only() -> None:
    assert [crop_photo(i) for i in (0, 1, len(PHOTOS))] == [PHOTOS[0], PHOTOS[1], PHOTOS[0]]
    assert "clock" not in PHOTOS  # scikit-image's clock photograph is itself motion-blurred


def test_true_path_kernel_explains_the_blurred_frame(quick_root: Path) -> None:
    config, seed = standin_settings(quick_root)
    sequence = load_split(quick_root, "chess", "test")[0]
    world, trajectory = sequence_trajectory("chess", sequence.number, config, seed)
    camera = intrinsics(config.width, config.height)
    for frame in sequence.frame_ids[:3]:
        sharp = as_float_image(read_image(sequence.path(frame, "sharp")))
        blurred = as_float_image(read_image(sequence.path(frame, "color")))
        tracks = exposure_tracks(world, trajectory, frame / config.fps, config, camera,
                                 read_depth(sequence.path(frame, "depth")), samples=17)  # fmt: skip
        kernel = exposure_kernel(tracks)
        assert kernel.sum() == pytest.approx(1.0)
        reblurred = linear_to_srgb(np.clip(blur_image(srgb_to_linear(sharp), kernel), 0, 1))
        mirrored = linear_to_srgb(np.clip(blur_image(srgb_to_linear(sharp), kernel[::-1, ::-1]),
                                          0, 1))  # fmt: skip
        assert psnr(blurred, reblurred, 1.0) >= psnr(blurred, sharp, 1.0) + 1.0
        assert psnr(blurred, reblurred, 1.0) >= psnr(blurred, mirrored, 1.0) - 0.1


def test_oracle_rows_and_tables(quick_root: Path) -> None:
    rows = oracle_rows(quick_root, "test", budget=3)  # every 4th of the 12 test frames
    frames = {(r["scene"], r["frame"]) for r in rows}
    assert len(frames) == 3  # chess frames 0 and 4, stairs (half as long) frame 0
    assert len(rows) == len(frames) * (len(VARIANTS) + 1)
    for key in frames:
        by = {r["variant"]: r for r in rows if (r["scene"], r["frame"]) == key}
        for kernel in ("line", "path", "path_linear"):  # the best NSR is an oracle
            assert by[f"{kernel}_best"]["psnr_db"] >= by[f"{kernel}_rule"]["psnr_db"] - 0.05
    summary = oracle_summary(rows)
    assert [r["variant"] for r in summary] == ["blurred", *VARIANTS]
    assert summary[0]["gain_db"] == 0.0
    table = oracle_scene_table(rows)
    assert [r["scene"] for r in table] == ["chess", "stairs", "mean"]
    assert table[0]["paper_psnr_db"] == pytest.approx(29.76)
    assert table[-1]["blurred_psnr_db"] == pytest.approx(
        np.mean([table[0]["blurred_psnr_db"], table[1]["blurred_psnr_db"]]), abs=1e-3
    )


def test_estimation_rows_against_recorded_blur(quick_root: Path) -> None:
    rows = estimation_rows(quick_root, "test")
    assert len(rows) == 24  # 8 chess frames, 4 stairs frames, each with its sharp render
    assert [r["kind"] for r in rows[:2]] == ["color", "sharp"] and rows[1]["extent_px"] == 0.0
    assert all(0 <= r["estimated_angle_deg"] < 180 and r["estimated_length_px"] >= 0 for r in rows)
    summary = {r["measure"]: r for r in estimation_summary(rows)}
    assert summary["median angle error (deg), extent >= 4 px"]["target"] == "<= 10"
    assert all(isinstance(r["met"], bool) for r in summary.values())
    assert summary["Spearman(estimated length, recorded extent)"]["frames"] == 12
    assert summary["passed, extent < 1 px and sharp renders"]["frames"] >= 12


def test_length_training_examples(quick_root: Path) -> None:
    features, extents = length_training_set(quick_root, "train", sharp_every=4)
    assert features.shape == (12 + 3, 78)  # 8 + 4 frames, sharp renders of frames 0, 4 and 0
    assert (extents == 0).sum() >= 3 and (extents > 0).sum() >= 10
    # rows: frame 0, its sharp render, frames 1-4, frame 4's sharp render, ...
    assert extents[1] == 0 and extents[6] == 0 and extents[0] > 0
    assert features[6][60] > features[1][60] + 0.2  # log noise σ: frame 4's sharp render is noisy
    photo_features, photo_extents = photo_training_set(count=12, seed=1)
    assert photo_features.shape == (12, 78) and (photo_extents >= 0).all()
    assert 0 < (photo_extents == 0).sum() < 12 and photo_extents.max() <= 25.0


def test_the_mean_kept_variant_is_eq_4_with_the_blurred_frames_mean() -> None:
    rng = np.random.default_rng(1)
    blurred = 0.3 + 0.4 * rng.random((48, 64, 3))  # no clipping: restorations stay in [0, 1]
    kernel = np.full((1, 5), 0.2)
    eq4 = _restore(blurred, kernel, 0.2, False)
    kept = _restore(blurred, kernel, 0.2, False, MEAN_KEPT)
    assert abs(eq4.mean() - blurred.mean()) > 0.05  # a constant NSR of 0.2 darkens by a sixth
    np.testing.assert_allclose(kept.mean(axis=(0, 1)), blurred.mean(axis=(0, 1)), atol=1e-6)
    np.testing.assert_allclose(kept - kept.mean(axis=(0, 1)), eq4 - eq4.mean(axis=(0, 1)),
                               atol=1e-6)  # fmt: skip
