"""Paired comparisons of experiment rows."""

from __future__ import annotations

import numpy as np
import pytest

from blurloc.experiments.comparisons import comparison_table, paired_differences


def rows(effect: float, noise: float = 0.01, seeds: int = 5) -> list[dict]:
    """Two conditions on 3 scenes x ``seeds`` seeds; ``rnn`` differs from ``blurred`` by
    ``effect`` plus noise; scenes differ a lot (which pairing must cancel)."""
    rng = np.random.default_rng(0)
    out = []
    for s, scene in enumerate(("chess", "fire", "heads")):
        for seed in range(seeds):
            base = 0.2 + 0.3 * s + 0.05 * rng.standard_normal()
            out.append(
                {"scene": scene, "seed": seed, "condition": "blurred", "head": "lstm", "err": base}
            )
            out.append(
                {
                    "scene": scene,
                    "seed": seed,
                    "condition": "rnn",
                    "head": "lstm",
                    "err": base + effect + noise * rng.standard_normal(),
                }
            )
    out.append({"scene": "chess", "seed": 0, "condition": "rnn", "head": "none", "err": 9.0})
    return out


def test_pairs_match_scene_and_seed_and_filter_rows() -> None:
    a, b, keys = paired_differences(
        rows(-0.05), "err", "condition", "blurred", "rnn", where={"head": "lstm"}
    )
    assert len(keys) == 15 and keys[0] == ("chess", 0)
    np.testing.assert_allclose(b - a, -0.05, atol=0.05)


def test_a_real_effect_is_reproduced_and_its_opposite_contradicted() -> None:
    table = comparison_table(rows(-0.05), [("blurred", "rnn")], ("err",), where={"head": "lstm"})
    assert table[0]["verdict"] == "reproduced" and table[0]["ci_high"] < 0
    table = comparison_table(rows(+0.05), [("blurred", "rnn")], ("err",), where={"head": "lstm"})
    assert table[0]["verdict"] == "contradicted"


def test_no_effect_is_unresolved_despite_large_scene_differences() -> None:
    table = comparison_table(
        rows(0.0, noise=0.02), [("blurred", "rnn")], ("err",), where={"head": "lstm"}
    )
    assert table[0]["verdict"].startswith("too small to resolve")
    assert table[0]["ci_high"] - table[0]["ci_low"] < 0.05  # pairing removed the scene spread


def test_duplicate_units_are_refused() -> None:
    data = rows(0.0)
    data.append(dict(data[0]))
    with pytest.raises(ValueError, match="appears twice"):
        paired_differences(data, "err", "condition", "blurred", "rnn", where={"head": "lstm"})
