"""Published notebooks: the current notebooks with the outputs of the run that executed them."""

from __future__ import annotations

import pytest

from blurloc.publish import code_sources, published_copy, reading_problems, stale_notebooks
from blurloc.runner import notebook_names


def _cell(kind: str, source: str, tags: tuple[str, ...] = (), outputs: list | None = None) -> dict:
    cell = {"cell_type": kind, "metadata": {"tags": list(tags)} if tags else {},
            "source": source}  # fmt: skip
    if kind == "code":
        cell |= {"outputs": outputs or [], "execution_count": 1 if outputs else None}
    return cell


SOURCE = {"cells": [_cell("markdown", "# Title, edited since the run"),
                    _cell("code", "quick = False", ("parameters",)),
                    _cell("code", "print(1)")]}  # fmt: skip
EXECUTED = {"cells": [_cell("markdown", "# Title"),
                      _cell("code", "quick = False", ("parameters",), [{"text": "p"}]),
                      _cell("code", "quick = True", ("injected-parameters",)),
                      _cell("code", "print(1)", (), [{"text": "1"}])]}  # fmt: skip


def test_the_published_copy_is_the_current_notebook_with_the_runs_outputs() -> None:
    published = published_copy(SOURCE, EXECUTED, "demo")
    assert [c["source"] for c in published["cells"]] == [
        "# Title, edited since the run",
        "quick = False",
        "quick = True",
        "print(1)",
    ]
    assert published["cells"][3]["outputs"] == [{"text": "1"}]
    assert code_sources(published) == code_sources(SOURCE) == ["quick = False", "print(1)"]
    assert SOURCE["cells"][2]["outputs"] == []  # the source is not modified


def test_the_machine_path_of_the_run_is_not_published(
    make_project, tmp_path, monkeypatch: pytest.MonkeyPatch
) -> None:
    root = make_project(tmp_path).resolve()
    monkeypatch.setenv("BLURLOC_ROOT", str(root))
    lines = [f"written to {root}/results/deblurred/rnn\n", f"root {root}\n"]
    printed = {"output_type": "stream", "name": "stdout", "text": lines}
    executed = {"cells": [*EXECUTED["cells"][:2],
                          _cell("code", f'data_root = "{root}/data/standin"',
                                ("injected-parameters",)),
                          _cell("code", "print(1)", (), [printed])]}  # fmt: skip
    published = published_copy(SOURCE, executed, "demo")
    assert published["cells"][2]["source"] == 'data_root = "../data/standin"'
    assert published["cells"][3]["outputs"][0]["text"] == [
        "written to results/deblurred/rnn\n", "root .\n"]  # fmt: skip
    assert reading_problems(published) == []
    assert str(root) in executed["cells"][2]["source"]  # the executed notebook is not modified


def test_code_that_changed_since_the_run_is_refused() -> None:
    changed = {"cells": [*SOURCE["cells"][:2], _cell("code", "print(2)")]}
    with pytest.raises(ValueError, match="demo: code cell 1 differs"):
        published_copy(changed, EXECUTED, "demo")
    with pytest.raises(ValueError, match="demo: 2 code cells ran, the notebook has 3"):
        published_copy({"cells": [*SOURCE["cells"], _cell("code", "x")]}, EXECUTED, "demo")


def test_published_notebooks_were_executed_from_the_current_sources() -> None:
    assert stale_notebooks(notebook_names()) == []


def _figure(data: str, alt: str = "") -> dict:
    metadata = {"image/png": {"alt": alt}} if alt else {}
    return {"output_type": "display_data", "data": {"image/png": data}, "metadata": metadata}


def test_reading_problems_finds_what_a_reader_should_not_see() -> None:
    printed = {"output_type": "stream", "name": "stdout", "text": "relative/figures/a.png"}
    clean = {"cells": [_cell("code", "plot()", (), [_figure("AAA", "kernels")]),
                       _cell("code", "print(x)", (), [printed])]}  # fmt: skip
    assert reading_problems(clean) == []
    messy = {"cells": [
        _cell("code", "a()", (), [{"output_type": "stream", "name": "stderr",
                                   "text": "estimation:  40%|####      | 4/10"}]),
        _cell("code", "b()", (), [_figure("AAA")]),
        _cell("code", "c()", (), [_figure("AAA", "again")]),
        _cell("code", "d()", (), [{"output_type": "execute_result",
                                   "data": {"text/plain": "interactive(children=(FloatSlider"}}]),
        _cell("code", "e()", (), [{"output_type": "stream", "name": "stdout",
                                   "text": "written to /work/main/results/x.csv"}]),
    ]}  # fmt: skip
    assert reading_problems(messy) == [
        "cell 0: stderr output", "cell 0: a progress bar", "cell 1: a figure without alt text",
        "cell 2: the figure of cell 1 shown again", "cell 3: a widget's text",
        "cell 4: an absolute path",
    ]  # fmt: skip


def test_executed_copies_read_cleanly() -> None:
    import json

    from blurloc.config import NOTEBOOKS_DIR

    problems = {}
    for name in notebook_names():
        executed = json.loads((NOTEBOOKS_DIR / "executed" / f"{name}.ipynb").read_text())
        problems[name] = reading_problems(executed)
    assert {name: found for name, found in problems.items() if found} == {}
