"""The ``blurloc`` command line: ``blurloc <command> --help`` for each command.

Each subcommand lives with its options in :mod:`.data_commands`, :mod:`.image_commands` or
:mod:`.pose_commands`; this module builds the parser and runs a command, turning errors and
interruptions into one line."""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from collections.abc import Sequence

from . import data_commands, image_commands, pose_commands
from .common import OVERWRITE_HELP, RESUME_TRAINING

__all__ = ["MAX_SEED", "OVERWRITE_HELP", "RESUME_TRAINING", "build_parser", "main"]

#: Largest seed NumPy's legacy seeding accepts (2**32 - 1).
MAX_SEED = 2**32 - 1


def _check_seed(args: argparse.Namespace) -> None:
    """ValueError naming ``--seed`` when the command has one outside 0 to :data:`MAX_SEED`."""
    seed = getattr(args, "seed", None)
    if seed is not None and not 0 <= seed <= MAX_SEED:
        raise ValueError(f"--seed must be a whole number from 0 to {MAX_SEED}, got {seed}")


#: Each subcommand's parser builder, in the order ``blurloc --help`` lists them.
_PARSER_BUILDERS = (
    data_commands.add_synth_parser,
    data_commands.add_check_data_parser,
    data_commands.add_convert_tum_parser,
    image_commands.add_blur_estimate_parser,
    image_commands.add_deblur_parser,
    image_commands.add_train_video_deblur_parser,
    image_commands.add_deblur_video_parser,
    pose_commands.add_train_pose_parser,
    pose_commands.add_eval_pose_parser,
    pose_commands.add_pose_error_parser,
    data_commands.add_run_notebooks_parser,
)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every subcommand."""
    parser = argparse.ArgumentParser(prog="blurloc", description=__doc__.splitlines()[0])
    commands = parser.add_subparsers(dest="command", required=True)
    for add_parser in _PARSER_BUILDERS:
        add_parser(commands)
    return parser


def _interrupt(signum: int, frame: object) -> None:
    """SIGTERM handler: end the command as Ctrl-C does (its files are finished first)."""
    raise KeyboardInterrupt


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``blurloc`` console script; returns the exit status.

    Errors are one ``error:`` line (status 1). Ctrl-C and SIGTERM end a command the same way:
    the trainers write ``history.json`` and keep their last checkpoint, and one line says how
    to resume (status 130).
    """
    args = build_parser().parse_args(argv)
    in_main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _interrupt) if in_main_thread else None
    try:
        _check_seed(args)
        return args.handler(args)
    except (ValueError, OSError) as error:  # DataError is a ValueError and names the file
        print(f"error: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        resume = getattr(args, "resume", None)
        print(f"interrupted{f'; {resume}' if resume else ''}", file=sys.stderr)
        return 130
    finally:
        if in_main_thread:
            signal.signal(signal.SIGTERM, previous)
