"""Paired intervals and the verdicts they support."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from blurloc.intervals import paired_interval, verdict


def test_t_interval_matches_scipy() -> None:
    values = np.random.default_rng(0).normal(0.3, 1.0, 35)
    interval = paired_interval(values, method="t")
    low, high = stats.t.interval(0.95, 34, loc=values.mean(), scale=stats.sem(values))
    assert interval.low == pytest.approx(low) and interval.high == pytest.approx(high)


def test_bootstrap_covers_the_true_mean_about_95_percent_of_the_time() -> None:
    rng = np.random.default_rng(1)
    covered = [
        (lambda i: i.low <= 0.5 <= i.high)(
            paired_interval(rng.normal(0.5, 1.0, 30), resamples=2000, seed=k)
        )
        for k in range(200)
    ]
    assert 0.88 <= np.mean(covered) <= 0.99


def test_bootstrap_is_seeded() -> None:
    values = np.random.default_rng(2).normal(size=20)
    assert paired_interval(values, seed=3) == paired_interval(values, seed=3)


def test_verdicts_follow_the_interval() -> None:
    lower = paired_interval(np.full(10, -1.0) + np.linspace(-0.1, 0.1, 10), method="t")
    higher = paired_interval(np.full(10, 1.0) + np.linspace(-0.1, 0.1, 10), method="t")
    noise = paired_interval(np.linspace(-1, 1, 10), method="t")
    assert verdict(lower, claimed_sign=-1) == "reproduced"
    assert verdict(higher, claimed_sign=-1) == "contradicted"
    assert verdict(lower, claimed_sign=1) == "contradicted"
    assert verdict(noise).startswith("too small to resolve at this power (±")


@pytest.mark.parametrize("bad", [[1.0], [1.0, np.nan], []])
def test_bad_differences_are_refused(bad: list) -> None:
    with pytest.raises(ValueError, match="paired differences"):
        paired_interval(np.array(bad))


def test_bootstrap_is_the_percentile_interval_of_resampled_means() -> None:
    values = np.random.default_rng(4).normal(0.2, 1.0, 12)
    picks = np.random.default_rng(5).integers(0, values.size, size=(4000, values.size))
    means = values[picks].mean(axis=1)
    interval = paired_interval(values, resamples=4000, seed=5)
    assert [interval.low, interval.high] == pytest.approx(np.quantile(means, [0.025, 0.975]))
