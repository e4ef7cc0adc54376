"""Selecting and grouping experiment rows: the one place result tables are pivoted.

The experiments return, and the notebooks store as CSV, flat rows: one dict per frame or per
run, e.g. ``{"scene": "chess", "seed": 3, "condition": "rnn", "psnr_db": 27.1}``. Rows read
back from CSV hold text, so columns are matched as text and values read as floats.
"""

from __future__ import annotations

from collections.abc import Hashable, Mapping

import numpy as np


def matching(rows: list[dict], where: Mapping[str, object] | None = None) -> list[dict]:
    """The rows whose columns equal the values of ``where``.

    Parameters
    ----------
    rows : list of dict
        Experiment rows (as returned, or read from CSV).
    where : mapping, optional
        ``{column: value}``; compared as text, so ``{"seed": 3}`` matches a CSV row's ``"3"``.
        None or empty: every row.

    Returns
    -------
    list of dict
        The matching rows, in their order.
    """
    wanted = {column: str(value) for column, value in (where or {}).items()}
    return [row for row in rows
            if all(str(row.get(column)) == value for column, value in wanted.items())]  # fmt: skip


def grouped_values(
    rows: list[dict], by: str, value: str, where: Mapping[str, object] | None = None
) -> dict[Hashable, list[float]]:
    """One column of the matching rows, grouped by another.

    Parameters
    ----------
    rows : list of dict
        Experiment rows.
    by : str
        The column whose values name the groups (e.g. ``scene``).
    value : str
        The column collected (numbers, or numeric text as read from CSV).
    where : mapping, optional
        Only rows matching it (:func:`matching`).

    Returns
    -------
    dict
        ``{group: [values as float]}``, groups in the order they first appear.
    """
    groups: dict[Hashable, list[float]] = {}
    for row in matching(rows, where):
        groups.setdefault(row[by], []).append(float(row[value]))
    return groups


def grouped_means(
    rows: list[dict], by: str, value: str, where: Mapping[str, object] | None = None
) -> dict[Hashable, float]:
    """The mean of one column of the matching rows, per group of another.

    Parameters
    ----------
    rows, by, value, where
        As in :func:`grouped_values`.

    Returns
    -------
    dict
        ``{group: mean}``, groups in the order they first appear.
    """
    return {group: float(np.mean(values))
            for group, values in grouped_values(rows, by, value, where).items()}  # fmt: skip
