"""Every benchmark writes its tables with the shared writer and is listed in docs/benchmarks.md.

Checked on the sources (no benchmark is run): each ``benchmarks/*.py`` calls
``add_out_dir_argument(`` and ``save_benchmark_tables(`` and is named in docs/benchmarks.md.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parents[1]
BENCHMARKS = sorted((REPOSITORY / "benchmarks").glob("*.py"))
DOCS = REPOSITORY / "docs" / "benchmarks.md"
#: Benchmarks not yet on the shared writer; empty this set as each one is wired.
NOT_YET_WIRED: set[str] = set()


def _called_names(path: Path) -> set[str]:
    """Names of the functions that ``path`` calls (``f(...)`` and ``module.f(...)``)."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call):
            function = node.func
            if isinstance(function, ast.Name):
                names.add(function.id)
            elif isinstance(function, ast.Attribute):
                names.add(function.attr)
    return names


def test_there_are_benchmarks_and_the_exclusions_exist() -> None:
    names = {path.name for path in BENCHMARKS}
    assert len(names - NOT_YET_WIRED) >= 10
    assert NOT_YET_WIRED <= names, sorted(NOT_YET_WIRED - names)


@pytest.mark.parametrize(
    "path", [p for p in BENCHMARKS if p.name not in NOT_YET_WIRED], ids=lambda p: p.name
)
def test_benchmark_uses_the_shared_table_writer(path: Path) -> None:
    called = _called_names(path)
    assert "add_out_dir_argument" in called, path.name
    assert "save_benchmark_tables" in called, path.name


@pytest.mark.parametrize(
    "path", [p for p in BENCHMARKS if p.name not in NOT_YET_WIRED], ids=lambda p: p.name
)
def test_benchmark_is_listed_in_docs(path: Path) -> None:
    assert f"benchmarks/{path.name}" in DOCS.read_text(encoding="utf-8"), path.name


def test_called_names_finds_calls_not_mentions(tmp_path: Path) -> None:
    script = tmp_path / "x.py"
    script.write_text(
        '"""save_benchmark_tables( in a docstring."""\n'
        "import blurloc.tables as t\n"
        "t.add_out_dir_argument(parser)\n",
        encoding="utf-8",
    )
    assert _called_names(script) >= {"add_out_dir_argument"}
    assert "save_benchmark_tables" not in _called_names(script)
