"""Published notebooks: the current notebooks with the outputs of the run that executed them."""

from __future__ import annotations

import pytest

from blurloc.publish import code_sources, published_copy, stale_notebooks
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


def test_code_that_changed_since_the_run_is_refused() -> None:
    changed = {"cells": [*SOURCE["cells"][:2], _cell("code", "print(2)")]}
    with pytest.raises(ValueError, match="demo: code cell 1 differs"):
        published_copy(changed, EXECUTED, "demo")
    with pytest.raises(ValueError, match="demo: 2 code cells ran, the notebook has 3"):
        published_copy({"cells": [*SOURCE["cells"], _cell("code", "x")]}, EXECUTED, "demo")


def test_published_notebooks_were_executed_from_the_current_sources() -> None:
    assert stale_notebooks(notebook_names()) == []
