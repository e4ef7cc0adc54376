"""Figures of pose regression (notebooks 04-05): training curves and predicted camera paths,
one frame through the pipeline (Fig. 2), views rendered at predicted poses (Fig. 5) and the
per-frame error distributions (Fig. 10)."""

from __future__ import annotations

import itertools
import textwrap

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import ConnectionPatch

from .style import METHOD_COLOURS, PAPER_COLOUR, label_metres_3d, styled


def _image_panel(axis: plt.Axes, panel: dict) -> None:
    axis.imshow(panel["image"], cmap=panel.get("cmap", "gray"), interpolation="nearest")
    axis.set_title(panel["title"], fontsize=8)
    axis.axis("off")


@styled
def plot_pipeline(
    panels: list[dict],
    truth: np.ndarray,
    predicted: np.ndarray,
    title: str = "",
    reference: dict | None = None,
) -> plt.Figure:
    """Fig. 2: one frame through the pipeline, panels in processing order joined by arrows,
    then the true and predicted camera path seen from above (x against z); optionally a
    reference image (e.g. the sharp ground truth) drawn apart, below the last image stage,
    with no arrow, since it is no stage of the pipeline.

    Parameters
    ----------
    panels : list of dict
        The stages, each with ``image`` (RGB, gray or a 2-D map), ``title`` and optional
        ``cmap``.
    truth, predicted : numpy.ndarray
        Camera positions (N, 3), metres.
    title : str
        Figure title (none when empty).
    reference : dict, optional
        A panel like those of ``panels`` shown for comparison only; its title is prefixed
        with "reference (not a stage):".

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Fig. 2 of the paper.
    """
    count = len(panels) + 1
    rows = 2 if reference else 1
    figure = plt.figure(figsize=(2.3 * count, 2.6 * rows + 0.2 * (rows - 1)))
    grid = figure.add_gridspec(rows, count)
    axes = [figure.add_subplot(grid[0, column]) for column in range(count)]
    for axis, panel in zip(axes, panels, strict=False):
        _image_panel(axis, panel)
    if reference:
        _image_panel(
            figure.add_subplot(grid[1, len(panels) - 1]),
            {**reference, "title": f"reference (not a stage):\n{reference['title']}"},
        )
    axis = axes[-1]
    axis.plot(truth[:, 0], truth[:, 2], "k-", lw=1.4, label="true")
    axis.plot(predicted[:, 0], predicted[:, 2], "-", color="#d62728", lw=1, label="predicted")
    axis.plot(*truth[-1, [0, 2]], "ko", ms=3)
    axis.plot(*predicted[-1, [0, 2]], "o", color="#d62728", ms=3)
    axis.set_aspect("equal", adjustable="datalim")
    axis.set_xlabel("x (m)")
    axis.set_ylabel("z (m)")
    axis.yaxis.set_label_position("right")
    axis.yaxis.tick_right()
    axis.set_title("pose (c, q): path from above", fontsize=8)
    axis.legend(fontsize=6)
    for left, right in itertools.pairwise(axes):
        figure.add_artist(ConnectionPatch((1.02, 0.5), (-0.02, 0.5), "axes fraction",
                                          "axes fraction", axesA=left, axesB=right,
                                          arrowstyle="->", color="#333333"))  # fmt: skip
    if title:
        figure.suptitle(title, y=1.04)
    return figure


