"""The front page stays a front page, and every relative link of the README and docs/ resolves."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parents[1]
README = REPOSITORY / "README.md"


def _load_module(name: str):
    spec = importlib.util.spec_from_file_location(name, REPOSITORY / "docs" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


stage_book = _load_module("stage_book")
check_book = _load_module("check_book")


def _section(text: str, heading: str) -> str:
    start = text.index(f"## {heading}\n")
    end = text.find("\n## ", start + 1)
    return text[start : end if end >= 0 else len(text)]


def _table_rows(section: str) -> list[list[str]]:
    rows = [line for line in section.splitlines() if line.startswith("|")]
    return [[cell.strip() for cell in row.strip("|").split("|")] for row in rows[2:]]


def test_readme_is_a_front_page_of_at_most_1200_words() -> None:
    words = len(README.read_text(encoding="utf-8").split())
    assert words <= 1200, words


def test_paper_vs_package_table_is_short() -> None:
    rows = _table_rows(_section(README.read_text(encoding="utf-8"), "Paper vs this package"))
    assert 1 <= len(rows) <= 8
    for row in rows:
        for cell in row:
            assert len(cell.split()) <= 15, cell


def test_every_docs_page_is_linked_from_the_readme() -> None:
    linked = {
        (REPOSITORY / target).resolve() for target in stage_book.relative_link_targets(README)
    }
    pages = set((REPOSITORY / "docs").glob("*.md"))
    assert pages and pages <= linked, sorted(page.name for page in pages - linked)


def test_every_executed_notebook_is_linked_from_the_readme() -> None:
    linked = set(stage_book.relative_link_targets(README))
    for notebook in (REPOSITORY / "notebooks" / "executed").glob("*.ipynb"):
        assert f"notebooks/executed/{notebook.name}" in linked, notebook.name


@pytest.mark.parametrize("page", stage_book.markdown_pages(REPOSITORY), ids=lambda page: page.name)
def test_relative_links_resolve(page: Path) -> None:
    missing = []
    for target in stage_book.relative_link_targets(page):
        path = (page.parent / target).resolve()
        if path.relative_to(REPOSITORY).parts[0] == "build":
            continue  # the built book, made by `make docs`
        if not path.exists():
            missing.append(target)
    assert not missing, missing


def test_link_targets_skip_urls_and_anchors(tmp_path: Path) -> None:
    page = tmp_path / "page.md"
    page.write_text(
        "[a](https://example.org/x) [b](#here) [c](../figures/x.png#top) ![d](y.png) "
        "[e](mailto:someone@example.org)",
        encoding="utf-8",
    )
    assert stage_book.relative_link_targets(page) == ["../figures/x.png", "y.png"]


def test_stage_copies_linked_files_and_points_the_book_link_home(tmp_path: Path) -> None:
    repository = tmp_path / "repository"
    (repository / "docs").mkdir(parents=True)
    (repository / "figures").mkdir()
    (repository / "figures" / "x.png").write_bytes(b"png")
    (repository / "README.md").write_text(
        "[docs](docs/a.md) [book](build/site/index.html) ![x](figures/x.png)", encoding="utf-8"
    )
    (repository / "docs" / "a.md").write_text("![x](../figures/x.png)", encoding="utf-8")
    out = tmp_path / "out"
    staged = stage_book.stage(out, repository)
    assert set(map(str, staged)) == {"README.md", "docs/a.md", "figures/x.png"}
    assert "[book](README.md)" in (out / "README.md").read_text(encoding="utf-8")
    (repository / "docs" / "a.md").write_text("[gone](../missing.md)", encoding="utf-8")
    with pytest.raises(FileNotFoundError, match=r"missing\.md"):
        stage_book.stage(out, repository)


def test_readme_links_the_book_entry_page() -> None:
    assert re.search(r"\]\(build/site/index\.html\)", README.read_text(encoding="utf-8"))


def test_book_check_fails_pages_without_their_figures_or_equations() -> None:
    shown = {"src": "a.png", "width": 640, "decoded": True, "alt": "a plot"}
    broken = {"src": "b.png", "width": 0, "decoded": False, "alt": "b"}
    page = {"title": "02", "text_length": 5000, "typeset_math": 3, "tex_source": False}
    notebook = "notebooks/executed/02.html"
    assert check_book.page_failures(notebook, page | {"images": [shown]}, True) == []
    assert check_book.page_failures(notebook, page | {"images": [shown, broken]}, True)
    assert check_book.page_failures(notebook, page | {"images": []}, True)
    unlabelled = shown | {"alt": ""}
    assert check_book.page_failures(notebook, page | {"images": [unlabelled]}, True) == [
        f"{notebook}: figure a.png has no alternative text"]  # fmt: skip
    assert check_book.page_failures("docs/gpu.html", page | {"images": [unlabelled]}, True) == []
    assert check_book.page_failures("docs/gpu.html", page | {"images": []}, True) == []
    untypeset = page | {"images": [shown], "tex_source": True}
    assert check_book.page_failures(notebook, untypeset, True)
    assert check_book.page_failures(notebook, untypeset, False) == []
    assert check_book.page_failures(notebook, {"error": "timed out"}, True)


def test_staged_notebook_figures_keep_their_alternative_text() -> None:
    described = {"output_type": "display_data", "data": {"image/png": "iVBO\nRw==",
                                                         "text/plain": "x"},
                 "metadata": {"image/png": {"alt": 'Bars "a" & b'}}}  # fmt: skip
    bare = {"output_type": "display_data", "data": {"image/png": "AAAA"}, "metadata": {}}
    notebook = stage_book.images_with_alt(
        {"cells": [{"cell_type": "code", "outputs": [described, bare]}]}
    )
    assert described["data"]["text/html"] == (
        '<img src="data:image/png;base64,iVBORw==" alt="Bars &quot;a&quot; &amp; b">'
    )
    assert "text/html" not in bare["data"]
    assert notebook["cells"][0]["outputs"][0] is described
