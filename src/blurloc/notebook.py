"""The set-up every notebook starts with: seeds, folders, the data and the device."""

from __future__ import annotations

import os
from pathlib import Path
from typing import NamedTuple

from .config import HEADLESS_VARIABLE, default_data_root, project_root, seed_everything
from .data.synth import prepare_data_root
from .train.loop import choose_device


class NotebookSetup(NamedTuple):
    """What a notebook's set-up cell resolved (unpack it in this order).

    Attributes
    ----------
    data_root : pathlib.Path
        The dataset the notebook reads (the stand-in, or a real 7-Scenes root).
    results_dir : pathlib.Path
        Where result files (CSV/JSON) that later notebooks read go.
    figures_dir : pathlib.Path
        Where figures and tables go.
    device : str or None
        The torch device (``"cpu"``, ``"cuda"``…), or None when the notebook asked for none.
    """

    data_root: Path
    results_dir: Path
    figures_dir: Path
    device: str | None


def setup(
    quick: bool,
    seed: int,
    data_root: str | os.PathLike = "",
    results_dir: str | os.PathLike = "",
    figures_dir: str | os.PathLike = "",
    device: str | None = None,
    prepare_data: bool = True,
) -> NotebookSetup:
    """Seed every generator, resolve the notebook's folders, make its data and pick its device.

    Parameters
    ----------
    quick : bool
        The notebook's quick mode (tiny stand-in, as in CI).
    seed : int
        Seed of Python's, NumPy's and torch's generators
        (:func:`blurloc.config.seed_everything`) and of the stand-in's render.
    data_root, results_dir, figures_dir : str or os.PathLike
        The notebook's parameters; empty means the project's default
        (``data/standin[-quick]``, ``results/``, ``figures/`` under
        :func:`blurloc.config.project_root`).
    device : str, optional
        ``"auto"``, ``"cpu"``, ``"cuda"``… (:func:`blurloc.train.loop.choose_device`); None
        for a notebook that runs nothing on a device.
    prepare_data : bool
        Render the stand-in at ``data_root`` if it is missing or out of date
        (:func:`blurloc.data.synth.prepare_data_root`; a real 7-Scenes root is left untouched).

    Returns
    -------
    NotebookSetup
        ``(data_root, results_dir, figures_dir, device)``.
    """
    seed_everything(seed)
    data = Path(data_root) if data_root else default_data_root(quick)
    if prepare_data:
        prepare_data_root(data, quick, seed, progress=show_progress(quick))
    chosen = None if device is None else str(choose_device(device))
    return NotebookSetup(
        data, _folder(results_dir, "results"), _folder(figures_dir, "figures"), chosen
    )


def show_progress(quick: bool) -> bool:
    """Whether a notebook's long loops draw progress bars.

    Only in a full run by a person: not in quick mode, and not when the notebook runner
    executes the notebook (it sets the environment variable ``BLURLOC_HEADLESS``), so that
    executed copies carry no progress-bar debris.

    Parameters
    ----------
    quick : bool
        The notebook's quick mode.

    Returns
    -------
    bool
        True to draw progress bars.
    """
    return not quick and not os.environ.get(HEADLESS_VARIABLE)


def _folder(given: str | os.PathLike, default: str) -> Path:
    return Path(given) if given else project_root() / default