@styled
def plot_predicted_views(
    views: dict[str, dict[str, np.ndarray]], captions: dict[str, str], title: str = ""
) -> plt.Figure:
    """Fig. 5: one column per scene, one row per kind of view (e.g. input, deblurred, ground
    truth, rendered at the predicted pose), captions under the columns.

    Parameters
    ----------
    views : dict
        ``{scene: {row label: image}}``, rows in the dicts' order, the same labels per scene.
    captions : dict
        ``{scene: caption}``, under the column (e.g. the shown frame's own errors).
    title : str
        Figure title (none when empty), wrapped to the figure's width.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Fig. 5 of the paper.
    """
    scenes = list(views)
    labels = list(views[scenes[0]])
    figure, axes = plt.subplots(len(labels), len(scenes), squeeze=False, layout="constrained",
                                figsize=(1.75 * len(scenes), 1.45 * len(labels) + 0.6))  # fmt: skip
    for column, scene in enumerate(scenes):
        for row, label in enumerate(labels):
            axis = axes[row, column]
            axis.imshow(views[scene][label])
            axis.set_xticks([])
            axis.set_yticks([])
            axis.grid(False)
            if row == 0:
                axis.set_title(scene, fontsize=8)
            if column == 0:
                axis.set_ylabel(label, fontsize=8)
        axes[-1, column].set_xlabel(captions.get(scene, ""), fontsize=7)
    if title:
        figure.suptitle(textwrap.fill(title, 16 * len(scenes)))
    return figure


@styled
def plot_error_distributions(
    errors: dict[str, dict[str, np.ndarray]],
    paper: dict[str, dict[str, float]] | None = None,
    ylabel: str = "combined error (eq. 14, per frame)",
    title: str = "",
) -> plt.Figure:
    """Fig. 10: per scene, the distribution of per-frame errors for each condition (violins,
    median marked); optionally a second panel with the paper's printed values as bars. Both
    error axes start at zero (errors are non-negative, and bars are compared by height).

    Parameters
    ----------
    errors : dict
        ``{scene: {condition: per-frame errors (N,)}}``.
    paper : dict, optional
        ``{label: {scene: printed value}}``, drawn hatched grey and labelled "paper".
    ylabel : str
        Label of the error axis.
    title : str
        Figure title (none when empty).

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Fig. 10 and eq. 14 of the paper.
    """
    scenes = list(errors)
    conditions = list(errors[scenes[0]])
    colours = [METHOD_COLOURS.get(c, f"C{i}") for i, c in enumerate(conditions)]
    panels = 2 if paper else 1
    figure, axes = plt.subplots(1, panels, figsize=(11, 3.6), squeeze=False,
                                gridspec_kw={"width_ratios": [3, 1.3][:panels]})  # fmt: skip
    axis = axes[0, 0]
    width = 0.8 / len(conditions)
    for index, (condition, colour) in enumerate(zip(conditions, colours, strict=True)):
        x = np.arange(len(scenes)) + (index - (len(conditions) - 1) / 2) * width
        data = [np.asarray(errors[scene][condition], float) for scene in scenes]
        parts = axis.violinplot(data, x, widths=width * 0.95, showextrema=False,
                                showmedians=True)  # fmt: skip
        for body in parts["bodies"]:
            body.set_facecolor(colour)
            body.set_alpha(0.6)
        parts["cmedians"].set_color("#222222")
        axis.plot([], [], "s", color=colour, alpha=0.6, label=condition)
    axis.set_xticks(np.arange(len(scenes)), scenes)
    axis.set_ylim(bottom=0)
    axis.set_ylabel(ylabel)
    axis.set_title("measured on the stand-in (violins: per-frame distribution, bar: median)")
    axis.legend(ncol=len(conditions), fontsize=7, loc="upper left")
    if paper:
        axis = axes[0, 1]
        width = 0.8 / len(paper)
        for index, (label, values) in enumerate(paper.items()):
            x = np.arange(len(scenes)) + (index - (len(paper) - 1) / 2) * width
            axis.bar(x, [values.get(s, np.nan) for s in scenes], width, label=label,
                     color=PAPER_COLOUR, alpha=1.0 - 0.45 * index, hatch="//",
                     edgecolor="#444444", linewidth=0.5)  # fmt: skip
        axis.set_xticks(np.arange(len(scenes)), scenes, rotation=60, fontsize=7)
        axis.set_title("paper (printed, 7-Scenes)")
        axis.set_ylim(0, max(max(v.values()) for v in paper.values()) * 1.25)
        axis.legend(fontsize=6, loc="upper left")
    if title:
        figure.suptitle(title, y=1.02)
    return figure


