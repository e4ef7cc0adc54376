"""Paper vs reproduction and the errata: computed from the printed numbers, measured side read
from result files; and every figure the README and docs/ show is one a notebook or a benchmark
writes."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest

from blurloc.config import FIGURES_DIR, NOTEBOOKS_DIR
from blurloc.paper import paper_values, reported_numbers
from blurloc.reproduction import (
    SCENE_ORDER,
    _rounding,
    average_errata,
    measured_numbers,
    paper_vs_reproduction,
    pose_comparison_rows,
    publication_errata,
    repeated_number_errata,
    text_claim_errata,
)
from blurloc.runner import EXPECTED_OUTPUTS

REPOSITORY = Path(__file__).resolve().parents[1]
PAGES = [REPOSITORY / "README.md", *sorted((REPOSITORY / "docs").glob("*.md"))]


def _find(rows: list[dict], where: str, metric: str) -> dict:
    return next(r for r in rows if r["where"] == where and r["metric"] == metric)


def test_rounding_tolerance_follows_the_printed_decimals() -> None:
    assert _rounding(10.4) == pytest.approx(0.05)
    assert _rounding(7.78) == pytest.approx(0.005)
    assert _rounding(19.0) == pytest.approx(0.5)


def test_table3_averages_against_their_own_scenes() -> None:
    rows = average_errata()
    proposed = _find(rows, "table3 Proposed", "orientation_deg")
    assert proposed["printed"] == 5.31
    assert proposed["recomputed"] == pytest.approx(6.259, abs=1e-3)  # the CSV's note says 6.26
    assert proposed["agrees"] is False
    assert _find(rows, "table3 Proposed", "position_m")["agrees"] is True
    assert _find(rows, "table3 AtLoc", "orientation_deg")["agrees"] is True
    # 10.4 printed to one decimal: 10.437 is within rounding
    assert _find(rows, "median_7scenes PoseNet15", "orientation_deg")["agrees"] is True


def test_numbers_printed_twice() -> None:
    rows = repeated_number_errata()
    abstract = _find(rows, "abstract Proposed average", "orientation_deg")
    assert (abstract["printed"], abstract["recomputed"], abstract["agrees"]) == (5.61, 5.31, False)
    deep = _find(rows, "abstract DeepAttention average", "position_m")
    assert (deep["printed"], deep["recomputed"], deep["agrees"]) == (19.0, 0.19, False)
    assert _find(rows, "abstract Proposed average", "position_m")["agrees"] is True


def test_compared_rows_against_original_publications() -> None:
    rows = publication_errata()
    assert all(r["agrees"] for r in rows if r["where"].startswith("table3 AtLoc"))
    chess = _find(rows, "table3 PoseNet chess", "orientation_deg")
    assert (chess["printed"], chess["recomputed"], chess["agrees"]) == (4.06, 8.12, False)


def test_text_claims_are_checked_against_the_tables() -> None:
    rows = {r["detail"]: r for r in text_claim_errata()}
    lowest = rows["fire has the lowest error of the seven scenes (combined 0.0379)"]
    assert lowest["agrees"] is False and lowest["recomputed"].startswith("stairs")
    assert rows["chess has the largest error (combined 0.0387)"]["agrees"] is True
    assert rows["pumpkin has the lowest orientation error (3.01°)"]["agrees"] is True


def _write(path: Path, rows: list[dict]) -> None:
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def test_measured_side_comes_from_the_result_files(tmp_path: Path) -> None:
    _write(tmp_path / "deblur_single_image.csv", [
        {"scene": "chess", "method": "blind_wiener", "psnr_db": 20.0, "ssim": 0.5},
        {"scene": "chess", "method": "blind_wiener", "psnr_db": 30.0, "ssim": 0.7},
        {"scene": "chess", "method": "blurred", "psnr_db": 99.0, "ssim": 0.9},
    ])  # fmt: skip
    summary = []
    for condition in ("blurred", "rnn"):
        for index, scene in enumerate(SCENE_ORDER):
            combined = 0.3 if condition == "blurred" else 0.2
            summary.append({"scene": scene, "condition": condition, "head": "lstm",
                            "position_m_median": 0.1 * (index + 1),
                            "orientation_deg_median": 2.0 + index, "mae": 0.01, "mse": 0.02,
                            "rmse": 0.03, "combined": combined})  # fmt: skip
    summary.append({**summary[-1], "head": "none", "position_m_median": 9.0})
    _write(tmp_path / "pose_summary.csv", summary)

    measured = measured_numbers(tmp_path)
    assert measured[("fig6", "proposed_wiener", "chess", "psnr_db")] == pytest.approx(25.0)
    assert measured[("fig7", "proposed_wiener", "chess", "ssim")] == pytest.approx(0.6)
    assert measured[("table3", "Proposed", "stairs", "position_m")] == pytest.approx(0.7)
    assert measured[("table3", "Proposed", "average", "position_m")] == pytest.approx(0.4)
    assert measured[("table1", "proposed_blurred", "fire", "combined")] == pytest.approx(0.3)
    assert measured[("table2", "proposed_deblurred", "fire", "combined")] == pytest.approx(0.2)

    rows = paper_vs_reproduction(measured)
    chess = next(r for r in rows if r["item"] == "fig6" and r["scene"] == "chess")
    assert chess["measured"] == 25.0 and chess["ratio"] == pytest.approx(25.0 / 29.76, abs=1e-3)
    abstract = next(r for r in rows if r["item"] == "abstract" and r["method"] == "Proposed"
                    and r["metric"] == "orientation_deg")  # fmt: skip
    assert abstract["measured"] == pytest.approx(5.0)  # Table III's average, beside 5.61
    assert all(r["measured"] == "" for r in rows if r["method"] in ("PoseNet", "AtLoc"))
    assert len(rows) == len(reported_numbers())


def test_missing_result_file_is_named(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match=r"deblur_single_image\.csv"):
        measured_numbers(tmp_path)


def test_table3_rows_are_labelled_and_formatted_like_the_paper() -> None:
    rows = pose_comparison_rows({"ours": {"chess": (0.123, 4.567), "average": (0.2, np.nan)}})
    proposed = next(r for r in rows if r["method"] == "Proposed")
    assert proposed["source"] == "paper (Table III)"
    assert proposed["average"] == "0.16 m, 5.31°"
    vidloc = next(r for r in rows if r["method"] == "VidLoc")
    assert vidloc["source"] == "original publication" and vidloc["chess"] == "0.18 m"
    ours = rows[-1]
    assert ours["source"] == "measured (stand-in)"
    assert (ours["chess"], ours["fire"], ours["average"]) == ("0.12 m, 4.57°", "-", "0.20 m")
    assert paper_values("table3", "position_m", "Proposed")["chess"] == 0.14


def test_readme_and_docs_show_only_figures_that_notebooks_or_benchmarks_write() -> None:
    figure_link = re.compile(r"\]\((?:\.\./)?figures/([\w.-]+)\)")
    shown = {name for page in PAGES for name in figure_link.findall(page.read_text())}
    written = {file for files in EXPECTED_OUTPUTS.values() for file in files}
    saved_by_notebooks = {  # save_table(..., figures_dir, "name") and save_figure alike
        name
        for notebook in NOTEBOOKS_DIR.glob("*.ipynb")
        for cell in json.loads(notebook.read_text())["cells"]
        if cell["cell_type"] == "code"
        for name in re.findall(r'figures_dir,\s*"([\w.-]+)"', "".join(cell["source"]))
    }
    written |= {f"{name}.{ext}" for name in saved_by_notebooks for ext in ("md", "csv", "png")}
    stems = [script.stem for script in (Path(__file__).parents[1] / "benchmarks").glob("*.py")]
    written |= {f"{stem}.{suffix}" for stem in stems for suffix in ("md", "csv", "png", "pdf")}
    # a benchmark run under another --stem (a variant of the run): the script's name, a suffix
    variant_run = re.compile(rf"(?:{'|'.join(stems)})_[\w-]+\.(?:md|csv|png|pdf)")
    assert {f"fig{n:02d}" for n in range(6, 11)} <= {name[:5] for name in shown}
    unwritten = {name for name in shown - written if not variant_run.fullmatch(name)}
    assert not unwritten, sorted(unwritten)
    for name in shown:
        assert (FIGURES_DIR / name).is_file(), name
