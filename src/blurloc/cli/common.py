"""What the ``blurloc`` subcommands share: option help, the trainers' options and resume line,
warnings as one line each."""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager

from ..config import DEFAULT_SEED

#: Help of the ``--overwrite`` option of the commands that write files.
OVERWRITE_HELP = "replace output files of the same names (refused without it)"

#: What a trainer's interruption line says.
RESUME_TRAINING = ("--out keeps the last finished epoch or validation and history.json; run the "
                   "same command again to resume")  # fmt: skip


def add_training_options(trainer: argparse.ArgumentParser) -> None:
    """Add the options every trainer has (``--seed``, ``--device``, ``--restart``, ``--quiet``)
    and the line an interrupted training ends with.

    Parameters
    ----------
    trainer : argparse.ArgumentParser
        The subcommand's parser (``train-video-deblur`` or ``train-pose``).
    """
    trainer.add_argument("--seed", type=int, default=DEFAULT_SEED)
    trainer.add_argument("--device", default="auto", help="auto (CUDA when present), cpu, cuda")
    trainer.add_argument(
        "--restart",
        action="store_true",
        help="start afresh, replacing a run with other settings in --out",
    )
    trainer.add_argument("--quiet", action="store_true", help="no progress bar")
    trainer.set_defaults(resume=RESUME_TRAINING)


@contextmanager
def warnings_to_stderr() -> Iterator[None]:
    """Print each warning raised inside the block as one ``warning:`` line on stderr."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield
        finally:
            for warning in caught:
                print(f"warning: {warning.message}", file=sys.stderr)
