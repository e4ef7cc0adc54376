"""Result tables for readers: Markdown (with a caption) beside CSV, as the notebooks save them."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

from .config import write_rows
from .files import atomic_path


class SavedTable(NamedTuple):
    """The two files of a saved table; shown in a notebook as the Markdown table.

    Attributes
    ----------
    markdown : pathlib.Path
        ``<name>.md``: the caption and the table in Markdown.
    csv : pathlib.Path
        ``<name>.csv``: the same rows as CSV.
    """

    markdown: Path
    csv: Path

    def _repr_markdown_(self) -> str:
        """The Markdown file's text (Jupyter shows it as the cell's output)."""
        return self.markdown.read_text()


def save_table(
    rows: list[dict],
    folder: str | os.PathLike,
    name: str,
    columns: Sequence[str] | None = None,
    caption: str = "",
) -> SavedTable:
    """Save rows as a Markdown table and a CSV file, each written whole (write, then rename).

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
    SavedTable
        ``<folder>/<name>.md`` and ``<folder>/<name>.csv``; the last expression of a notebook
        cell, it shows the table.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    columns = list(columns or rows[0].keys())
    table = [{column: row.get(column, "") for column in columns} for row in rows]
    csv_path = write_rows(table, folder / f"{name}.csv", columns)
    lines = [caption, ""] if caption else []
    lines.append("| " + " | ".join(columns) + " |")
    lines.append("|" + "|".join("---" for _ in columns) + "|")
    lines += ["| " + " | ".join(str(row[c]) for c in columns) + " |" for row in table]
    md_path = folder / f"{name}.md"
    with atomic_path(md_path) as temporary:
        temporary.write_text("\n".join(lines) + "\n")
    return SavedTable(md_path, csv_path)


def save_findings(
    findings: dict[str, object], folder: str | os.PathLike, name: str, caption: str = ""
) -> SavedTable:
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
    SavedTable
        ``<folder>/<name>.md`` and ``<folder>/<name>.csv``.
    """
    rows = [{"quantity": quantity, "value": value} for quantity, value in findings.items()]
    return save_table(rows, folder, name, caption=caption)
