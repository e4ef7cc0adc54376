"""The project's folders are found from the working folder, not from the package's location."""

from __future__ import annotations

from pathlib import Path

import pytest

from blurloc import config


def test_the_project_is_found_from_a_folder_inside_it(
    make_project, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv(config.PROJECT_VARIABLE, raising=False)
    root = make_project(tmp_path / "project")
    inside = root / "notebooks" / "scratch"
    inside.mkdir()
    monkeypatch.chdir(inside)
    assert config.project_root() == root.resolve()
    assert config.RESULTS_DIR == root.resolve() / "results"
    assert config.default_data_root(quick=True) == root.resolve() / "data" / "standin-quick"


def test_the_variable_names_the_project(
    make_project, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    root = make_project(tmp_path / "elsewhere")
    monkeypatch.setenv(config.PROJECT_VARIABLE, str(root))
    monkeypatch.chdir(tmp_path)
    assert config.project_root() == root.resolve()
    monkeypatch.setenv(config.PROJECT_VARIABLE, str(tmp_path))
    with pytest.raises(FileNotFoundError, match=r"BLURLOC_ROOT=.* holds no notebooks"):
        config.project_root()


def test_outside_a_project_the_error_says_what_to_do(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv(config.PROJECT_VARIABLE, raising=False)
    (tmp_path / "notebooks").mkdir()  # a notebooks folder without the numbered notebooks
    with pytest.raises(FileNotFoundError, match="run from inside the project or set BLURLOC_ROOT"):
        config.project_root(tmp_path)
    with pytest.raises(AttributeError, match="SCRATCH_DIR"):
        config.SCRATCH_DIR  # noqa: B018
