"""The notebooks' conclusions are prose a reader can read on a code host, and every number in
them was produced by the code: each decimal number in a "What we saw" cell must be one of the
numbers of the tables (``figures/*.csv``) that the cell names, at the precision printed."""

from __future__ import annotations

import ast
import csv
import json
import math
import re
from pathlib import Path

from blurloc.config import FIGURES_DIR, NOTEBOOKS_DIR
from blurloc.runner import notebook_names

#: A decimal number as written in prose or in a table cell (ASCII or Unicode minus, or plus).
DECIMAL = re.compile(r"(?<![\w.])[-−+]?\d+\.\d+")
SOURCES = re.compile(r"<!-- numbers: (.*?) -->")
MAX_CELL_LINES = 25


def _cells(name: str) -> list[dict]:
    return json.loads((NOTEBOOKS_DIR / f"{name}.ipynb").read_text())["cells"]


def _conclusions(name: str) -> str:
    cells = _cells(name)
    text = "".join(cells[-1]["source"])
    assert cells[-1]["cell_type"] == "markdown" and text.startswith("## What we saw"), (
        f"{name}: the last cell must be the Markdown conclusions ('## What we saw')"
    )
    return text


def _value(token: str) -> float:
    return float(token.replace("−", "-"))


def _table_numbers(stem: str, folder: Path) -> list[float]:
    path = folder / f"{stem}.csv"
    assert path.is_file(), f"{path}: named by a conclusion but missing"
    with open(path, newline="") as handle:
        cells = [value for row in csv.reader(handle) for value in row]
    numbers = []
    for value in cells:
        try:
            numbers.append(float(value))
        except ValueError:
            numbers += [_value(token) for token in DECIMAL.findall(value)]
    return numbers


def _produced(token: str, numbers: list[float]) -> bool:
    """Whether the prose number ``token`` is a table number rounded to the digits printed
    (its magnitude, so that "a drop of 0.02" may quote a difference of -0.02)."""
    digits = len(token.split(".")[1])
    value = abs(_value(token))
    return any(math.isclose(round(abs(number), digits), value, abs_tol=1e-9) for number in numbers)


def _unproduced(text: str, folder: Path = FIGURES_DIR) -> list[str]:
    """The decimal numbers of a conclusion that no table it names (in ``folder``) holds."""
    match = SOURCES.search(text)
    assert match, "a conclusion names its tables: <!-- numbers: stem, stem -->"
    numbers = [n for stem in match.group(1).split(",")
               for n in _table_numbers(stem.strip(), folder)]  # fmt: skip
    prose = SOURCES.sub("", text)
    return [token for token in DECIMAL.findall(prose) if not _produced(token, numbers)]


def test_every_number_in_the_conclusions_comes_from_a_table() -> None:
    unproduced = {}
    for name in notebook_names():
        text = _conclusions(name)
        assert len(DECIMAL.findall(SOURCES.sub("", text))) >= 3, f"{name}: no numbers quoted"
        if missing := _unproduced(text):
            unproduced[name] = missing
    assert unproduced == {}


def test_the_check_catches_a_number_no_table_holds(tmp_path: Path) -> None:
    """The checker itself: a rounded table value passes, a changed digit does not."""
    (tmp_path / "t.csv").write_text("quantity,value\ngain_db,-0.7634\nrange,1.1-2.0\n")
    quoted = "<!-- numbers: t -->\n+0.76 dB, −0.763 dB, −0.8 dB, 1.1-2.0"
    assert _unproduced(quoted, tmp_path) == []
    assert _unproduced("<!-- numbers: t -->\nthe gain is 0.77 dB (2.00)", tmp_path) == ["0.77"]


def test_notebook_cells_stay_thin() -> None:
    """No function or class is defined in a notebook, and no code cell is over 25 lines:
    logic and plotting live in the package, where they are tested."""
    offenders = []
    for name in notebook_names():
        for index, cell in enumerate(_cells(name)):
            if cell["cell_type"] != "code":
                continue
            source = "".join(cell["source"])
            defined = [node for node in ast.walk(ast.parse(source))
                       if isinstance(node, ast.FunctionDef | ast.ClassDef)]  # fmt: skip
            if defined or len(source.splitlines()) > MAX_CELL_LINES:
                offenders.append((name, index))
    assert offenders == []
