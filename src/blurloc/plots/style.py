"""The one style of every figure, applied through :func:`matplotlib.pyplot.style.context` around
each figure function (no global matplotlib state changes), its colours, and saving."""

from __future__ import annotations

import base64
import contextlib
import functools
import io
import os
import sys
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import NamedTuple, ParamSpec, TypeVar

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
    "blind_wiener_gradient": "#17becf",
    "blind_deblurring": "#8c564b",
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


class SavedFigure(NamedTuple):
    """The files of a saved figure and its alternative text.

    Attributes
    ----------
    png : pathlib.Path
        ``<name>.png`` (150 dpi).
    pdf : pathlib.Path
        ``<name>.pdf`` (no creation date).
    alt : str
        What the figure shows, in words, for a reader who cannot see it.
    """

    png: Path
    pdf: Path
    alt: str

    def _ipython_display_(self) -> None:
        """Show nothing: :func:`save_figure` has shown the figure already (once)."""


def describe_figure(figure: plt.Figure) -> str:
    """Alternative text of a figure from its own words: the title, then each panel's title and
    axis labels.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure.

    Returns
    -------
    str
        E.g. ``"Blur length. Panels: estimate (x: recorded extent, y: estimated length)."``;
        ``"A figure."`` for a figure without any text.
    """
    panels = []
    for axis in figure.axes:
        labels = [
            f"{name}: {text}"
            for name, text in (("x", axis.get_xlabel()), ("y", axis.get_ylabel()))
            if text
        ]
        heading = axis.get_title() or axis.get_title("left")
        if heading or labels:
            panels.append(heading + (f" ({', '.join(labels)})" if labels else ""))
    title = figure.get_suptitle().strip().rstrip(".")
    words = [f"{title}." if title else ""]
    if panels:
        words.append("Panels: " + "; ".join(dict.fromkeys(panels)) + ".")
    text = " ".join(word for word in words if word)
    return " ".join(text.split()) or "A figure."


def _in_notebook() -> bool:
    """Whether this code runs in a Jupyter kernel (IPython imported and serving a kernel)."""
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None else None
    return getattr(shell, "kernel", None) is not None


def show_figure(figure: plt.Figure, alt: str | None = None) -> None:
    """In a notebook, show a figure once with its alternative text and close it; elsewhere do
    nothing.

    The PNG (at the style's screen resolution, ``figure.dpi``) goes out with
    ``{"image/png": {"alt": alt}}`` as its output metadata (the convention
    nbconvert and notebook renderers read) and the alternative text as its plain-text form; the
    figure is then closed, so that the inline backend does not show it a second time.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure.
    alt : str, optional
        Alternative text; default :func:`describe_figure`.
    """
    if not _in_notebook():
        return
    from IPython.display import display

    alt = alt if alt is not None else describe_figure(figure)
    buffer = io.BytesIO()
    with figure_style():  # on screen at the figures' own resolution, not the files' 150 dpi
        figure.savefig(buffer, format="png", dpi=STYLE["figure.dpi"])
    png = base64.b64encode(buffer.getvalue()).decode("ascii")
    display({"image/png": png, "text/plain": alt}, raw=True, metadata={"image/png": {"alt": alt}})
    plt.close(figure)


def save_figure(
    figure: plt.Figure, folder: str | os.PathLike, name: str, alt: str | None = None
) -> SavedFigure:
    """Save a figure as PNG and PDF (PDF without a creation date, so reruns are identical); in a
    notebook, show it once with its alternative text and close it (:func:`show_figure`).

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure.
    folder : str or os.PathLike
        Output folder (created).
    name : str
        File stem.
    alt : str, optional
        Alternative text; default :func:`describe_figure`.

    Returns
    -------
    SavedFigure
        ``<folder>/<name>.png`` and ``.pdf`` (150 dpi, tight bounding box) and the alternative
        text. As a notebook cell's last value it shows nothing more.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    saved = SavedFigure(folder / f"{name}.png", folder / f"{name}.pdf",
                        alt if alt is not None else describe_figure(figure))  # fmt: skip
    with figure_style():
        for path in (saved.png, saved.pdf):
            figure.savefig(path, metadata={"CreationDate": None} if path.suffix == ".pdf" else None)
    show_figure(figure, saved.alt)
    return saved


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
