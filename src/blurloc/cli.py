"""The ``blurloc`` command line: ``blurloc <command> --help`` for each command."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence

from .config import DEFAULT_SEED


def _synth(args: argparse.Namespace) -> int:
    from .data.synth import SynthConfig, synthesize

    overrides = {
        k: v
        for k, v in {
            "frames_per_sequence": args.frames,
            "width": args.width,
            "height": args.height,
            "blur_strength": args.blur_strength,
            "noise_sigma": args.noise,
        }.items()
        if v is not None
    }
    config = SynthConfig.quick(**overrides) if args.quick else SynthConfig(**overrides)
    root = synthesize(
        args.out,
        scenes=args.scenes,
        config=config,
        seed=args.seed,
        workers=args.workers,
        progress=not args.quiet,
        overwrite=args.overwrite,
    )
    print(root)
    return 0


def _check_data(args: argparse.Namespace) -> int:
    from .data import check_data

    print(json.dumps(check_data(args.root, progress=sys.stderr.isatty())))
    return 0


def _run_notebooks(args: argparse.Namespace) -> int:
    from .runner import run_notebooks

    run_notebooks(quick=args.quick, names=args.notebooks or None)
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every subcommand."""
    parser = argparse.ArgumentParser(prog="blurloc", description=__doc__)
    commands = parser.add_subparsers(dest="command", required=True)

    synth = commands.add_parser("synth", help="render the synthetic 7-Scenes stand-in")
    synth.add_argument("--out", required=True, help="root folder to write (7-Scenes layout)")
    synth.add_argument("--scenes", nargs="+", help="scenes to render (default: all seven)")
    synth.add_argument("--quick", action="store_true", help="tiny version for tests (seconds)")
    synth.add_argument("--seed", type=int, default=DEFAULT_SEED)
    synth.add_argument("--frames", type=int, help="frames per sequence (stairs: half)")
    synth.add_argument("--width", type=int)
    synth.add_argument("--height", type=int)
    synth.add_argument("--blur-strength", type=float, help="exposure in frame intervals")
    synth.add_argument("--noise", type=float, help="sensor noise sigma on [0, 1] intensities")
    synth.add_argument("--workers", type=int, help="processes (default: one per core)")
    synth.add_argument("--overwrite", action="store_true", help="render even if up to date")
    synth.add_argument("--quiet", action="store_true", help="no progress bar")
    synth.set_defaults(handler=_synth)

    check = commands.add_parser("check-data", help="validate a 7-Scenes-layout root, print counts")
    check.add_argument("root")
    check.set_defaults(handler=_check_data)

    run = commands.add_parser("run-notebooks", help="run the notebooks in order with papermill")
    run.add_argument("--quick", action="store_true", help="small sizes (as in the tests)")
    run.add_argument("notebooks", nargs="*", help="notebook names (default: all, in order)")
    run.set_defaults(handler=_run_notebooks)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``blurloc`` console script; returns the exit status."""
    args = build_parser().parse_args(argv)
    try:
        return args.handler(args)
    except (ValueError, OSError) as error:  # DataError is a ValueError and names the file
        print(f"error: {error}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
