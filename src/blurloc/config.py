"""The project's folders (found from the working folder, not from where the package is
installed), the one seeding helper, and atomic result files."""

from __future__ import annotations

import csv
import os
import random
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .files import atomic_path

#: The environment variable that names the project folder, overriding the search.
PROJECT_VARIABLE = "BLURLOC_ROOT"

#: The environment variable the notebook runner sets: no progress bars in executed copies.
HEADLESS_VARIABLE = "BLURLOC_HEADLESS"

#: The project's folders, by the module attribute that names each (resolved when read).
PROJECT_FOLDERS = {
    "NOTEBOOKS_DIR": "notebooks",
    "DATA_DIR": "data",
    "RESULTS_DIR": "results",
    "FIGURES_DIR": "figures",
    "BUILD_DIR": "build",
}

DEFAULT_SEED = 0


def _is_project(folder: Path) -> bool:
    return any((folder / "notebooks").glob("[0-9][0-9]_*.ipynb"))


def project_root(start: str | os.PathLike | None = None) -> Path:
    """The project folder: the one holding ``notebooks/`` with the numbered notebooks.

    Parameters
    ----------
    start : str or os.PathLike, optional
        Where the search starts (default: the working folder); it goes up from there.

    Returns
    -------
    pathlib.Path
        The folder named by the environment variable ``BLURLOC_ROOT`` when it is set, else the
        nearest folder at or above ``start`` holding ``notebooks/NN_*.ipynb``.

    Raises
    ------
    FileNotFoundError
        Naming the folder searched from (or the variable's value) when no project is found.
    """
    named = os.environ.get(PROJECT_VARIABLE)
    if named:
        if not _is_project(Path(named)):
            raise FileNotFoundError(
                f"{PROJECT_VARIABLE}={named} holds no notebooks/NN_*.ipynb: "
                "point it at the blurloc project folder"
            )
        return Path(named).resolve()
    here = Path(start or Path.cwd()).resolve()
    for folder in (here, *here.parents):
        if _is_project(folder):
            return folder
    raise FileNotFoundError(
        f"no blurloc project (a folder holding notebooks/NN_*.ipynb) at or above {here}: "
        f"run from inside the project or set {PROJECT_VARIABLE}"
    )


def __getattr__(name: str) -> Path:
    """``NOTEBOOKS_DIR``, ``DATA_DIR``, ``RESULTS_DIR``, ``FIGURES_DIR``, ``BUILD_DIR``: the
    project's folders (:func:`project_root`), found when read."""
    if name in PROJECT_FOLDERS:
        return project_root() / PROJECT_FOLDERS[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def default_data_root(quick: bool = False) -> Path:
    """Where the synthetic stand-in lives.

    Parameters
    ----------
    quick : bool
        The tiny stand-in of the quick runs.

    Returns
    -------
    pathlib.Path
        ``data/standin`` (or ``data/standin-quick``) in the project (:func:`project_root`).
    """
    return project_root() / "data" / ("standin-quick" if quick else "standin")


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
