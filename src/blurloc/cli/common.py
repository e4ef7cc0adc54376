"""What the ``blurloc`` subcommands share: option help, the trainers' resume line, warnings as
one line each."""

from __future__ import annotations

import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager

#: Help of the ``--overwrite`` option of the commands that write files.
OVERWRITE_HELP = "replace output files of the same names (refused without it)"

#: What a trainer's interruption line says.
RESUME_TRAINING = ("--out keeps the last finished epoch or validation and history.json; run the "
                   "same command again to resume")  # fmt: skip


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
