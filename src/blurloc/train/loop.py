"""What both trainers share: the device, the thread count, the validation cut and the rule for
resuming a run from its folder.

A run folder holds ``best.pt`` (the best validation), ``last.pt`` (everything needed to resume)
and ``history.json``. A folder holds one model kind and one run: training into a folder whose
checkpoints were made with other settings is refused unless the caller asks to start afresh
(``restart``, the CLI's ``--restart``); a folder holding another model kind is always refused.
"""

from __future__ import annotations

import json
import multiprocessing
import os
import tempfile
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager
from pathlib import Path

import torch

from ..checkpoints import checkpoint_kind, load_checkpoint
from ..files import RUN_FILES
from ..processes import watch_parent
from ..stored import changes, complete, switches_off

#: Fraction of every training sequence held out (at its end) for validation.
VALIDATION_FRACTION = 0.15
#: Files of a run folder that identify the run (both hold the kind and the settings).
RUN_CHECKPOINTS = RUN_FILES[:2]


def validation_cut(length: int) -> int:
    """Number of frames at the end of a training sequence held out for validation.

    The cut is temporal (no validation frame sits inside a training window) and holds at least
    2 frames: the video network needs two frames to carry a state, and a recurrent pose head
    needs two to be validated as a sequence.

    Parameters
    ----------
    length : int
        Frames in the training sequence.

    Returns
    -------
    int
        ``max(2, round(VALIDATION_FRACTION * length))``.

    Raises
    ------
    ValueError
        If fewer than 3 frames would remain (at least one for training).
    """
    held_out = max(2, round(VALIDATION_FRACTION * length))
    if length - held_out < 1:
        raise ValueError(f"a training sequence of {length} frames is too short to hold out "
                         f"{held_out} validation frames")  # fmt: skip
    return held_out


def choose_device(device: str = "auto") -> torch.device:
    """The torch device named by ``device``.

    Parameters
    ----------
    device : str
        ``auto`` (CUDA when present, else CPU), ``cpu``, ``cuda`` or ``cuda:N``, ``mps``.

    Returns
    -------
    torch.device

    Raises
    ------
    ValueError
        If the name is not a device (``gpu0``) or names CUDA on a machine without it; the
        message names ``--device``.
    """
    if device == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    try:
        chosen = torch.device(device)
    except (RuntimeError, TypeError):
        raise ValueError(f"--device {device!r}: not a device (use auto, cpu, cuda or cuda:N)") \
            from None  # fmt: skip
    if chosen.type == "cuda":
        if not torch.cuda.is_available():
            raise ValueError(f"--device {device!r}: CUDA is not available on this machine "
                             "(use auto or cpu)")  # fmt: skip
        if chosen.index is not None and chosen.index >= torch.cuda.device_count():
            raise ValueError(f"--device {device!r}: this machine has "
                             f"{torch.cuda.device_count()} CUDA device(s)")  # fmt: skip
    elif chosen.type == "mps" and not torch.backends.mps.is_available():
        raise ValueError(f"--device {device!r}: MPS is not available on this machine")
    elif chosen.type not in ("cpu", "cuda", "mps"):
        raise ValueError(f"--device {device!r}: not supported (use auto, cpu, cuda or cuda:N)")
    return chosen


@contextmanager
def fixed_threads(threads: int) -> Iterator[None]:
    """Run the enclosed code with ``threads`` intra-op CPU threads, then restore the count.

    On CPU the sums inside convolutions and matrix products are split among the threads, so
    the rounding (and a trained network) depends on the thread count; fixing it makes one seed
    give the same numbers whatever the machine's core count. It does not fix the CPU's own
    kernels: on another processor the rounding may differ, and training amplifies it.

    Parameters
    ----------
    threads : int
        Intra-op threads (``torch.set_num_threads``), >= 1.
    """
    previous = torch.get_num_threads()
    torch.set_num_threads(threads)
    try:
        yield
    finally:
        torch.set_num_threads(previous)


