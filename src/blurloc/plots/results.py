"""Figures that set measured numbers beside the paper (notebooks 02, 04, 05): the architecture
(Fig. 1), measured vs printed per-scene bars (Fig. 6-7 style) and measured/printed ratios."""

from __future__ import annotations

import itertools

import matplotlib.pyplot as plt
import numpy as np

from .style import METHOD_COLOURS, PAPER_COLOUR, styled


@styled
def plot_architecture(stages: list[list[str]], title: str) -> plt.Figure:
    """Fig. 1: the architecture as boxes, one column per stage in data-flow order; the
    alternatives of a stage (e.g. image or video deblurring) are stacked in its column.

    Parameters
    ----------
    stages : list of list of str
        Box texts per stage, built by the caller from the package's own objects, so that the
        figure follows the code.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure

    References
    ----------
    Fig. 1 of the paper.
    """
    colours = ["#eeeeee", "#fdd0a2", "#c6dbef", "#c7e9c0", "#dadaeb", "#fcbba1", "#eeeeee"]
    step, width = 2.45, 2.15
    figure, axis = plt.subplots(figsize=(2.0 * len(stages), 3.3))
    axis.set_xlim(-0.1, step * len(stages) - 0.2)
    axis.set_ylim(0, 3.6)
    axis.axis("off")
    centres = []
    for index, boxes in enumerate(stages):
        x = step * index + width / 2
        ys = np.linspace(2.6, 1.0, len(boxes)) if len(boxes) > 1 else [1.8]
        colour = colours[index % len(colours)]
        for y, text in zip(ys, boxes, strict=True):
            axis.add_patch(plt.Rectangle((x - width / 2, y - 0.55), width, 1.1, facecolor=colour,
                                         edgecolor="#333333", lw=0.8))  # fmt: skip
            axis.text(x, y, text, ha="center", va="center", fontsize=7, wrap=True)
        centres.append([(x, y) for y in ys])
    for left, right in itertools.pairwise(centres):
        for x0, y0 in left:
            for x1, y1 in right:
                arrow = {"arrowstyle": "->", "lw": 0.8, "color": "#333333"}
                axis.annotate("", (x1 - width / 2, y1), (x0 + width / 2, y0), arrowprops=arrow)
    axis.set_title(title)
    return figure


