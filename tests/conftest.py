"""Shared fixtures: one quick stand-in rendered once per test session, and empty projects."""

from __future__ import annotations

from pathlib import Path

import pytest

from blurloc.data.synth import SynthConfig, synthesize


@pytest.fixture(scope="session")
def quick_root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Two scenes of the quick stand-in (one training and one test sequence of 8 frames each)."""
    root = tmp_path_factory.mktemp("standin")
    return synthesize(
        root,
        scenes=["chess", "stairs"],
        config=SynthConfig.quick(),
        seed=3,
        workers=1,
        progress=False,
    )


@pytest.fixture
def make_project():
    """A function that makes ``folder`` a minimal blurloc project (a ``notebooks/`` folder with
    one numbered notebook) and returns it."""

    def make(folder: Path) -> Path:
        (folder / "notebooks").mkdir(parents=True)
        (folder / "notebooks" / "00_first.ipynb").write_text("{}")
        return folder

    return make
