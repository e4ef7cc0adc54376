"""The blur dose-response: rows per strength, paired differences with t-intervals."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy import stats

import blurloc.experiments.dose as dose
from blurloc.data.synth import SynthConfig
from blurloc.experiments.dose import blur_dose_response, dose_response_table
from blurloc.train.config import PoseTrainConfig


def _row(strength: float, condition: str, seed: int, position: float) -> dict:
    return {"blur_strength": strength, "frame_median_blur_px": 3.0 * strength,
            "input_median_blur_px": 1.6 * strength, "scene": "chess", "seed": seed,
            "condition": condition, "head": "lstm", "position_m_median": position,
            "orientation_deg_median": 10 * position}  # fmt: skip


def test_the_table_pairs_inputs_by_seed_at_each_strength() -> None:
    blurred = [0.30, 0.40, 0.35]
    deblurred = [0.25, 0.34, 0.30]  # lower in every seed at the second strength
    rows = [_row(0.0, c, s, 0.2) for c in ("blurred", "rnn") for s in range(3)]
    rows += [_row(2.0, "blurred", s, v) for s, v in enumerate(blurred)]
    rows += [_row(2.0, "rnn", s, v) for s, v in enumerate(deblurred)]
    rows[1]["position_m_median"] = 0.21  # seeds differ a little with no blur
    table = dose_response_table(rows)
    assert [r["blur_strength"] for r in table] == [0.0, 2.0]
    second = table[1]
    differences = np.subtract(deblurred, blurred)
    half = stats.t.ppf(0.975, 2) * differences.std(ddof=1) / np.sqrt(3)
    assert second["pairs"] == 3 and second["frame_median_blur_px"] == 6.0
    assert second["blurred_position_m"] == pytest.approx(np.mean(blurred))
    assert second["position_difference_m"] == pytest.approx(differences.mean())
    assert second["position_ci_low"] == pytest.approx(differences.mean() - half)
    assert second["orientation_difference_deg"] == pytest.approx(10 * differences.mean())
    assert second["position_verdict"] == "reproduced"


def test_every_strength_is_rendered_with_the_same_seed_and_trained_on_both_inputs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    calls = []

    def fake_synthesize(root, scenes, seed, progress, config):
        calls.append(("render", Path(root).name, config.blur_strength, seed))
        return Path(root)

    def fake_matrix(roots, scenes, runs, config, out_dir, seeds, workers):
        calls.append(("train", sorted(roots), runs, seeds))
        return [{"scene": "chess", "seed": s, "condition": c, "head": h}
                for c, h in runs for s in seeds], []  # fmt: skip

    monkeypatch.setattr(dose, "synthesize", fake_synthesize)
    monkeypatch.setattr(dose, "write_deblurred_root", lambda root, out, method, workers: Path(out))
    monkeypatch.setattr(
        dose, "blur_at_input", lambda root, config: {"frame_median_px": 1.0, "input_median_px": 0.5}
    )
    monkeypatch.setattr(dose, "run_pose_matrix", fake_matrix)
    rows = blur_dose_response(
        tmp_path,
        ["chess"],
        (0.0, 4.4),
        SynthConfig.quick(),
        PoseTrainConfig(),
        lambda f: f,
        seeds=(1, 2),
        seed=7,
    )
    assert [c for c in calls if c[0] == "render"] == [
        ("render", "blur-0", 0.0, 7),
        ("render", "blur-4.4", 4.4, 7),
    ]
    assert all(c[1:] == (["blurred", "rnn"], [("blurred", "lstm"), ("rnn", "lstm")], (1, 2))
               for c in calls if c[0] == "train")  # fmt: skip
    assert len(rows) == 8 and {r["blur_strength"] for r in rows} == {0.0, 4.4}
    assert rows[0]["input_median_blur_px"] == 0.5
