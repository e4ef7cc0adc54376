"""What reproduced: every printed number beside the number this package measured for the same
quantity, and the paper's errata computed from its own printed numbers.

The measured side is read from the files the notebooks write under ``results/`` (never from
the paper): ``deblur_single_image.csv`` (notebook 02) and ``pose_summary.csv`` (notebook 04).
"""

from __future__ import annotations

import csv
import os
from collections import defaultdict
from pathlib import Path

import numpy as np

from .experiments.comparisons import per_scene_mean
from .experiments.rows import grouped_means
from .paper import reported_numbers

#: Scene order of the paper's tables.
SCENE_ORDER = ("chess", "fire", "heads", "office", "pumpkin", "redkitchen", "stairs")

#: Table III methods whose rows the paper copied from an original publication (our CSV name).
ORIGINAL_PUBLICATION_NAMES = {"PoseNet": "PoseNet15", "MapNet": "MapNet", "AtLoc": "AtLoc"}

#: What each printed item is compared with (the measured counterpart), in words.
MEASURED_COUNTERPARTS = {
    "fig6": "blind Wiener (notebook 02): mean PSNR of the scene's stand-in test frames",
    "fig7": "blind Wiener (notebook 02): mean SSIM of the scene's stand-in test frames",
    "table1": "LSTM trained and tested on blurred stand-in frames (notebook 04)",
    "table2": "LSTM trained and tested on network-deblurred stand-in frames (notebook 04)",
    "Proposed": "LSTM on network-deblurred stand-in frames: median error per scene; "
                "average = mean of the scene medians (notebook 04)",
}  # fmt: skip

#: Ranking claims the paper's text makes about its own printed numbers:
#: (where, claim, item, method, metric, "min" or "max", the scene the text names).
TEXT_CLAIMS = (
    ("IV.B, Fig. 6", "heads has the lowest PSNR (28.23)", "fig6", "proposed_wiener", "psnr_db",
     "min", "heads"),
    ("IV.B, Fig. 6", "heads has the highest PSNR (31.96)", "fig6", "proposed_wiener", "psnr_db",
     "max", "heads"),
    ("IV.C, Fig. 8", "stairs has the largest position error (0.19 m)", "table3", "Proposed",
     "position_m", "max", "stairs"),
    ("IV.C, Fig. 9", "heads has the worst orientation error (9.75°); range 3.01°-9.75°",
     "table3", "Proposed", "orientation_deg", "max", "heads"),
    ("IV.C, Fig. 9", "pumpkin has the lowest orientation error (3.01°)", "table3", "Proposed",
     "orientation_deg", "min", "pumpkin"),
    ("IV.D, Table I", "fire has the lowest error of the seven scenes (combined 0.0379)",
     "table1", "proposed_blurred", "combined", "min", "fire"),
    ("IV.D, Table I", "chess has the largest error (combined 0.0387)", "table1",
     "proposed_blurred", "combined", "max", "chess"),
    ("IV.D, Table II", "stairs has the lowest MAE (0.0643)", "table2", "proposed_deblurred",
     "mae", "min", "stairs"),
    ("IV.D, Table II", "pumpkin has the highest MAE (0.0761)", "table2", "proposed_deblurred",
     "mae", "max", "pumpkin"),
    ("IV.D, Table II", "fire has the lowest RMSE (0.0789)", "table2", "proposed_deblurred",
     "rmse", "min", "fire"),
    ("IV.D, Table II", "redkitchen has the highest RMSE (0.0973)", "table2",
     "proposed_deblurred", "rmse", "max", "redkitchen"),
)  # fmt: skip

_POSE_METRICS = {
    "mae": "mae",
    "mse": "mse",
    "rmse": "rmse",
    "combined": "combined",
    "position_m": "position_m_median",
    "orientation_deg": "orientation_deg_median",
}


