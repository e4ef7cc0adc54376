"""The video network's ablations: equal capacity, paired seeds, intervals and their verdicts."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from blurloc import plots
from blurloc.experiments.video_ablation import (
    ABLATED_PARTS,
    AblationRun,
    ablation_gains,
    ablation_intervals,
    equal_parameter_variants,
    train_ablations,
    training_health,
)
from blurloc.models.video_deblur import (
    VideoDeblurConfig,
    VideoDeblurNet,
    matched_blocks,
    parameter_count,
)
from blurloc.train.config import VideoTrainConfig


def _count(config: VideoDeblurConfig) -> int:
    return parameter_count(VideoDeblurNet(config))


def test_matched_blocks_picks_the_nearest_count_and_refuses_a_bad_target() -> None:
    single = VideoDeblurConfig(aux_state=False, blending=False, recurrent=False)
    target = _count(VideoDeblurConfig())
    matched = matched_blocks(single, target)
    assert matched.blocks > single.blocks  # it lost parameters, so it gets blocks back
    error = abs(_count(matched) - target)
    for blocks in (matched.blocks - 1, matched.blocks + 1):
        assert abs(_count(replace(single, blocks=blocks)) - target) >= error
    assert matched.recurrent is False and matched.aux_state is False  # switches kept
    with pytest.raises(ValueError, match="positive"):
        matched_blocks(single, 0)


def test_every_ablation_has_the_full_networks_parameter_count_within_two_percent() -> None:
    variants = equal_parameter_variants()
    assert list(variants) == ["full", *ABLATED_PARTS]
    full = _count(variants["full"])
    for name, config in variants.items():
        assert abs(_count(config) - full) <= 0.02 * full, name
    assert variants["single_frame"].recurrent is False
    assert variants["no_aux"].aux_state is False and variants["no_aux"].blending is True
    assert variants["no_blending"].blending is False and variants["no_blending"].aux_state is True


def test_intervals_pair_by_seed_and_word_the_verdict_from_the_interval() -> None:
    full = {0: 0.50, 1: 0.30, 2: 0.70}
    gains = {
        "full": full,
        "worse": {s: g - 0.20 + 0.01 * s for s, g in full.items()},  # always 0.18-0.20 lower
        "better": {s: g + 0.20 for s, g in full.items()},
        "noisy": {0: 0.90, 1: 0.00, 2: 0.60},
    }
    rows = {r["variant"]: r for r in ablation_intervals(gains, dict.fromkeys(gains, 100))}
    assert "minus_reference" not in rows["full"]
    assert rows["full"]["gain_min"] == pytest.approx(0.30)
    # paired: the seed-to-seed spread of ±0.2 dB cancels, so a steady 0.19 dB is resolved
    assert rows["worse"]["minus_reference"] == pytest.approx(-0.19)
    assert rows["worse"]["ci_high"] < 0 and rows["worse"]["verdict"] == "the part helps"
    assert rows["better"]["verdict"] == "the part hurts"
    assert rows["noisy"]["ci_low"] < 0 < rows["noisy"]["ci_high"]
    assert rows["noisy"]["verdict"].startswith("too small to resolve at this power (±")
    worded = ablation_intervals(gains, dict.fromkeys(gains, 100), below="lower", above="higher")
    assert [r.get("verdict") for r in worded][1:3] == ["lower", "higher"]
    with pytest.raises(ValueError, match="paired"):
        ablation_intervals({"full": full, "other": {0: 0.1, 1: 0.2}}, {"full": 1, "other": 1})
    with pytest.raises(ValueError, match="reference"):
        ablation_intervals({"other": full}, {"other": 1})


def test_training_health_flags_a_loss_spike_and_a_scored_network_from_before_a_collapse() -> None:
    def run(losses: list[float], psnr: list[float]) -> AblationRun:
        steps = [100 * (k + 1) for k in range(len(losses))]
        history = {"step": steps, "train_loss": losses, "val_psnr": psnr, "seconds": steps}
        return AblationRun("full", len(psnr), Path("."), history)

    steady = run([0.05, 0.03, 0.03, 0.02], [30.0, 31.0, 31.5, 31.6])
    # the collapse of a recurrent training: a spike, then validation low for good (NaN too)
    collapsed = run([0.04, 41.0, 0.04, 0.03], [30.5, 19.4, float("nan"), 19.4])
    healthy, broken = training_health([steady, collapsed])
    assert healthy["best_step"] == healthy["steps"] == 400 and not healthy["spike"]
    assert healthy["last_val_db"] == healthy["best_val_db"] == pytest.approx(31.6)
    assert broken["best_step"] == 100 and broken["steps"] == 400 and broken["spike"]
    assert broken["peak_loss_ratio"] == pytest.approx(41.0 / 0.04)
    assert broken["best_val_db"] - broken["last_val_db"] == pytest.approx(11.1)


def test_ablations_train_once_per_seed_and_score_against_the_blurred_input(
    quick_root: Path, tmp_path: Path
) -> None:
    small = VideoDeblurConfig(channels=8, hidden=4, blocks=1)
    variants = equal_parameter_variants(small)
    budget = VideoTrainConfig(steps=2, batch=2, clip_frames=3, crop=16, validate_every=2)
    runs = train_ablations(quick_root, variants, [0, 1], budget, tmp_path, workers=2)
    assert [(r.variant, r.seed) for r in runs] == [(v, s) for v in variants for s in (0, 1)]
    assert all((r.folder / "best.pt").is_file() and r.history["step"] == [2] for r in runs)
    # the finished runs are reused, not retrained
    again = train_ablations(quick_root, variants, [0, 1], budget, tmp_path, workers=2)
    assert [r.history for r in again] == [r.history for r in runs]
    with pytest.raises(ValueError, match="workers"):
        train_ablations(quick_root, variants, [0], budget, tmp_path, workers=0)
    gains, rows = ablation_gains(quick_root, runs, frames_per_sequence=3)
    # scored in two worker processes: the same gains (one thread each; float rounding only)
    spread, _ = ablation_gains(quick_root, runs[:2], frames_per_sequence=3, workers=2)
    assert spread["full"] == pytest.approx(gains["full"], abs=1e-4)
    assert set(gains) == set(variants) and all(set(g) == {0, 1} for g in gains.values())
    assert all("ssim" not in row for row in rows)  # the gains need PSNR only
    blurred = np.mean([r["psnr_db"] for r in rows if r["method"] == "blurred"])
    restored = [r["psnr_db"] for r in rows if r["method"] == "full-seed0"]
    # one scene in the quick stand-in: the gain is the restored mean minus the blurred mean
    assert gains["full"][0] == pytest.approx(np.mean(restored) - blurred, abs=1e-9)
    intervals = ablation_intervals(gains, dict.fromkeys(gains, 1))
    figure = plots.plot_ablation_intervals(gains, intervals)
    assert len(figure.axes) == 2
