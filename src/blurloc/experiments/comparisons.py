"""Paired comparisons of experiment rows: differences matched by unit, their interval, verdict.

Rows are the flat dicts the experiments return (one per run), e.g. ``{"scene": "chess",
"seed": 3, "condition": "rnn", "head": "lstm", "position_m_median": 0.21, ...}``. A comparison
pairs the rows of two configurations that share a unit (by default the scene x seed pair), so
that the scene's difficulty and the seed's luck cancel in each difference.
"""

from __future__ import annotations

import numpy as np

from ..intervals import paired_interval, verdict
from .rows import grouped_means, grouped_values, matching


def paired_differences(
    rows: list[dict],
    metric: str,
    factor: str,
    baseline: str,
    other: str,
    units: tuple[str, ...] = ("scene", "seed"),
    where: dict | None = None,
) -> tuple[np.ndarray, np.ndarray, list[tuple]]:
    """Values of ``metric`` for two levels of ``factor``, matched unit by unit.

    Parameters
    ----------
    rows : list of dict
        One row per run.
    metric : str
        Column compared (e.g. ``position_m_median``).
    factor : str
        Column that differs between the two configurations (e.g. ``condition``).
    baseline, other : str
        Its two levels; differences are ``other - baseline``.
    units : tuple of str
        Columns that identify a pair (default scene and seed).
    where : dict, optional
        Only rows whose columns equal these values (e.g. ``{"head": "lstm"}``), compared as
        text (:func:`blurloc.experiments.rows.matching`).

    Returns
    -------
    baseline_values, other_values : numpy.ndarray
        (N,) values of the N units present for both levels, in sorted unit order.
    unit_keys : list of tuple
        The N units.

    Raises
    ------
    ValueError
        If a unit appears twice for one level, or no unit has both levels.
    """
    chosen = matching(rows, where)
    tables: dict[str, dict[tuple, float]] = {baseline: {}, other: {}}
    for row in chosen:
        level = row.get(factor)
        if level not in tables:
            continue
        key = tuple(row[u] for u in units)
        if key in tables[level]:
            raise ValueError(f"{factor}={level!r}: unit {key} appears twice")
        tables[level][key] = float(row[metric])
    keys = sorted(set(tables[baseline]) & set(tables[other]))
    if not keys:
        raise ValueError(f"no {units} unit has both {factor}={baseline!r} and {other!r}")
    a = np.array([tables[baseline][k] for k in keys])
    b = np.array([tables[other][k] for k in keys])
    return a, b, keys


def comparison_table(
    rows: list[dict],
    comparisons: list[tuple[str, str]],
    metrics: tuple[str, ...],
    factor: str = "condition",
    units: tuple[str, ...] = ("scene", "seed"),
    where: dict | None = None,
    claimed_sign: int = -1,
    method: str = "bootstrap",
    seed: int = 0,
) -> list[dict]:
    """Mean paired difference, its 95 % interval and the verdict, per comparison and metric.

    Parameters
    ----------
    rows : list of dict
        One row per run.
    comparisons : list of (str, str)
        ``(baseline, other)`` levels of ``factor``; each row of the result is ``other -
        baseline``.
    metrics : tuple of str
        Columns compared.
    factor, units, where
        As in :func:`paired_differences`.
    claimed_sign : {-1, 1}
        The direction claimed for ``other - baseline`` (-1: ``other`` has the lower error).
    method : {"bootstrap", "t"}
        Interval method (:func:`blurloc.intervals.paired_interval`).
    seed : int
        Bootstrap seed.

    Returns
    -------
    list of dict
        Per comparison and metric: ``comparison``, ``metric``, ``pairs``, ``baseline_mean``,
        ``other_mean``, ``mean_difference``, ``ci_low``, ``ci_high``, ``relative_difference``
        (mean difference over the baseline mean), ``interval`` (the method) and ``verdict``.
    """
    table = []
    for baseline, other in comparisons:
        for metric in metrics:
            a, b, _ = paired_differences(rows, metric, factor, baseline, other, units, where)
            interval = paired_interval(b - a, method=method, seed=seed)
            table.append({
                "comparison": f"{other} - {baseline}", "metric": metric, "pairs": interval.pairs,
                "baseline_mean": float(a.mean()), "other_mean": float(b.mean()),
                "mean_difference": interval.mean, "ci_low": interval.low,
                "ci_high": interval.high,
                "relative_difference": interval.mean / float(a.mean()) if a.mean() else np.nan,
                "interval": f"{interval.level:.0%} {interval.method}",
                "verdict": verdict(interval, claimed_sign),
            })  # fmt: skip
    return table


def per_scene_mean(rows: list[dict], metric: str, where: dict | None = None) -> dict[str, float]:
    """The mean over seeds of ``metric``, per scene.

    Parameters
    ----------
    rows : list of dict
        One row per run with ``scene`` and ``metric`` (numbers, or numeric strings as read from
        CSV).
    metric : str
        Column averaged (e.g. ``position_m_median``: each run's median error).
    where : dict, optional
        Only rows whose columns equal these values (e.g. ``{"condition": "rnn", "head":
        "lstm"}``); values are compared as text, so CSV rows match too.

    Returns
    -------
    dict
        ``{scene: mean over the scene's runs}``, scenes in the rows' order.
    """
    return grouped_means(rows, "scene", metric, where)


def per_scene_spread(rows: list[dict], metric: str, where: dict | None = None) -> dict[str, float]:
    """The standard deviation over seeds of ``metric``, per scene (the seed spread).

    Parameters
    ----------
    rows, metric, where
        As in :func:`per_scene_mean`.

    Returns
    -------
    dict
        ``{scene: sample standard deviation (ddof 1) over the scene's runs}``; 0 for a scene with
        one run.
    """
    return {scene: float(np.std(values, ddof=1)) if len(values) > 1 else 0.0
            for scene, values in grouped_values(rows, "scene", metric, where).items()}  # fmt: skip