def _read_csv(path: Path) -> list[dict]:
    if not path.is_file():
        raise FileNotFoundError(f"{path} is missing: run the notebook that writes it first")
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def measured_numbers(results_dir: str | os.PathLike) -> dict[tuple[str, str, str, str], float]:
    """This package's measured counterparts of the printed numbers.

    See :data:`MEASURED_COUNTERPARTS` for what each one is.

    Parameters
    ----------
    results_dir : str or os.PathLike
        Folder holding ``deblur_single_image.csv`` (notebook 02) and ``pose_summary.csv``
        (notebook 04).

    Returns
    -------
    dict
        ``{(item, method, scene, metric): value}``, keyed like the paper's rows (PSNR in dB,
        positions in metres, orientations in degrees).
    """
    results_dir = Path(results_dir)
    measured: dict[tuple[str, str, str, str], float] = {}

    frames = _read_csv(results_dir / "deblur_single_image.csv")
    for item, metric in (("fig6", "psnr_db"), ("fig7", "ssim")):
        means = grouped_means(frames, "scene", metric, {"method": "blind_wiener"})
        for scene, value in means.items():
            measured[(item, "proposed_wiener", scene, metric)] = value

    summary = _read_csv(results_dir / "pose_summary.csv")
    for item, method, condition, metrics in (
        ("table1", "proposed_blurred", "blurred", ("mae", "mse", "rmse", "combined")),
        ("table2", "proposed_deblurred", "rnn", ("mae", "mse", "rmse", "combined")),
        ("table3", "Proposed", "rnn", ("position_m", "orientation_deg")),
    ):
        run = {"condition": condition, "head": "lstm"}
        for metric in metrics:
            values = per_scene_mean(summary, _POSE_METRICS[metric], run)  # mean over seeds
            for scene, value in values.items():
                measured[(item, method, scene, metric)] = value
            if item == "table3" and values:
                measured[(item, method, "average", metric)] = float(np.mean(list(values.values())))
    return measured


def _counterpart(row: dict, measured: dict) -> float | None:
    key = (row["item"], row["method"], row["scene"], row["metric"])
    if key in measured:
        return measured[key]
    if row["method"] == "Proposed":  # the abstract and the text repeat Table III's quantities
        return measured.get(("table3", "Proposed", row["scene"], row["metric"]))
    return None


def paper_vs_reproduction(measured: dict[tuple[str, str, str, str], float]) -> list[dict]:
    """Every printed number beside the measured number for the same quantity.

    Parameters
    ----------
    measured : dict
        :func:`measured_numbers`.

    Returns
    -------
    list of dict
        One row per row of reported_numbers.csv: source, item, method, scene, metric,
        printed, measured (empty where this package measures none, e.g. the compared
        methods), ratio (measured / printed) and measured_as (what was measured).
    """
    rows = []
    for row in reported_numbers():
        value = _counterpart(row, measured)
        what = MEASURED_COUNTERPARTS.get(
            "Proposed" if row["method"] == "Proposed" else row["item"], ""
        )
        rows.append({
            "source": row["source"], "item": row["item"], "method": row["method"],
            "scene": row["scene"], "metric": row["metric"], "printed": row["value"],
            "measured": "" if value is None else round(value, 4),
            "ratio": "" if value is None or row["value"] == 0 else round(value / row["value"], 3),
            "measured_as": what if value is not None else "",
        })  # fmt: skip
    return rows


def ratios_by_item(comparison: list[dict]) -> dict[str, list[float]]:
    """Measured ÷ printed ratios grouped by printed item and metric.

    Parameters
    ----------
    comparison : list of dict
        :func:`paper_vs_reproduction`; rows without a measured counterpart are left out.

    Returns
    -------
    dict of str to list of float
        ``{"item · metric": [ratio, ...]}`` in order of first appearance.
    """
    groups: dict[str, list[float]] = {}
    for row in comparison:
        if row["measured"] != "":
            groups.setdefault(f"{row['item']} · {row['metric']}", []).append(row["ratio"])
    return groups


def proposed_measured_vs_printed(
    comparison: list[dict], item: str, metric: str, scene: str = "average"
) -> str:
    """One number of the paper's own method, measured beside printed, as text.

    Parameters
    ----------
    comparison : list of dict
        :func:`paper_vs_reproduction`.
    item, metric : str
        Printed item (e.g. ``table3``) and metric (e.g. ``position_m``).
    scene : str
        Scene name or ``average``.

    Returns
    -------
    str
        ``"<measured> (printed <printed>)"``, measured to two decimals.
    """
    row = next(r for r in comparison if r["item"] == item and r["metric"] == metric
               and r["method"] == "Proposed" and r["scene"] == scene)  # fmt: skip
    return f"{row['measured']:.2f} (printed {row['printed']:g})"


