"""Checkpoints of the package's networks: their format tags, atomic saving and safe loading.

Every checkpoint is read with ``torch.load(..., weights_only=True)`` (tensors and plain data
only: a crafted file cannot run code) and must carry the format tag of its kind
(:data:`CHECKPOINT_FORMATS`); every failure is a :class:`~blurloc.errors.CheckpointError` (a
``ValueError``) naming the file. Training (:mod:`blurloc.train`) and inference
(:mod:`blurloc.inference`) both read and write checkpoints through this module.
"""

from __future__ import annotations

import os
import pickle
import tempfile
import warnings
from pathlib import Path

import torch

from .errors import CheckpointError

#: Format tag stored in each kind of checkpoint, by kind.
CHECKPOINT_FORMATS = {"video-deblur": "blurloc-video-deblur-1", "pose": "blurloc-pose-1"}


def checkpoint_kind(payload: dict) -> str:
    """The kind (``video-deblur`` or ``pose``) of a loaded checkpoint payload.

    Parameters
    ----------
    payload : dict
        What :func:`load_checkpoint` returned.

    Returns
    -------
    str
        A key of :data:`CHECKPOINT_FORMATS`.
    """
    return next(k for k, tag in CHECKPOINT_FORMATS.items() if payload.get("format") == tag)


def load_checkpoint(
    path: str | os.PathLike, kind: str | None, device: torch.device | str = "cpu"
) -> dict:
    """Read a checkpoint of this package safely.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    kind : str or None
        Expected kind (a key of :data:`CHECKPOINT_FORMATS`); None accepts any kind.
    device : torch.device or str
        Where its tensors are placed.

    Returns
    -------
    dict
        The payload: ``format``, ``model`` (a state dict) and the kind's settings.

    Raises
    ------
    CheckpointError
        Naming the file: it is missing or empty, damaged or truncated, not a torch file, a
        pickle holding anything but tensors and plain data, or a checkpoint of another kind.
    """
    path = Path(path)
    if not path.is_file():
        raise CheckpointError(f"{path}: checkpoint file is missing")
    if path.stat().st_size == 0:
        raise CheckpointError(f"{path}: checkpoint file is empty")
    try:
        with warnings.catch_warnings():  # torch warns about pickle protocols of foreign files
            warnings.simplefilter("ignore")
            payload = torch.load(path, map_location=device, weights_only=True)
    except pickle.UnpicklingError as error:
        if "weights only" not in str(error).lower():
            raise CheckpointError(
                f"{path}: not a readable checkpoint (damaged or truncated)"
            ) from None
        raise CheckpointError(f"{path}: holds objects other than tensors and plain data; "
                              "refused, since loading it could run code") from None  # fmt: skip
    except Exception:  # torch raises several types for damaged or foreign files
        raise CheckpointError(f"{path}: not a readable checkpoint (damaged, truncated or not "
                              "a torch file)") from None  # fmt: skip
    tags = {tag: name for name, tag in CHECKPOINT_FORMATS.items()}
    found = tags.get(payload.get("format")) if isinstance(payload, dict) else None
    if found is None or not isinstance(payload.get("model"), dict):
        raise CheckpointError(f"{path}: not a blurloc checkpoint")
    if kind is not None and found != kind:
        raise CheckpointError(f"{path}: a blurloc {found} checkpoint, not a {kind} one")
    return payload


def save_checkpoint(path: str | os.PathLike, payload: dict) -> None:
    """Save ``payload`` with ``torch.save`` atomically.

    It is written to a temporary file in the same folder and renamed, so a crash never leaves
    half a checkpoint.

    Parameters
    ----------
    path : str or os.PathLike
        Target file; its folder is created.
    payload : dict
        Tensors and plain data only (so that it loads with ``weights_only=True``).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(handle)
    try:
        torch.save(payload, temporary)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
