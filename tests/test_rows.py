"""Selecting and grouping experiment rows, as returned or as read back from CSV."""

from __future__ import annotations

import pytest

from blurloc.experiments.rows import grouped_means, grouped_values, matching

ROWS = [
    {"scene": "fire", "seed": 0, "condition": "rnn", "err": 1.0},
    {"scene": "chess", "seed": 0, "condition": "rnn", "err": 3.0},
    {"scene": "fire", "seed": 1, "condition": "rnn", "err": 2.0},
    {"scene": "fire", "seed": 0, "condition": "blurred", "err": 9.0},
]


def test_columns_match_as_text_so_csv_rows_match_too() -> None:
    as_read = [{key: str(value) for key, value in row.items()} for row in ROWS]
    assert matching(ROWS, {"seed": 0, "condition": "rnn"}) == ROWS[:2]
    assert matching(as_read, {"seed": 0, "condition": "rnn"}) == as_read[:2]
    assert matching(ROWS) == ROWS


def test_groups_keep_their_first_order_and_only_matching_rows() -> None:
    assert grouped_values(ROWS, "scene", "err", {"condition": "rnn"}) == {
        "fire": [1.0, 2.0],
        "chess": [3.0],
    }
    assert grouped_means(ROWS, "scene", "err", {"condition": "rnn"}) == {"fire": 1.5, "chess": 3.0}
    assert grouped_means(ROWS, "scene", "err", {"condition": "sharp"}) == {}


def test_a_missing_value_column_is_named() -> None:
    with pytest.raises(KeyError, match="psnr_db"):
        grouped_values(ROWS, "scene", "psnr_db")
