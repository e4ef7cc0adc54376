"""Result tables for readers: Markdown (with a caption) beside CSV, as the notebooks save them."""

from __future__ import annotations

import csv
import os
from collections.abc import Sequence
from pathlib import Path


def save_table(
    rows: list[dict],
    folder: str | os.PathLike,
    name: str,
    columns: Sequence[str] | None = None,
    caption: str = "",
) -> list[Path]:
    """Save rows as a Markdown table and a CSV file.

    Parameters
    ----------
    rows : list of dict
        One dict per row; missing keys are written empty, extra keys ignored.
    folder : str or os.PathLike
        Output folder (created).
    name : str
        File stem.
    columns : sequence of str, optional
        Column order (default: the keys of the first row).
    caption : str
        Line written above the Markdown table.

    Returns
    -------
    list of pathlib.Path
        ``<folder>/<name>.md`` and ``<folder>/<name>.csv``.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    columns = list(columns or rows[0].keys())
    csv_path, md_path = folder / f"{name}.csv", folder / f"{name}.md"
    with open(csv_path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    lines = [caption, ""] if caption else []
    lines.append("| " + " | ".join(columns) + " |")
    lines.append("|" + "|".join("---" for _ in columns) + "|")
    lines += ["| " + " | ".join(str(row.get(c, "")) for c in columns) + " |" for row in rows]
    md_path.write_text("\n".join(lines) + "\n")
    return [md_path, csv_path]


def save_findings(
    findings: dict[str, object], folder: str | os.PathLike, name: str, caption: str = ""
) -> list[Path]:
    """Save the numbers a notebook's conclusions quote, one row per quantity.

    The conclusions are Markdown written by a person; every decimal number in them must be one
    of the numbers of the notebook's tables (``tests/test_conclusions.py`` checks it), and this
    table holds the ones no other table has.

    Parameters
    ----------
    findings : dict
        ``{quantity: value}``.
    folder : str or os.PathLike
        Output folder (created).
    name : str
        File stem.
    caption : str
        Line written above the Markdown table.

    Returns
    -------
    list of pathlib.Path
        ``<folder>/<name>.md`` and ``<folder>/<name>.csv``.
    """
    rows = [{"quantity": quantity, "value": value} for quantity, value in findings.items()]
    return save_table(rows, folder, name, caption=caption)
