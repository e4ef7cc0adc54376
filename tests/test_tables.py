"""The benchmarks' table writer: provenance in the Markdown, one CSV per table, --out-dir."""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import pytest

from blurloc.tables import add_out_dir_argument, save_benchmark_tables


def test_save_benchmark_tables_writes_command_date_and_every_table(tmp_path: Path) -> None:
    tables = {
        "timings": [{"stage": "render", "seconds": 1.5}, {"stage": "train", "seconds": 20}],
        "per scene": [{"scene": "heads", "psnr_db": 30.25}],
    }
    command = ["python", "benchmarks/bench_x.py", "--frames", "3 4"]
    saved = save_benchmark_tables("bench_x", tables, tmp_path / "out", "Timing", command)
    text = saved.markdown.read_text()
    assert text.startswith("# Timing\n")
    assert "`python benchmarks/bench_x.py --frames '3 4'`" in text
    assert "UTC" in text and "code version: " in text
    assert "## timings" in text and "## per scene" in text
    assert "| heads | 30.25 |" in text
    assert saved.csv == tmp_path / "out" / "bench_x.csv"
    with open(saved.csv, newline="") as handle:
        assert list(csv.DictReader(handle)) == [
            {"stage": "render", "seconds": "1.5"},
            {"stage": "train", "seconds": "20"},
        ]
    with open(tmp_path / "out" / "bench_x-per_scene.csv", newline="") as handle:
        assert list(csv.DictReader(handle)) == [{"scene": "heads", "psnr_db": "30.25"}]
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        "bench_x-per_scene.csv",
        "bench_x.csv",
        "bench_x.md",
    ]


def test_save_benchmark_tables_refuses_empty_tables(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="without rows"):
        save_benchmark_tables("x", {"a": [{"v": 1}], "b": []}, tmp_path)
    with pytest.raises(ValueError, match="no tables"):
        save_benchmark_tables("x", {}, tmp_path)
    assert not list(tmp_path.iterdir())


def test_out_dir_argument_defaults_to_figures() -> None:
    parser = argparse.ArgumentParser()
    add_out_dir_argument(parser)
    assert parser.parse_args([]).out_dir == Path("figures")
    assert parser.parse_args(["--out-dir", "/tmp/t"]).out_dir == Path("/tmp/t")
