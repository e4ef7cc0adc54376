"""Executed notebooks a reader can open without running anything.

A full ``make reproduce`` executes every notebook into ``build/``. The published copies under
``notebooks/executed/`` are the current notebooks (their Markdown as it is now) with the
outputs of that run attached to their code cells, which must be the very code that ran:
:func:`publish_notebooks` refuses a notebook whose code cells differ from the executed ones,
and :func:`stale_notebooks` (run by the tests) lists published copies whose code no longer
matches the sources.
"""

from __future__ import annotations

import copy
import json
import os
import re
from pathlib import Path

from .config import project_root
from .files import atomic_path

#: The tag papermill gives the cell holding the parameters it injected.
INJECTED_TAG = "injected-parameters"


def code_sources(notebook: dict) -> list[str]:
    """The source of every code cell, in order, without papermill's injected parameters.

    Parameters
    ----------
    notebook : dict
        A notebook as read by :func:`json.load`.

    Returns
    -------
    list of str
        One source text per code cell.
    """
    return ["".join(cell["source"]) for cell in notebook["cells"]
            if cell["cell_type"] == "code" and not _injected(cell)]  # fmt: skip


def _injected(cell: dict) -> bool:
    return INJECTED_TAG in cell.get("metadata", {}).get("tags", [])


def _read(path: Path) -> dict:
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such notebook")
    return json.loads(path.read_text())


def published_copy(source: dict, executed: dict, name: str = "notebook") -> dict:
    """``source`` with the outputs of ``executed`` attached to its code cells.

    Parameters
    ----------
    source : dict
        The notebook as it is now (no outputs).
    executed : dict
        The same notebook executed by papermill.
    name : str
        Named in the error.

    Returns
    -------
    dict
        ``source``'s cells with the executed code cells' outputs and execution counts, and
        papermill's injected-parameters cell after the parameters cell. The project's
        absolute path is made relative: ``../`` in those parameters (the notebooks run in
        ``notebooks/``), the project's root in printed text (``/home/me/blurloc/results/x``
        reads ``results/x``).

    Raises
    ------
    ValueError
        If the code cells of the two differ (naming the first that does).
    """
    ran = [c for c in executed["cells"] if c["cell_type"] == "code" and not _injected(c)]
    now = code_sources(source)
    if len(ran) != len(now):
        raise ValueError(f"{name}: {len(ran)} code cells ran, the notebook has {len(now)}; "
                         "run the notebooks again (make reproduce)")  # fmt: skip
    for index, (cell, text) in enumerate(zip(ran, now, strict=True)):
        if "".join(cell["source"]) != text:
            raise ValueError(f"{name}: code cell {index} differs from the one that ran; "
                             "run the notebooks again (make reproduce)")  # fmt: skip
    published = copy.deepcopy(source)
    executed = _without_root(executed, str(project_root()))
    ran = [c for c in executed["cells"] if c["cell_type"] == "code" and not _injected(c)]
    outputs = iter(ran)
    cells = []
    for cell in published["cells"]:
        if cell["cell_type"] == "code":
            executed_cell = next(outputs)
            cell["outputs"] = executed_cell.get("outputs", [])
            cell["execution_count"] = executed_cell.get("execution_count")
        cells.append(cell)
        if "parameters" in cell.get("metadata", {}).get("tags", []):
            cells += [c for c in executed["cells"] if _injected(c)]
    published["cells"] = cells
    return published


def _without_root(notebook: dict, root: str) -> dict:
    """A copy of an executed notebook without the project's absolute path: in papermill's
    parameters it becomes ``../`` (the notebooks run in ``notebooks/``), in printed text a path
    relative to the project."""
    prefix = re.compile(re.escape(root.rstrip("/\\")) + r"(?:[/\\]|(?=[\s\"',)]|$))")

    def relative(value, replacement: str):
        if isinstance(value, str):  # the root itself: "." or ".."; a path below it: "" or "../"
            return prefix.sub(lambda found: replacement if found.group(0)[-1:] in "/\\"
                              else replacement.rstrip("/") or ".", value)  # fmt: skip
        if isinstance(value, list):
            return [relative(item, replacement) for item in value]
        return value

    notebook = copy.deepcopy(notebook)
    for cell in notebook["cells"]:
        if _injected(cell):
            cell["source"] = relative(cell["source"], "../")
        for output in cell.get("outputs", []):
            if "text" in output:
                output["text"] = relative(output["text"], "")
            for kind in ("text/plain", "text/markdown", "text/html"):
                if kind in output.get("data", {}):
                    output["data"][kind] = relative(output["data"][kind], "")
    return notebook


