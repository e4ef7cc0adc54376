"""What a file stored by an earlier version of the package means: one rule for all of them.

Settings are only ever added, never renamed or given another meaning. A file stored before a
setting existed (a checkpoint's network settings, a training run's settings, the stand-in's
manifest) lacks it, and reading the file fills it in with the value that reproduces what the
package did before the setting existed (:func:`complete`):

- a switch of the video network: off (:data:`VIDEO_SWITCHES_ADDED`, whatever its default is now);
- a switch of a training run: off (False or None, :func:`switches_off`), so a run made before a
  switch existed is resumed when the switch is off and refused when it is on;
- a rendering setting of the stand-in: the value that renders what the renderer rendered before
  it existed (``blurloc.data.synth_config.PREVIOUS_LOOK`` for the settings of its look, the
  default for the others).

A file completed so is then compared or used as it is; whatever differs (:func:`changes`) is
named in the caller's refusal, with the command or option that remakes the file.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

#: The switches of the video network added after its first checkpoints, with the value the
#: checkpoints stored before them were trained with (the networks stored before
#: ``bounded_state`` existed have unbounded states; those stored before ``wiener_input`` read
#: the blurred frames alone; those stored before ``blur_condition`` are told no blur; those
#: stored before ``wiener_gradient`` read eq. 4's Wiener copies, and those stored before
#: ``wiener_motion`` read copies deblurred by each frame's blind estimate).
VIDEO_SWITCHES_ADDED = {
    "align": False,
    "bounded_state": False,
    "wiener_input": False,
    "blur_condition": False,
    "wiener_gradient": False,
    "wiener_motion": False,
}


def complete(stored: Mapping[str, Any], added: Mapping[str, Any]) -> dict[str, Any]:
    """Stored settings with the settings added since filled in.

    Parameters
    ----------
    stored : mapping
        Settings read from a file (nested mappings allowed).
    added : mapping
        Settings added since, with the value that reproduces what the package did before
        each existed (nested like ``stored``).

    Returns
    -------
    dict
        ``stored`` with every entry of ``added`` that it lacks; nested mappings are completed
        the same way, and entries ``stored`` holds are kept as they are.
    """
    completed = dict(stored)
    for key, value in added.items():
        if key not in completed:
            completed[key] = value
        elif isinstance(value, Mapping) and isinstance(completed[key], Mapping):
            completed[key] = complete(completed[key], value)
    return completed


def switches_off(settings: Mapping[str, Any]) -> dict[str, Any]:
    """The entries of ``settings`` that are off (False or None), nested as they are.

    Parameters
    ----------
    settings : mapping
        Settings of a run (nested mappings allowed).

    Returns
    -------
    dict
        The off entries; nested mappings keep only theirs (and are dropped when they have
        none). Completing a stored run with them (:func:`complete`) reads a switch the run
        lacks as off: what the run did before the switch existed.
    """
    off: dict[str, Any] = {}
    for key, value in settings.items():
        if isinstance(value, Mapping):
            nested = switches_off(value)
            if nested:
                off[key] = nested
        elif value is False or value is None:
            off[key] = value
    return off


def changes(stored: Mapping[str, Any], wanted: Mapping[str, Any], prefix: str = "") -> list[str]:
    """The entries of ``wanted`` that ``stored`` lacks or holds otherwise.

    Parameters
    ----------
    stored : mapping
        Settings read from a file, completed (:func:`complete`).
    wanted : mapping
        The settings of this run (nested mappings allowed).
    prefix : str
        Prepended to every name (the path of a nested mapping).

    Returns
    -------
    list of str
        ``"name: stored -> wanted"`` per difference, nested names joined with dots; an
        entry ``stored`` lacks shows as ``None``.
    """
    found = []
    for key, value in wanted.items():
        old = stored.get(key)
        if isinstance(value, Mapping) and isinstance(old, Mapping):
            found += changes(old, value, f"{prefix}{key}.")
        elif old != value:
            found.append(f"{prefix}{key}: {old!r} -> {value!r}")
    return found