def write_history(out_dir: str | os.PathLike, history: dict) -> Path:
    """Write a run's history as ``out_dir/history.json`` atomically (temporary file, rename).

    Parameters
    ----------
    out_dir : str or os.PathLike
        The run folder.
    history : dict
        Lists of numbers per quantity.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    path = Path(out_dir) / "history.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=path.parent, suffix=".tmp", delete=False) as handle:
        json.dump(history, handle, indent=1)
    os.replace(handle.name, path)
    return path


def resume_state(
    out_dir: str | os.PathLike,
    kind: str,
    settings: dict,
    restart: bool = False,
    device: torch.device | str = "cpu",
) -> dict | None:
    """The ``last.pt`` payload to resume from, after checking what the run folder holds.

    Parameters
    ----------
    out_dir : str or os.PathLike
        The run folder (may not exist yet).
    kind : str
        Model kind of this run (a key of :data:`blurloc.checkpoints.CHECKPOINT_FORMATS`).
    settings : dict
        Entries every checkpoint of this run stores and must match to be resumed (the training
        settings, and e.g. the scene).
    restart : bool
        Start afresh even if the folder holds a run of this kind with other settings (its
        results will be replaced).
    device : torch.device or str
        Where the tensors of ``last.pt`` are loaded.

    Returns
    -------
    dict or None
        The ``last.pt`` payload when the run continues; None when it starts afresh.

    Raises
    ------
    ValueError
        Naming the file: it is not a readable checkpoint, holds another model kind, or was made
        with other settings and ``restart`` is False (the message names ``--restart``).
    """
    out_dir = Path(out_dir)
    resumed = None
    for name in RUN_CHECKPOINTS:
        path = out_dir / name
        if not path.is_file():
            continue
        payload = load_checkpoint(path, None, device)
        if checkpoint_kind(payload) != kind:
            raise ValueError(
                f"{path}: holds a {checkpoint_kind(payload)} model; a folder "
                f"holds one model kind: give another --out for this {kind} model"
            )
        if restart:
            continue
        changed = changes(complete(payload, switches_off(settings)), settings)
        if changed:
            raise ValueError(f"{path}: made with other settings ({', '.join(changed)}); give "
                             "--restart to start afresh (its results are replaced) or another "
                             "--out")  # fmt: skip
        if name == "last.pt":
            resumed = payload
    return resumed


def parallel_map(
    function: Callable, jobs: Iterable, workers: int = 1, chunksize: int = 1
) -> Iterator:
    """``map(function, jobs)``, results in order, spread over ``workers`` processes.

    Workers are spawned (a forked PyTorch may hang on its threads) and each runs one PyTorch
    thread: on 2 CPU cores, two one-thread processes finish two small networks' work in about
    14 s where one two-thread process needs 2 x 12 s. With ``workers > 1``, ``function`` and the
    jobs must be picklable (module-level functions, plain data).

    Parameters
    ----------
    function : callable
        Applied to every job.
    jobs : iterable
        The arguments, one per call.
    workers : int
        Processes (1: in this process, with its thread count).
    chunksize : int
        Consecutive jobs handed to one process together (jobs that read the same files then
        read them in one process only).

    Returns
    -------
    iterator
        ``function(job)`` for every job, in the order of ``jobs``.

    Raises
    ------
    ValueError
        If ``workers`` or ``chunksize`` is not positive.
    """
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    if chunksize < 1:
        raise ValueError(f"chunksize must be >= 1, got {chunksize}")
    if workers == 1:
        return map(function, jobs)
    return _pooled(function, jobs, workers, chunksize)


def _start_worker(parent_pid: int) -> None:
    """Initializer of :func:`parallel_map`'s workers: one PyTorch thread, and an end with the
    parent (:func:`~blurloc.processes.watch_parent`)."""
    torch.set_num_threads(1)
    watch_parent(parent_pid)


def _pooled(function: Callable, jobs: Iterable, workers: int, chunksize: int) -> Iterator:
    """The results of :func:`parallel_map` from a pool that closes when they are consumed."""
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(workers, mp_context=context, initializer=_start_worker,
                             initargs=(os.getpid(),)) as pool:  # fmt: skip
        yield from pool.map(function, jobs, chunksize=chunksize)