@styled
def plot_per_scene_metric(
    measured: dict[str, dict[str, float]],
    paper: dict[str, float],
    ylabel: str,
    title: str,
    spread: dict[str, dict[str, float]] | None = None,
    reference: dict[str, float] | None = None,
    reference_label: str = "mean training pose",
) -> plt.Figure:
    """Grouped bars per scene: each measured method, with its seed spread as error bars, and
    the paper's printed values (hatched grey, labelled "paper (printed)"); the y-axis starts at
    zero.

    Parameters
    ----------
    measured : dict
        ``{method: {scene: value}}``.
    paper : dict
        ``{scene: printed value}``; its scenes set the order.
    ylabel, title : str
        Axis label (with the unit) and title.
    spread : dict, optional
        ``{method: {scene: standard deviation over seeds}}``, drawn as error bars (± 1 sd).
    reference : dict, optional
        ``{scene: value}`` drawn as a black line across each scene's group (e.g. the error of
        predicting the mean training pose).
    reference_label : str
        Legend label of ``reference``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    scenes = list(paper)
    spread = spread or {}
    series = [(name, values, METHOD_COLOURS.get(name, None), None)
              for name, values in measured.items()]  # fmt: skip
    series.append(("paper (printed)", paper, PAPER_COLOUR, "//"))
    width = 0.8 / len(series)
    figure, axis = plt.subplots(figsize=(10, 3.6))
    for index, (name, values, colour, hatch) in enumerate(series):
        x = np.arange(len(scenes)) + (index - (len(series) - 1) / 2) * width
        heights = [values.get(scene, np.nan) for scene in scenes]
        errors = [spread.get(name, {}).get(scene, np.nan) for scene in scenes]
        axis.bar(x, heights, width, label=name, color=colour, hatch=hatch,
                 yerr=errors if name in spread else None, capsize=1.5,
                 error_kw={"elinewidth": 0.8},
                 edgecolor="white" if hatch is None else "#444444", linewidth=0.5)  # fmt: skip
    if reference:
        for index, scene in enumerate(scenes):
            if scene in reference:
                label = reference_label if index == 0 else None
                axis.hlines(reference[scene], index - 0.45, index + 0.45, colors="black",
                            linewidth=1.2, label=label)  # fmt: skip
    axis.set_xticks(np.arange(len(scenes)), scenes)
    axis.set_ylabel(ylabel)
    axis.set_title(title)
    axis.set_ylim(bottom=0)
    axis.legend(ncol=4, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12))
    return figure


@styled
def plot_paired_differences(rows: list[dict], title: str) -> plt.Figure:
    """Mean paired differences with their confidence intervals, one panel per metric, relative
    to the baseline's mean (a forest plot).

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`blurloc.experiments.comparisons.comparison_table`: ``comparison``,
        ``metric``, ``baseline_mean``, ``mean_difference``, ``ci_low``, ``ci_high``,
        ``interval`` and ``verdict``.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
        x: difference in % of the baseline's mean (negative: the other configuration has the
        lower error); a line at zero.
    """
    metrics = list(dict.fromkeys(r["metric"] for r in rows))
    comparisons = list(dict.fromkeys(r["comparison"] for r in rows))
    figure, axes = plt.subplots(1, len(metrics), figsize=(3.4 * len(metrics), 1.3
                                                          + 0.45 * len(comparisons)),
                                sharey=True, squeeze=False, layout="constrained")  # fmt: skip
    for axis, metric in zip(axes[0], metrics, strict=True):
        for y, comparison in enumerate(comparisons):
            row = next((r for r in rows if r["metric"] == metric
                        and r["comparison"] == comparison), None)  # fmt: skip
            if row is None:
                continue
            scale = 100.0 / row["baseline_mean"]
            low, high = row["ci_low"] * scale, row["ci_high"] * scale
            colour = "#2a7" if high < 0 else "#c33" if low > 0 else "#555"
            axis.errorbar(row["mean_difference"] * scale, y,
                          xerr=[[row["mean_difference"] * scale - low],
                                [high - row["mean_difference"] * scale]],
                          fmt="o", color=colour, capsize=3)  # fmt: skip
        axis.axvline(0, color="black", linewidth=0.8)
        axis.set_title(metric, fontsize=9)
        axis.set_xlabel("difference (% of baseline)")
    axes[0][0].set_yticks(range(len(comparisons)), comparisons)
    axes[0][0].invert_yaxis()
    interval = rows[0]["interval"] if rows else ""
    figure.suptitle(f"{title}\n(mean paired difference, {interval} interval)", fontsize=10)
    return figure


@styled
def plot_ratios(groups: dict[str, list[float]], title: str) -> plt.Figure:
    """Measured / printed ratios, one column of dots per group, on a log scale with the line
    of agreement at 1.

    Parameters
    ----------
    groups : dict
        ``{label: [ratios]}``.
    title : str
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    figure, axis = plt.subplots(figsize=(9, 3.2))
    for index, ratios in enumerate(groups.values()):
        spread = np.linspace(-0.15, 0.15, len(ratios))
        axis.plot(np.full(len(ratios), index) + spread, ratios, "o", ms=4, alpha=0.8)
    axis.axhline(1.0, color="#555555", ls=":")
    axis.set_yscale("log")
    axis.set_xticks(range(len(groups)), list(groups), rotation=35, ha="right", fontsize=7)
    axis.set_ylabel("measured / printed")
    axis.set_title(title)
    return figure
