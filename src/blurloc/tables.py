"""Result tables for readers: Markdown (with a caption) beside CSV, as the notebooks save them."""

from __future__ import annotations

import argparse
import datetime
import os
import shlex
import subprocess
import sys
from collections.abc import Mapping, Sequence
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


def add_out_dir_argument(parser: argparse.ArgumentParser, default: str = "figures") -> None:
    """Give a benchmark the common ``--out-dir`` option: the folder its tables are written to.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The benchmark's parser; ``args.out_dir`` (a :class:`pathlib.Path`) is added.
    default : str
        Folder used when the option is not given.
    """
    parser.add_argument(
        "--out-dir", type=Path, default=Path(default), help=f"tables' folder (default {default})"
    )


def code_version() -> str:
    """The code's version: ``git describe --always --dirty`` of the source, else the package's.

    Returns
    -------
    str
        E.g. ``925abd5`` or ``925abd5-dirty``; ``blurloc <version>`` outside a git checkout.
    """
    try:
        described = subprocess.run(
            ["git", "describe", "--always", "--dirty"],
            cwd=Path(__file__).resolve().parent,
            capture_output=True,
            text=True,
            timeout=10,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        described = ""
    if described:
        return described
    from . import __version__

    return f"blurloc {__version__}"


def save_benchmark_tables(
    stem: str,
    tables: Mapping[str, list[dict]],
    out_dir: str | os.PathLike = "figures",
    title: str = "",
    command: Sequence[str] | None = None,
    notes: str = "",
) -> SavedTable:
    """Write a benchmark's tables: one Markdown file with its provenance, one CSV per table.

    ``<out_dir>/<stem>.md`` holds the title, the command line that ran the benchmark, the UTC
    date, the code version (:func:`code_version`), optional notes, then each table under its
    name as a heading. The first table's rows go to ``<stem>.csv``, every other table's to
    ``<stem>-<name>.csv`` (the name with spaces as ``_``). Every file is written whole
    (write, then rename).

    Parameters
    ----------
    stem : str
        File stem, usually the benchmark script's name.
    tables : mapping of str to list of dict
        ``{table name: rows}`` in the order written; each table needs at least one row, and its
        columns are the keys of its first row.
    out_dir : str or os.PathLike
        Output folder (created).
    title : str
        First line of the Markdown (default: the stem).
    command : sequence of str, optional
        The command that ran (default: ``python`` and ``sys.argv``).
    notes : str
        Text written above the tables (settings, what a column means).

    Returns
    -------
    SavedTable
        ``<out_dir>/<stem>.md`` and the first table's CSV.

    Raises
    ------
    ValueError
        When ``tables`` is empty or one of them has no rows.
    """
    if not tables:
        raise ValueError(f"{stem}: no tables to write")
    empty = [name for name, rows in tables.items() if not rows]
    if empty:
        raise ValueError(f"{stem}: tables without rows: {', '.join(empty)}")
    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    words = list(command) if command is not None else ["python", *sys.argv]
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        f"# {title or stem}",
        "",
        f"Command: `{shlex.join(words)}`",
        "",
        f"Date: {date}; code version: {code_version()}",
        "",
    ]
    if notes:
        lines += [notes, ""]
    csv_paths = []
    for index, (name, rows) in enumerate(tables.items()):
        columns = list(rows[0].keys())
        csv_name = stem if index == 0 else f"{stem}-{name.replace(' ', '_')}"
        csv_paths.append(write_rows(rows, folder / f"{csv_name}.csv", columns))
        lines += [f"## {name}", "", f"CSV: `{csv_name}.csv`", ""]
        lines.append("| " + " | ".join(columns) + " |")
        lines.append("|" + "|".join("---" for _ in columns) + "|")
        lines += ["| " + " | ".join(str(row.get(c, "")) for c in columns) + " |" for row in rows]
        lines.append("")
    md_path = folder / f"{stem}.md"
    with atomic_path(md_path) as temporary:
        temporary.write_text("\n".join(lines))
    return SavedTable(md_path, csv_paths[0])
