"""Worker processes that end with their parent.

A pool's workers outlive a parent killed with SIGKILL or SIGTERM (no clean-up runs in it): a
stopped render would go on writing frames, a stopped training on training, each for minutes, on
cores the next run needs. :func:`watch_parent`, given to a pool as its initializer, ends a worker
as soon as the process that started the pool is gone.
"""

from __future__ import annotations

import os
import signal
import threading
import time


def process_alive(pid: int) -> bool:
    """Whether a process with this PID runs (one owned by another user counts as running).

    Parameters
    ----------
    pid : int
        The process ID.

    Returns
    -------
    bool
    """
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # alive, owned by someone else
        return True
    return True


def watch_parent(parent_pid: int, interval_s: float = 0.2) -> None:
    """End this process as soon as process ``parent_pid`` is gone (a pool's initializer).

    A daemon thread polls the PID and exits the process when it no longer runs. The worker
    leaves Ctrl-C to the parent: the terminal sends SIGINT to every process of the command, and
    the parent stops the pool, so one line is printed instead of a traceback per worker. (With
    forkserver a worker's own parent is the fork server, which lives as long as the workers, so
    ``os.getppid`` cannot tell; hence the PID of the process that made the pool.)

    Parameters
    ----------
    parent_pid : int
        The process whose end ends this one, e.g. ``os.getpid()`` where the pool is made.
    interval_s : float
        Seconds between two looks.
    """

    def watch() -> None:
        while process_alive(parent_pid):
            time.sleep(interval_s)
        os._exit(1)

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    threading.Thread(target=watch, daemon=True, name="watch-parent").start()
