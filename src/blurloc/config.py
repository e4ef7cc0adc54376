"""Paths anchored on the package file, the one seeding helper, and atomic result files."""

from __future__ import annotations

import csv
import os
import random
import tempfile
from pathlib import Path

import numpy as np

PACKAGE_DIR = Path(__file__).resolve().parent
REPO_ROOT = PACKAGE_DIR.parent.parent
NOTEBOOKS_DIR = REPO_ROOT / "notebooks"
DATA_DIR = REPO_ROOT / "data"
RESULTS_DIR = REPO_ROOT / "results"
FIGURES_DIR = REPO_ROOT / "figures"
BUILD_DIR = REPO_ROOT / "build"

DEFAULT_SEED = 0


def default_data_root(quick: bool = False) -> Path:
    """Where the synthetic stand-in lives: ``data/standin`` (or ``data/standin-quick``)."""
    return DATA_DIR / ("standin-quick" if quick else "standin")


def resolve_dir(path: str | os.PathLike | None, default: Path) -> Path:
    """``path`` as a Path, or ``default`` when it is None or empty (notebook parameters)."""
    return Path(path) if path else default


def seed_everything(seed: int) -> None:
    """Seed Python, NumPy and torch's generators.

    With the same seed, the trainers give the same numbers on CPU whatever the machine's thread
    count: they also fix torch's intra-op thread count while they run
    (:data:`blurloc.train.config.TRAIN_THREADS`), since CPU kernels split their sums among the
    threads and the rounding depends on the split. On CUDA some kernels are not deterministic.

    Parameters
    ----------
    seed : int
        Non-negative seed.
    """
    import torch  # here, so that commands that never touch torch start fast

    random.seed(seed)
    np.random.seed(seed)  # noqa: NPY002 (the global generator, for code that still uses it)
    torch.manual_seed(seed)


def write_rows(rows: list[dict], path: str | os.PathLike) -> Path:
    """Write ``rows`` (dicts with the same keys) as CSV, atomically: to a temporary file in the
    same folder, then renamed, so a reader never sees half a file."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=path.parent, suffix=".tmp", delete=False,
                                     newline="") as handle:  # fmt: skip
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    os.replace(handle.name, path)
    return path