def publish_notebooks(
    names: list[str],
    executed_dir: str | os.PathLike | None = None,
    out_dir: str | os.PathLike | None = None,
) -> list[Path]:
    """Write the published copy of each notebook (see :func:`published_copy`).

    Parameters
    ----------
    names : list of str
        Notebook names without ``.ipynb``.
    executed_dir : str or os.PathLike, optional
        Where the executed notebooks are (default: the project's ``build/``,
        :func:`blurloc.config.project_root`).
    out_dir : str or os.PathLike, optional
        Where the published copies go (default: the project's ``notebooks/executed/``).

    Returns
    -------
    list of pathlib.Path
        The files written.

    Raises
    ------
    FileNotFoundError
        If an executed notebook is missing.
    ValueError
        If a notebook's code changed since it ran.
    """
    notebooks = project_root() / "notebooks"
    executed_dir = Path(executed_dir or project_root() / "build")
    out_dir = Path(out_dir or notebooks / "executed")
    # every notebook is checked before any copy is written
    copies = {name: published_copy(_read(notebooks / f"{name}.ipynb"),
                                   _read(executed_dir / f"{name}.ipynb"), name)
              for name in names}  # fmt: skip
    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    for name, notebook in copies.items():
        path = out_dir / f"{name}.ipynb"
        with atomic_path(path) as temporary:
            Path(temporary).write_text(json.dumps(notebook, indent=1, ensure_ascii=False) + "\n")
        written.append(path)
    return written


def stale_notebooks(names: list[str], published_dir: str | os.PathLike | None = None) -> list[str]:
    """Notebooks whose published copy is missing or holds other code than the source.

    Parameters
    ----------
    names : list of str
        Notebook names without ``.ipynb``.
    published_dir : str or os.PathLike, optional
        Where the published copies are (default: the project's ``notebooks/executed/``,
        :func:`blurloc.config.project_root`).

    Returns
    -------
    list of str
        The names whose copy is missing, or whose code cells differ from the notebook's.
    """
    notebooks = project_root() / "notebooks"
    published_dir = Path(published_dir or notebooks / "executed")
    stale = []
    for name in names:
        path = published_dir / f"{name}.ipynb"
        source = _read(notebooks / f"{name}.ipynb")
        if not path.is_file() or code_sources(_read(path)) != code_sources(source):
            stale.append(name)
    return stale


#: Text in an executed copy's outputs that a reader should not see.
_DEBRIS = (
    (re.compile(r"\d+%\|.*\|"), "a progress bar"),
    (re.compile(r"interactive\(children=|VBox\(children=|HBox\(children="), "a widget's text"),
    (re.compile(r"(?<![\w.])(/work/|/home/|/tmp/|/root/|/Users/|[A-Z]:\\\\)"), "an absolute path"),
)


def reading_problems(notebook: dict) -> list[str]:
    """What in an executed notebook would not read cleanly on a code host.

    Checks every code cell's outputs for stderr text, progress bars, widget text standing where
    a static figure or a plain note should, absolute paths, PNG figures without alt text (the
    output's ``metadata["image/png"]["alt"]``) and the same figure shown twice.

    Parameters
    ----------
    notebook : dict
        An executed notebook (nbformat 4 JSON).

    Returns
    -------
    list of str
        One line per problem (``"cell 12: an absolute path"``); empty when it reads cleanly.
    """
    problems, seen = [], {}
    code = [c for c in notebook["cells"] if c["cell_type"] == "code"]
    for index, cell in enumerate(code):
        for output in cell.get("outputs", []):
            if output.get("output_type") == "stream" and output.get("name") == "stderr":
                problems.append(f"cell {index}: stderr output")
            data = output.get("data", {})
            texts = ["".join(output.get("text", "")), "".join(data.get("text/plain", ""))]
            for pattern, what in _DEBRIS:
                if any(pattern.search(text) for text in texts):
                    problems.append(f"cell {index}: {what}")
            png = data.get("image/png")
            if png is None:
                continue
            png = "".join(png)
            if not output.get("metadata", {}).get("image/png", {}).get("alt"):
                problems.append(f"cell {index}: a figure without alt text")
            if png in seen:
                problems.append(f"cell {index}: the figure of cell {seen[png]} shown again")
            seen.setdefault(png, index)
    return problems