def _groups(item: str | None = None) -> dict[tuple[str, str, str, str], dict[str, float]]:
    """{(source, item, method, metric): {scene: value}} over the printed rows."""
    groups: dict[tuple[str, str, str, str], dict[str, float]] = defaultdict(dict)
    for row in reported_numbers():
        if item is None or row["item"] == item:
            key = (row["source"], row["item"], row["method"], row["metric"])
            groups[key][row["scene"]] = row["value"]
    return groups


def _rounding(value: float) -> float:
    """Half a unit in the last printed decimal of ``value`` (10.4 -> 0.05, 7.78 -> 0.005)."""
    decimals = len(repr(float(value)).split(".")[1].rstrip("0")) if "." in repr(value) else 0
    return 0.5 * 10.0**-decimals


def average_errata() -> list[dict]:
    """Printed averages against the mean of the same row's printed per-scene values.

    ``agrees`` is False where the two differ by more than rounding explains (half a unit in
    the last decimal of the average plus half a unit of the per-scene values).

    Returns
    -------
    list of dict
        Rows with kind, where, metric, printed, recomputed, agrees (bool), detail.
    """
    rows = []
    for (_, item, method, metric), values in _groups().items():
        scenes = [v for s, v in values.items() if s != "average"]
        if "average" not in values or len(scenes) < 2:
            continue
        mean = float(np.mean(scenes))
        tolerance = _rounding(values["average"]) + max(_rounding(v) for v in scenes)
        rows.append({
            "kind": "average", "where": f"{item} {method}", "metric": metric,
            "printed": values["average"], "recomputed": round(mean, 3),
            "agrees": abs(mean - values["average"]) <= tolerance + 1e-9,
            "detail": f"mean of its {len(scenes)} per-scene values",
        })  # fmt: skip
    return rows


def repeated_number_errata() -> list[dict]:
    """Numbers printed twice (abstract or text and Table III) that disagree.

    Returns
    -------
    list of dict
        Rows with kind, where, metric, printed, recomputed, agrees (bool), detail.
    """
    table3 = {(r["method"], r["scene"], r["metric"]): r["value"]
              for r in reported_numbers() if r["item"] == "table3"}  # fmt: skip
    rows = []
    for row in reported_numbers():
        if row["source"] != "seed" or row["item"] in ("table3", "fig6", "fig7", "table1",
                                                       "table2"):  # fmt: skip
            continue
        other = table3.get((row["method"], row["scene"], row["metric"]))
        if other is None:
            continue
        rows.append({
            "kind": "repeated", "where": f"{row['item']} {row['method']} {row['scene']}",
            "metric": row["metric"], "printed": row["value"], "recomputed": other,
            "agrees": bool(np.isclose(row["value"], other)),
            "detail": "Table III prints the second value",
        })  # fmt: skip
    return rows


def publication_errata() -> list[dict]:
    """Table III's rows for compared methods against their original publications.

    Returns
    -------
    list of dict
        Rows with kind, where, metric, printed, recomputed, agrees (bool), detail.
    """
    printed = _groups("table3")
    original = _groups("median_7scenes")
    rows = []
    for method, published in ORIGINAL_PUBLICATION_NAMES.items():
        for metric in ("position_m", "orientation_deg"):
            ours = printed.get(("seed", "table3", method, metric), {})
            theirs = original.get(("original_publication", "median_7scenes", published, metric),
                                  {})  # fmt: skip
            for scene in ours:
                if scene in theirs:
                    rows.append({
                        "kind": "publication", "where": f"table3 {method} {scene}",
                        "metric": metric, "printed": ours[scene], "recomputed": theirs[scene],
                        "agrees": bool(np.isclose(ours[scene], theirs[scene])),
                        "detail": f"{published} as originally published",
                    })  # fmt: skip
    return rows


