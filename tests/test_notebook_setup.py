"""The one set-up call every notebook starts with."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from blurloc.notebook import setup


def test_empty_parameters_give_the_project_folders(
    make_project, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    root = make_project(tmp_path).resolve()
    monkeypatch.setenv("BLURLOC_ROOT", str(root))
    found = setup(True, 0, prepare_data=False)
    assert found == (root / "data" / "standin-quick", root / "results", root / "figures", None)
    assert setup(False, 0, device="cpu", prepare_data=False).device == "cpu"


def test_given_folders_are_kept_and_the_generators_seeded(tmp_path: Path) -> None:
    data, results, figures, _ = setup(False, 7, tmp_path / "d", "r", "f", prepare_data=False)
    first = np.random.rand()  # noqa: NPY002 (the global generator the set-up seeds)
    setup(False, 7, tmp_path / "d", "r", "f", prepare_data=False)
    assert (data, results, figures) == (tmp_path / "d", Path("r"), Path("f"))
    assert np.random.rand() == first  # noqa: NPY002


def test_a_foreign_dataset_is_left_untouched(tmp_path: Path) -> None:
    (tmp_path / "chess").mkdir()
    (tmp_path / "chess" / "note.txt").write_text("real 7-Scenes")
    setup(True, 0, tmp_path, "r", "f")
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["chess", "note.txt"]


def test_an_unknown_device_is_refused() -> None:
    with pytest.raises(ValueError, match="--device 'gpu0'"):
        setup(True, 0, "d", "r", "f", device="gpu0", prepare_data=False)


def test_progress_bars_only_in_a_full_run_by_a_person(monkeypatch: pytest.MonkeyPatch) -> None:
    from blurloc.config import HEADLESS_VARIABLE
    from blurloc.notebook import show_progress

    monkeypatch.delenv(HEADLESS_VARIABLE, raising=False)
    assert show_progress(False) and not show_progress(True)
    monkeypatch.setenv(HEADLESS_VARIABLE, "1")  # set by the notebook runner
    assert not show_progress(False)
