"""The stand-in's manifest (``standin.json``: the settings and seed that made it, and whether the
render finished) and the lock a render holds while it writes."""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import asdict
from pathlib import Path

from ..processes import process_alive
from ..stored import complete
from .synth_config import SynthConfig

FORMAT_VERSION = 5  # bump whenever rendering changes, so stale stand-ins are rendered again


#: File that marks a folder as a rendered stand-in and records the settings and seed.
STANDIN_MANIFEST = "standin.json"
#: File held (created exclusively, holding the PID) while a render writes into a stand-in.
LOCK_FILE = ".synth.lock"


def manifest_record(config: SynthConfig, seed: int, scenes: list[str]) -> dict:
    """The manifest of a stand-in rendered with ``config`` and ``seed``: the format version, the
    seed, the scenes and every setting (JSON-ready)."""
    settings = asdict(config)
    settings["sequence_counts"] = {k: list(v) for k, v in config.sequence_counts.items()}
    return {"format": FORMAT_VERSION, "seed": seed, "scenes": scenes, "config": settings}


def is_foreign_dataset(root: Path) -> bool:
    """True when ``root`` holds something other than a stand-in (non-empty, no manifest)."""
    return (
        root.is_dir()
        and any(entry.name != LOCK_FILE for entry in root.iterdir())
        and not (root / STANDIN_MANIFEST).exists()
    )


@contextmanager
def render_lock(root: Path) -> Iterator[None]:
    """Hold ``root/.synth.lock`` (created exclusively, holding this PID) while rendering.

    A lock left by a process that no longer runs is taken over.

    Parameters
    ----------
    root : pathlib.Path
        The stand-in folder (it exists).

    Raises
    ------
    ValueError
        Naming the lock file and the PID holding it, when another process renders into ``root``.
    """
    lock = root / LOCK_FILE
    for _ in range(2):
        try:
            handle = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            text = lock.read_text().strip() if lock.exists() else ""
            holder = int(text) if text.isdigit() else None
            if holder is None or process_alive(holder):
                raise ValueError(
                    f"{lock}: another synth (PID {holder or 'unknown'}) is rendering into "
                    f"{root}; wait for it, or delete the lock if that process is gone"
                ) from None
            lock.unlink(missing_ok=True)  # its holder died: take it over
            continue
        with os.fdopen(handle, "w") as file:
            file.write(f"{os.getpid()}\n")
        break
    else:
        raise ValueError(f"{lock}: cannot take over the lock; try again")
    try:
        yield
    finally:
        lock.unlink(missing_ok=True)


def manifest_expectations(root: str | os.PathLike) -> dict[str, tuple[int, int, int]] | None:
    """What ``root/standin.json`` promises: per scene, frames per sequence, height and width.

    Parameters
    ----------
    root : str or os.PathLike
        A 7-Scenes-layout root.

    Returns
    -------
    dict or None
        ``{scene: (frames, height_px, width_px)}``; None when ``root`` has no manifest (not a
        stand-in, e.g. the real 7-Scenes).

    Raises
    ------
    ValueError
        Naming the manifest, when it is unreadable or marks an unfinished render.
    """
    path = Path(root) / STANDIN_MANIFEST
    if not path.is_file():
        return None
    try:
        manifest = json.loads(path.read_text())
        if manifest.get("incomplete"):
            raise ValueError("the render that made this stand-in did not finish; run "
                             "blurloc synth again")  # fmt: skip
        settings = manifest["config"]
        config = SynthConfig(width=settings["width"], height=settings["height"],
                             frames_per_sequence=settings["frames_per_sequence"])  # fmt: skip
        return {scene: (config.frames_for(scene), config.height, config.width)
                for scene in manifest["scenes"]}  # fmt: skip
    except (ValueError, KeyError, TypeError, AttributeError) as error:
        detail = f"lacks {error}" if isinstance(error, KeyError) else error
        raise ValueError(f"{path}: not a usable stand-in manifest ({detail})") from None


def is_up_to_date(manifest_path: Path, manifest: dict) -> bool:
    """True when the stand-in at ``manifest_path`` was rendered as ``manifest`` describes. A
    setting added to :class:`SynthConfig` after it was rendered counts as the value that renders
    what the renderer rendered before (:func:`blurloc.stored.complete`): its value in
    :data:`~blurloc.data.synth_config.PREVIOUS_LOOK`, or else its default."""
    try:
        stored = json.loads(manifest_path.read_text())
        before = manifest_record(SynthConfig.previous_look(), 0, [])["config"]
        stored["config"] = complete(stored["config"], before)
        return stored == manifest
    except (OSError, ValueError, KeyError, TypeError):
        return False


def render_settings(root: str | os.PathLike) -> dict:
    """The settings a stand-in was rendered with (``root/standin.json``'s ``config``: e.g.
    ``blur_strength``, the exposure in frame intervals).

    Parameters
    ----------
    root : str or os.PathLike
        A stand-in root.

    Returns
    -------
    dict
        The render's settings, as :class:`~blurloc.data.synth_config.SynthConfig` names them.

    Raises
    ------
    ValueError
        Naming the manifest, when it is missing or has no settings.
    """
    path = Path(root) / STANDIN_MANIFEST
    try:
        return dict(json.loads(path.read_text())["config"])
    except (OSError, ValueError, KeyError, TypeError) as error:
        raise ValueError(f"{path}: no stand-in settings to read ({error})") from None
