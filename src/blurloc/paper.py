"""The numbers the paper printed (and the original publications' numbers for the methods it
compares), as data: a copy of ``reported_numbers.csv``. They are reference values, labelled
"paper" wherever they appear, and never mixed into measured values."""

from __future__ import annotations

import csv
from functools import cache
from pathlib import Path

REPORTED_NUMBERS = Path(__file__).with_name("reported_numbers.csv")


@cache
def reported_numbers() -> tuple[dict, ...]:
    """Every number the paper printed (and the compared methods' original numbers).

    Returns
    -------
    tuple of dict
        Rows of reported_numbers.csv (source, item, method, scene, metric, value, note),
        ``value`` as float, exact duplicate rows dropped.
    """
    rows, seen = [], set()
    with open(REPORTED_NUMBERS, newline="") as handle:
        for record in csv.DictReader(handle):
            key = tuple(record.values())
            if key in seen:
                continue
            seen.add(key)
            rows.append({**record, "value": float(record["value"])})
    return tuple(rows)


def paper_values(item: str, metric: str, method: str | None = None) -> dict[str, float]:
    """Per-scene values of one printed item.

    Parameters
    ----------
    item : str
        E.g. ``fig6``, ``table1``.
    metric : str
        E.g. ``psnr_db``, ``rmse``.
    method : str, optional
        Restrict to one method's rows.

    Returns
    -------
    dict
        ``{scene: printed value}`` (units as printed).

    Raises
    ------
    KeyError
        If the paper printed no such values.
    """
    values = {
        row["scene"]: row["value"]
        for row in reported_numbers()
        if row["item"] == item and row["metric"] == metric
        and (method is None or row["method"] == method)
    }  # fmt: skip
    if not values:
        raise KeyError(f"no printed values for item={item!r}, metric={metric!r}, method={method!r}")
    return values
