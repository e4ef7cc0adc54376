"""Every notebook runs headless with papermill in quick mode, in order, and writes its figures."""

from __future__ import annotations

import ast
import json
import re
from pathlib import Path

import pytest

from blurloc.config import NOTEBOOKS_DIR
from blurloc.data.real import files_present
from blurloc.runner import EXPECTED_OUTPUTS, notebook_names, run_notebooks

REQUIRED_PARAMETERS = {"quick", "seed", "data_root", "results_dir", "figures_dir", "device"}


def _cells(name: str) -> list[dict]:
    return json.loads((NOTEBOOKS_DIR / f"{name}.ipynb").read_text())["cells"]


def test_every_notebook_is_clean_and_parameterised() -> None:
    names = notebook_names()
    assert names[0] == "00_synthetic_scenes"
    assert set(names) == set(EXPECTED_OUTPUTS)
    for name in names:
        notebook = json.loads((NOTEBOOKS_DIR / f"{name}.ipynb").read_text())
        assert notebook["metadata"]["kernelspec"]["name"] == "python3", name
        code = [c for c in notebook["cells"] if c["cell_type"] == "code"]
        assert all(not c["outputs"] and c["execution_count"] is None for c in code), name
        tagged = [c for c in code if "parameters" in c.get("metadata", {}).get("tags", [])]
        assert len(tagged) == 1, name
        assigned = {}
        for statement in ast.parse("".join(tagged[0]["source"])).body:
            assert isinstance(statement, ast.Assign), f"{name}: parameters hold assignments only"
            assigned[statement.targets[0].id] = ast.literal_eval(statement.value)  # literals only
        assert REQUIRED_PARAMETERS <= set(assigned), name
        last = notebook["cells"][-2:]
        assert any("What we saw" in "".join(c["source"]) for c in last), name


@pytest.mark.notebooks
def test_notebooks_run_in_quick_mode(tmp_path: Path, capfd: pytest.CaptureFixture) -> None:
    figures = tmp_path / "figures"
    parameters = {
        "quick": True,
        "data_root": str(tmp_path / "data"),
        "results_dir": str(tmp_path / "results"),
        "figures_dir": str(figures),
    }
    timings = run_notebooks(
        quick=True, parameters=parameters, output_dir=tmp_path / "build", cell_timeout_s=600
    )
    real_data = files_present()  # the whole development set: every real-frames section runs
    assert [name for name, _ in timings] == notebook_names()
    for name, files in EXPECTED_OUTPUTS.items():
        for file in files:
            path = figures / file
            assert path.is_file() and path.stat().st_size > 0, f"{name} did not write {file}"
        executed = json.loads((tmp_path / "build" / f"{name}.ipynb").read_text())
        errors = [
            o
            for c in executed["cells"]
            if c["cell_type"] == "code"
            for o in c.get("outputs", [])
            if o.get("output_type") == "error"
        ]
        assert not errors, name
        code = [c for c in executed["cells"] if c["cell_type"] == "code"]
        if not real_data:  # the real-frames sections skip their figures, with a note
            code = [c for c in code if not "".join(c["source"]).startswith("if real_data")]
        drawing = sum("save_figure(" in "".join(c["source"]) for c in code)
        shown = sum("image/png" in o.get("data", {}) for c in code for o in c.get("outputs", []))
        assert shown >= drawing, f"{name}: {shown} figures shown, {drawing} cells draw one"
    log = capfd.readouterr()
    noise = [line for line in (log.out + log.err).splitlines()
             if "WARNING" in line or "ERROR" in line]  # fmt: skip
    assert noise == [], noise[:3]  # a clean log: the kernels' own warnings are silenced


def test_run_notebooks_command_passes_its_parameters(monkeypatch: pytest.MonkeyPatch) -> None:
    import blurloc.runner
    from blurloc.cli import main

    calls = []
    monkeypatch.setattr(blurloc.runner, "run_notebooks", lambda **kwargs: calls.append(kwargs))
    assert main(["run-notebooks", "--data-root", "/data/7scenes", "--device", "cpu",
                 "05_results_figures"]) == 0  # fmt: skip
    assert calls == [{"quick": False, "names": ["05_results_figures"],
                      "parameters": {"data_root": "/data/7scenes", "device": "cpu"}}]  # fmt: skip


def test_every_equation_of_the_paper_is_stated_once() -> None:
    """Eq. 1-17 each appear, labelled, in the display math of exactly one notebook."""
    where: dict[int, list[str]] = {n: [] for n in range(1, 18)}
    for name in notebook_names():
        markdown = "".join("".join(c["source"]) for c in _cells(name)
                           if c["cell_type"] == "markdown")  # fmt: skip
        display = " ".join(markdown.split("$$")[1::2])
        for number in where:
            if re.search(rf"\(eq\. {number}[),]", display):
                where[number].append(name)
    assert {n: names for n, names in where.items() if len(names) != 1} == {}
