"""Deblurring many image files at once, on every core this process may use.

Each frame is read, deblurred (blind, or with one given kernel) and written by a worker of a
process pool sized to the cores of :func:`os.sched_getaffinity`; frames go out in chunks and the
results come back in the order of the input. While the workers start, the calling process
deblurs the first chunk itself. A worker runs OpenCV on one thread (the pool
supplies the parallelism), ignores Ctrl-C (the caller's process handles it) and ends with the
process that made the pool.
"""

from __future__ import annotations

import functools
import math
import multiprocessing
import os
import shutil
import signal
import sys
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path

import numpy as np

from .blur import check_kernel, motion_kernel
from .deconv import BLIND_REGULARISER, blind_kernel, blind_nsr, wiener_deconvolve
from .files import atomic_path, read_image_file, write_image_file
from .processes import watch_parent

#: Frames per task sent to a worker at most (fewer when the folder is small, so that every
#: worker gets work).
MAX_CHUNK = 8

#: A per-frame check of the image's shape before it is deblurred: ``check(shape, path)`` raises
#: a ValueError (its message is passed on as it is) for a frame the caller refuses.
FrameCheck = Callable[[tuple[int, ...], Path], None]


def available_cores() -> int:
    """The number of CPU cores this process may run on (its affinity mask where the system has
    one, else the machine's count).

    Returns
    -------
    int
        At least 1.
    """
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


def deblur_file(
    path_in: Path,
    path_out: Path,
    kernel: np.ndarray | None = None,
    line: tuple[float, float] | None = None,
    nsr: float | None = None,
    check: FrameCheck | None = None,
) -> list[str]:
    """Read one image file, deblur it and write the result atomically.

    Parameters
    ----------
    path_in, path_out : pathlib.Path
        The image to read and the file to write (see :func:`~blurloc.files.write_image_file`).
    kernel : numpy.ndarray, optional
        A known blur kernel: Wiener deconvolution (eq. 4) with it. Without ``kernel`` and
        ``line``, blind deblurring as :func:`~blurloc.deconv.deblur_blind` does it (gated, its
        regulariser); a frame it passes through is written as a byte copy of ``path_in`` where
        both have one suffix.
    line : tuple of float, optional
        (length px, angle degrees) of a known linear blur, used when ``kernel`` is None; the
        kernel is made after ``check`` has accepted the frame.
    nsr : float, optional
        The NSR of eq. 4 (blind: the weight of blind deblurring's regulariser); estimated from
        each frame when None (:func:`~blurloc.deconv.estimate_nsr`,
        :func:`~blurloc.deconv.blind_nsr`).
    check : callable, optional
        ``check(shape, path_in)``, called first; it raises a ValueError to refuse the frame.

    Returns
    -------
    list of str
        What the output's format could not keep ("16-bit depth", "alpha"); empty when nothing.

    Raises
    ------
    ValueError
        Naming ``path_in`` (or with ``check``'s own message), when the frame cannot be read,
        is refused, or its kernel does not fit inside it.
    """
    image, alpha = read_image_file(path_in)
    if check is not None:
        check(image.shape, path_in)
    if kernel is None and line is not None:
        kernel = motion_kernel(*line)
    regulariser = "constant"  # a known kernel: eq. 4
    try:
        if kernel is None:
            kernel, regulariser = blind_kernel(image, gated=True), BLIND_REGULARISER
            if kernel is None and path_in.suffix.lower() == path_out.suffix.lower():
                with atomic_path(path_out) as temporary:  # passed through: the same file
                    shutil.copyfile(path_in, temporary)
                return []
            if kernel is not None and nsr is None:
                nsr = blind_nsr(image, regulariser)
        if kernel is None:
            restored = image
        else:
            restored = wiener_deconvolve(image, check_kernel(kernel, image.shape), nsr, regulariser)
    except ValueError as error:
        raise ValueError(f"{path_in}: {error}") from error
    return write_image_file(path_out, restored, alpha)


def _deblur_pair(pair: tuple[Path, Path], **options) -> list[str]:
    """:func:`deblur_file` on one (input, output) pair (a pool task)."""
    return deblur_file(*pair, **options)


def _start_worker(parent_pid: int) -> None:
    """Initializer of the pool's workers: one OpenCV thread, Ctrl-C left to the parent, an end
    with the parent (:func:`~blurloc.processes.watch_parent`)."""
    import cv2

    cv2.setNumThreads(1)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    watch_parent(parent_pid)


def deblur_files(
    pairs: Sequence[tuple[Path, Path]],
    kernel: np.ndarray | None = None,
    line: tuple[float, float] | None = None,
    nsr: float | None = None,
    check: FrameCheck | None = None,
    workers: int | None = None,
) -> Iterator[tuple[Path, Path, list[str]]]:
    """Deblur image files in parallel: :func:`deblur_file` on each (input, output) pair.

    Parameters
    ----------
    pairs : sequence of (pathlib.Path, pathlib.Path)
        (input image, output file) pairs.
    kernel, line, nsr, check
        As in :func:`deblur_file`, the same for every frame. ``check`` must be picklable (a
        module-level function or a :func:`functools.partial` of one) when workers are used.
    workers : int, optional
        Worker processes; by default one per available core (:func:`available_cores`), never
        more than there are chunks of frames. With 1 the frames are deblurred in this process.

    Yields
    ------
    tuple
        (input, output, what the output's format could not keep), in the order of ``pairs``,
        each once its file is written.

    Raises
    ------
    ValueError
        The first frame, in input order, that fails (as :func:`deblur_file`); frames after it
        that workers had already finished stay written.
    """
    workers = available_cores() if workers is None else workers
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    options = {"kernel": kernel, "line": line, "nsr": nsr, "check": check}
    task = functools.partial(_deblur_pair, **options)
    chunk = max(1, min(MAX_CHUNK, len(pairs) // (2 * workers)))
    workers = min(workers, math.ceil(len(pairs) / chunk))
    if workers <= 1:
        for pair in pairs:
            yield (*pair, task(pair))
        return
    method = "forkserver" if sys.platform.startswith("linux") else "spawn"
    context = multiprocessing.get_context(method)
    if method == "forkserver":  # workers fork from a server that has the libraries loaded
        context.set_forkserver_preload([__name__])
    pool = ProcessPoolExecutor(workers, mp_context=context, initializer=_start_worker,
                               initargs=(os.getpid(),))  # fmt: skip
    starter = ThreadPoolExecutor(1)  # starting the workers takes about a second: meanwhile,
    try:  # this process deblurs the first chunk
        head = chunk
        pooled = starter.submit(pool.map, task, pairs[head:], chunksize=chunk)
        for pair in pairs[:head]:
            yield (*pair, task(pair))
        for pair, lost in zip(pairs[head:], pooled.result(), strict=True):
            yield (*pair, lost)
    finally:
        starter.shutdown(wait=True)
        pool.shutdown(wait=True, cancel_futures=True)
