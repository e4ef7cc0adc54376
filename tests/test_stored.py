"""The one rule for files stored by an earlier version: settings added since are filled in with
the value that reproduces what the package did before them."""

from __future__ import annotations

from blurloc.stored import changes, complete, switches_off


def test_a_switch_added_off_since_a_run_is_not_a_change() -> None:
    """Runs made before a model switch existed (e.g. ``bounded_state``) resume when it is off,
    and are refused when it is on; other settings are compared as they are."""
    stored = {"train_config": {"lr": 0.002, "model": {"channels": 32}}}

    def changed(wanted: dict) -> list[str]:
        return changes(complete(stored, switches_off(wanted)), wanted)

    off = {"train_config": {"lr": 0.002, "model": {"channels": 32, "bounded_state": False}}}
    assert changed(off) == []
    on = {"train_config": {"lr": 0.002, "model": {"channels": 32, "bounded_state": True}}}
    assert changed(on) == ["train_config.model.bounded_state: None -> True"]
    zero = {"train_config": {"lr": 0.002, "model": {"channels": 32, "blocks": 0}}}
    assert changed(zero) == ["train_config.model.blocks: None -> 0"]
    other = {"train_config": {"lr": 0.001, "model": {"channels": 32}}}
    assert changed(other) == ["train_config.lr: 0.002 -> 0.001"]


def test_completion_keeps_what_the_file_holds() -> None:
    stored = {"noise": 0.01, "camera": {"fov": 60}}
    added = {"noise": 0.0, "camera": {"fov": 50, "rolling_shutter": False}, "gamma": 2.2}
    assert complete(stored, added) == {
        "noise": 0.01,
        "camera": {"fov": 60, "rolling_shutter": False},
        "gamma": 2.2,
    }
    assert stored == {"noise": 0.01, "camera": {"fov": 60}}  # the read settings are not changed


def test_only_off_switches_are_taken_as_what_ran_before() -> None:
    settings = {"lr": 0.1, "align": False, "limit": None, "model": {"blocks": 0, "aux": False}}
    assert switches_off(settings) == {"align": False, "limit": None, "model": {"aux": False}}
    assert switches_off({"model": {"blocks": 4}}) == {}