@styled
def plot_pose_training_curves(histories: dict[str, dict[str, list[float]]]) -> plt.Figure:
    """Pose training, one curve per head: the training loss (eq. 14) and the median validation
    position error (eq. 12) per epoch.

    Parameters
    ----------
    histories : dict
        ``{head: history}``, each history with ``epoch``, ``train_loss`` and
        ``val_position_m`` (metres) lists of the same length (``history.json`` of a run).

    Returns
    -------
    matplotlib.figure.Figure
        Two panels: loss, then validation position error.

    References
    ----------
    Eq. 12 and 14 of the paper.
    """
    figure, axes = plt.subplots(1, 2, figsize=(10, 3.2))
    for head, history in histories.items():
        axes[0].plot(history["epoch"], history["train_loss"], "o-", ms=3, label=head)
        axes[1].plot(history["epoch"], history["val_position_m"], "o-", ms=3, label=head)
    axes[0].set_xlabel("epoch")
    axes[0].set_ylabel("eq. 14 loss (training)")
    axes[1].set_xlabel("epoch")
    axes[1].set_ylabel("median validation position error (m)")
    axes[1].legend()
    return figure


@styled
def plot_predicted_paths(
    truth: np.ndarray, predicted: dict[str, np.ndarray], titles: dict[str, str]
) -> plt.Figure:
    """True and predicted camera paths in 3-D (axes in metres), one panel per prediction.

    Parameters
    ----------
    truth : numpy.ndarray
        True camera positions (N, 3), metres.
    predicted : dict
        ``{label: predicted positions (N, 3)}``, one panel each, in the dict's order.
    titles : dict
        ``{label: panel title}``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    figure = plt.figure(figsize=(5 * len(predicted), 4))
    for column, (label, positions) in enumerate(predicted.items()):
        axis = figure.add_subplot(1, len(predicted), column + 1, projection="3d")
        axis.plot(*truth.T, "k-", lw=1.5, label="true")
        axis.plot(*positions.T, "-", color="#d62728", lw=1, label="predicted")
        axis.set_title(titles[label])
        label_metres_3d(axis)
        axis.legend(fontsize=7)
    return figure


@styled
def plot_dose_response(table: list[dict], title: str) -> plt.Figure:
    """Pose error against blur strength, blurred vs deblurred input, and their paired
    difference with its interval.

    Parameters
    ----------
    table : list of dict
        Rows of :func:`blurloc.experiments.dose.dose_response_table`, one per blur strength.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        Three panels against the frames' median blur (px): the median position error (m) of
        each input; the paired difference deblurred - blurred in position (m) and in
        orientation (degrees), each with its 95 % interval and a line at zero.
    """
    blur = np.array([row["frame_median_blur_px"] for row in table])
    figure, axes = plt.subplots(1, 3, figsize=(11, 3.6), layout="constrained")
    for key, label in (("blurred_position_m", "blurred"), ("deblurred_position_m", "deblurred")):
        axes[0].plot(blur, [row[key] for row in table], "o-", label=label,
                     color=METHOD_COLOURS.get(label))  # fmt: skip
    axes[0].set(xlabel="median blur in the frames (px)", ylabel="median position error (m)",
                title="Error by input")  # fmt: skip
    axes[0].set_ylim(bottom=0)
    axes[0].legend(fontsize=8)
    for axis, prefix, unit in ((axes[1], "position", "m"), (axes[2], "orientation", "°")):
        key = "position_difference_m" if prefix == "position" else "orientation_difference_deg"
        means = np.array([row[key] for row in table])
        low = np.array([row[f"{prefix}_ci_low"] for row in table])
        high = np.array([row[f"{prefix}_ci_high"] for row in table])
        axis.errorbar(blur, means, yerr=[means - low, high - means], fmt="o-", capsize=3,
                      color="#555")  # fmt: skip
        axis.axhline(0, color="black", linewidth=0.8)
        axis.set(xlabel="median blur in the frames (px)",
                 ylabel=f"deblurred − blurred ({unit})",
                 title=f"{prefix.capitalize()}: paired difference\n(95 % interval)")  # fmt: skip
    figure.suptitle(title, fontsize=10)
    return figure
