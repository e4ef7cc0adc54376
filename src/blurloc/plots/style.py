"""The one style of every figure, applied through :func:`matplotlib.pyplot.style.context` around
each figure function (no global matplotlib state changes), its colours, and saving."""

from __future__ import annotations

import contextlib
import functools
import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import ParamSpec, TypeVar

import matplotlib
import matplotlib.pyplot as plt
import numpy as np

#: rcParams of every figure of the package.
STYLE = {
    "figure.dpi": 110,
    "savefig.dpi": 150,
    "savefig.bbox": "tight",
    "font.size": 9,
    "axes.titlesize": 10,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "legend.frameon": False,
}
SPLIT_COLOURS = {"train": "#1f77b4", "test": "#d62728"}
#: Printed (paper) values: hatched grey.
PAPER_COLOUR = "#999999"
METHOD_COLOURS = {
    "blurred": "#555555",
    "blind_wiener": "#1f77b4",
    "skimage_wiener": "#ff7f0e",
    "unsupervised_wiener": "#2ca02c",
    "richardson_lucy": "#9467bd",
    "wiener": "#1f77b4",
    "rnn": "#d62728",
    "sharp": "#2ca02c",
}

_P = ParamSpec("_P")
_R = TypeVar("_R")


@contextlib.contextmanager
def figure_style() -> Iterator[None]:
    """The package's style as a context manager, for figures drawn outside this package.

    The rcParams of STYLE hold inside and are restored on exit, except interactive mode: a
    notebook's inline backend switches it on when it loads with the first figure, and
    restoring it would leave every later figure of the notebook unshown.

    Yields
    ------
    None
        Inside ``plt.style.context(STYLE)``.
    """
    with plt.style.context(STYLE):
        try:
            yield
        finally:
            interactive = matplotlib.is_interactive()
    matplotlib.interactive(interactive)


def styled(function: Callable[_P, _R]) -> Callable[_P, _R]:
    """Decorate a figure function so that it draws inside :func:`figure_style`.

    Parameters
    ----------
    function : callable
        Returns a figure.

    Returns
    -------
    callable
        The same function, run within ``plt.style.context(STYLE)``.
    """

    @functools.wraps(function)
    def draw(*args: _P.args, **kwargs: _P.kwargs) -> _R:
        with figure_style():
            return function(*args, **kwargs)

    return draw


def save_figure(figure: plt.Figure, folder: str | os.PathLike, name: str) -> list[Path]:
    """Save a figure as PNG and PDF (PDF without a creation date, so reruns are identical).

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure.
    folder : str or os.PathLike
        Output folder (created).
    name : str
        File stem.

    Returns
    -------
    list of pathlib.Path
        ``<folder>/<name>.png`` and ``.pdf`` (150 dpi, tight bounding box).
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = [folder / f"{name}.png", folder / f"{name}.pdf"]
    with figure_style():
        for path in paths:
            figure.savefig(path, metadata={"CreationDate": None} if path.suffix == ".pdf" else None)
    return paths


def image_axis(axis: plt.Axes, image: np.ndarray, title: str, cmap: str = "gray") -> None:
    """Show an image without ticks (float images clipped to [0, 1]) under a title.

    Parameters
    ----------
    axis : matplotlib.axes.Axes
        Where to draw.
    image : numpy.ndarray
        (H, W) or (H, W, 3), uint8 or float in [0, 1].
    title : str
        Axis title.
    cmap : str
        Colour map of gray images.
    """
    axis.imshow(np.clip(image, 0, 1) if image.dtype != np.uint8 else image, cmap=cmap)
    axis.set_title(title)
    axis.axis("off")


def label_metres_3d(axis: plt.Axes, labelpad: float = 0.0) -> None:
    """Label the x, y and z axes of a 3-D axis in metres.

    Parameters
    ----------
    axis : mpl_toolkits.mplot3d.axes3d.Axes3D
        A 3-D axis (``projection="3d"``).
    labelpad : float
        Space between the ticks and the labels, points (negative in small panels).
    """
    axis.set_xlabel("x (m)", labelpad=labelpad)
    axis.set_ylabel("y (m)", labelpad=labelpad)
    axis.set_zlabel("z (m)", labelpad=labelpad)
