"""Paths anchored on the package file, the one seeding helper, and atomic result files."""

from __future__ import annotations

import csv
import os
import random
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .files import atomic_path

PACKAGE_DIR = Path(__file__).resolve().parent
REPO_ROOT = PACKAGE_DIR.parent.parent
NOTEBOOKS_DIR = REPO_ROOT / "notebooks"
DATA_DIR = REPO_ROOT / "data"
RESULTS_DIR = REPO_ROOT / "results"
FIGURES_DIR = REPO_ROOT / "figures"
BUILD_DIR = REPO_ROOT / "build"

DEFAULT_SEED = 0


def default_data_root(quick: bool = False) -> Path:
    """Where the synthetic stand-in lives.

    Parameters
    ----------
    quick : bool
        The tiny stand-in of the quick runs.

    Returns
    -------
    pathlib.Path
        ``data/standin`` (or ``data/standin-quick``) in the repository.
    """
    return DATA_DIR / ("standin-quick" if quick else "standin")


def resolve_dir(path: str | os.PathLike | None, default: Path) -> Path:
    """A folder given as a notebook parameter, or its default.

    Parameters
    ----------
    path : str or os.PathLike or None
        The parameter (None or empty: not given).
    default : pathlib.Path
        Used when ``path`` is not given.

    Returns
    -------
    pathlib.Path
    """
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


def write_rows(
    rows: list[dict], path: str | os.PathLike, columns: Sequence[str] | None = None
) -> Path:
    """Write ``rows`` as CSV, atomically (:func:`blurloc.files.atomic_path`).

    Parameters
    ----------
    rows : list of dict
        Rows with the same keys, in order.
    path : str or os.PathLike
        CSV file to write; a reader never sees half of it.
    columns : sequence of str, optional
        The header (default: the keys of the first row); needed when ``rows`` is empty.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    with atomic_path(path) as temporary, open(temporary, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(columns or rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    return path
