"""The ``blurloc`` command line: ``blurloc <command> --help`` for each command."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path

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


IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff")


def _read_image(path: Path):
    from .data import read_image

    return read_image(path)


def _blur_estimate(args: argparse.Namespace) -> int:
    from .blur import detect_blur, estimate_motion_blur

    for name in args.images:
        image = _read_image(Path(name))
        try:
            blurred, score = detect_blur(image)
            estimate = estimate_motion_blur(image)
        except ValueError as error:
            raise ValueError(f"{name}: {error}") from error
        print(json.dumps({
            "path": name, "blurred": bool(blurred), "score": round(score, 4),
            "length_px": round(estimate.length_px, 2), "angle_deg": round(estimate.angle_deg, 2),
        }))  # fmt: skip
    return 0


def _load_kernel(path: Path):
    import numpy as np

    from .blur import check_kernel

    if not path.is_file():
        raise ValueError(f"{path}: kernel file is missing")
    if path.suffix == ".npy":
        kernel = np.load(path, allow_pickle=False)
    else:
        import cv2

        kernel = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE | cv2.IMREAD_ANYDEPTH)
        if kernel is None:
            raise ValueError(f"{path}: kernel image cannot be read")
    try:
        return check_kernel(kernel)
    except ValueError as error:
        raise ValueError(f"{path}: {error}") from error


def _deblur(args: argparse.Namespace) -> int:
    import cv2

    from .blur import motion_kernel
    from .deconv import deblur_blind, wiener_deconvolve

    source, target = Path(args.input), Path(args.output)
    if (args.length is None) != (args.angle is None):
        raise ValueError("give both --length and --angle, or neither")
    if args.kernel and args.length is not None:
        raise ValueError("give --kernel or --length/--angle, not both")
    if args.nsr is not None and args.nsr <= 0:
        raise ValueError(f"--nsr must be > 0, got {args.nsr}")
    kernel = None
    if args.kernel:
        kernel = _load_kernel(Path(args.kernel))
    elif args.length is not None:
        kernel = motion_kernel(args.length, args.angle)
    if source.is_dir():
        pairs = [(p, target / p.name) for p in sorted(source.iterdir())
                 if p.suffix.lower() in IMAGE_SUFFIXES]  # fmt: skip
        if not pairs:
            raise ValueError(f"{source}: no images in this folder")
        target.mkdir(parents=True, exist_ok=True)
    elif source.is_file():
        pairs = [(source, target)]
    else:
        raise ValueError(f"{source}: no such file or folder")
    for path_in, path_out in pairs:
        image = _read_image(path_in)
        try:
            restored = (deblur_blind(image, args.nsr) if kernel is None
                        else wiener_deconvolve(image, kernel, args.nsr))  # fmt: skip
        except ValueError as error:
            raise ValueError(f"{path_in}: {error}") from error
        if not cv2.imwrite(str(path_out), restored[..., ::-1]):
            raise ValueError(f"{path_out}: cannot write this image (folder or suffix?)")
        print(path_out)
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

    estimate = commands.add_parser(
        "blur-estimate", help="detect motion blur, estimate its length and angle (JSON lines)"
    )
    estimate.add_argument("images", nargs="+", help="image files")
    estimate.set_defaults(handler=_blur_estimate)

    deblur = commands.add_parser(
        "deblur", help="Wiener deblurring of an image or a folder (blind without a kernel)"
    )
    deblur.add_argument("input", help="image file, or folder of images")
    deblur.add_argument("output", help="image file, or folder (same names as in the input)")
    deblur.add_argument("--kernel", help="blur kernel as .npy or a gray image (normalised)")
    deblur.add_argument("--length", type=float, help="linear motion blur length, px")
    deblur.add_argument("--angle", type=float, help="its angle, degrees CCW from horizontal")
    deblur.add_argument("--nsr", type=float, help="noise-to-signal ratio (default: estimated)")
    deblur.set_defaults(handler=_deblur)

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