def text_claim_errata() -> list[dict]:
    """The text's ranking claims (:data:`TEXT_CLAIMS`) checked against the printed numbers.

    Returns
    -------
    list of dict
        Rows with kind, where, metric, printed, recomputed, agrees (bool), detail.
    """
    rows = []
    for where, claim, item, method, metric, extreme, scene in TEXT_CLAIMS:
        values = {s: v for s, v in _groups(item)[("seed", item, method, metric)].items()
                  if s != "average"}  # fmt: skip
        pick = min if extreme == "min" else max
        best = pick(values, key=values.get)
        ties = sorted(s for s, v in values.items() if np.isclose(v, values[best]))
        rows.append({
            "kind": "text claim", "where": where, "metric": metric,
            "printed": f"{scene} ({values[scene]:g})",
            "recomputed": ", ".join(f"{s} ({values[s]:g})" for s in ties),
            "agrees": ties == [scene], "detail": claim,
        })  # fmt: skip
    return rows


def printing_notes() -> list[dict]:
    """How the tables and figures were printed (wrong column names, units, typos, scene
    names), one row per note and printed item; ``agrees`` is always False.

    Returns
    -------
    list of dict
        Rows with kind, where, metric, printed, recomputed, agrees (bool), detail.
    """
    scenes: dict[tuple[str, str, str, str], list[str]] = defaultdict(list)
    for row in reported_numbers():
        if (
            row["note"]
            and row["source"] == "seed"
            and row["item"] in ("fig6", "fig7", "table1", "table2", "table3")
        ):
            scenes[(row["item"], row["method"], row["metric"], row["note"])].append(row["scene"])
    return [
        {"kind": "printing", "where": f"{item} {method} {', '.join(names)}", "metric": metric,
         "printed": "", "recomputed": "", "agrees": False, "detail": note}
        for (item, method, metric, note), names in scenes.items()
    ]  # fmt: skip


def errata() -> list[dict]:
    """Every check on the paper's printed numbers: averages, repeated numbers, copied rows,
    text claims, printing notes. Filter on ``agrees`` is False for the disagreements.

    Returns
    -------
    list of dict
        Rows with kind, where, metric, printed, recomputed, agrees (bool), detail.
    """
    return (average_errata() + repeated_number_errata() + publication_errata()
            + text_claim_errata() + printing_notes())  # fmt: skip


def pose_comparison_rows(measured: dict[str, dict[str, tuple[float, float]]]) -> list[dict]:
    """Table III: per-scene pose errors as printed, as originally published by the compared
    methods, and as measured here; cells formatted like the paper's ("0.14 m, 3.76°").

    Parameters
    ----------
    measured : dict
        ``{label: {scene: (position m, orientation degrees)}}``, scene ``average`` included.

    Returns
    -------
    list of dict
        One labelled row per method and source (source, method, one cell per scene).

    References
    ----------
    Table III of the paper.
    """
    rows = []

    def add(source: str, method: str, values: dict[str, tuple[float, float]]) -> None:
        row = {"source": source, "method": method}
        for scene in (*SCENE_ORDER, "average"):
            position, orientation = values.get(scene, (np.nan, np.nan))
            cells = []
            if np.isfinite(position):
                cells.append(f"{position:.2f} m")
            if np.isfinite(orientation):
                cells.append(f"{orientation:.2f}°")
            row[scene] = ", ".join(cells) or "-"
        rows.append(row)

    for source, item, label in (("seed", "table3", "paper (Table III)"),
                                ("original_publication", "median_7scenes",
                                 "original publication")):  # fmt: skip
        groups = _groups(item)
        methods = dict.fromkeys(method for (_, _, method, _) in groups)
        for method in methods:
            position = groups.get((source, item, method, "position_m"), {})
            orientation = groups.get((source, item, method, "orientation_deg"), {})
            add(label, method, {s: (position.get(s, np.nan), orientation.get(s, np.nan))
                                for s in set(position) | set(orientation)})  # fmt: skip
    for method, values in measured.items():
        add("measured (stand-in)", method, values)
    return rows
