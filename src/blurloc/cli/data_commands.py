"""``blurloc`` subcommands for data and the notebooks: synth, check-data, convert-tum,
run-notebooks."""

from __future__ import annotations

import argparse
import json
import sys

from ..config import DEFAULT_SEED


def _synth(args: argparse.Namespace) -> int:
    from ..data.synth import SynthConfig, synthesize
    from ..data.synth_config import PREVIOUS_LOOK

    overrides = {
        k: v
        for k, v in {
            "frames_per_sequence": args.frames,
            "width": args.width,
            "height": args.height,
            "blur_strength": args.blur_strength,
            "noise_sigma": args.noise,
            "route_share": args.route_share,
            "supersample": args.supersample,
            "scene_content": args.scene_content,
            "exposure_gain": args.exposure_gain,
            "optics_blur_px": args.optics_blur,
            "shot_noise": args.shot_noise,
            "read_noise": args.read_noise,
            "jpeg_quality": args.jpeg_quality,
        }.items()
        if v is not None
    }
    if args.previous_look:
        overrides = {**PREVIOUS_LOOK, **overrides}
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
    from ..data import check_data

    print(json.dumps(check_data(args.root, progress=sys.stderr.isatty())))
    return 0


def _convert_tum(args: argparse.Namespace) -> int:
    from ..data.tum import convert_tum

    print(convert_tum(args.source, args.out, args.scene, sequences=args.sequences,
                      test_every=args.test_every, width=args.width,
                      overwrite=args.overwrite))  # fmt: skip
    return 0


def _run_notebooks(args: argparse.Namespace) -> int:
    from ..errors import NotebookError
    from ..publish import publish_notebooks
    from ..runner import notebook_names, run_notebooks

    overrides = {"data_root": args.data_root, "results_dir": args.results_dir,
                 "figures_dir": args.figures_dir, "device": args.device}  # fmt: skip
    parameters = {key: value for key, value in overrides.items() if value is not None}
    try:
        run_notebooks(quick=args.quick, names=args.notebooks or None, parameters=parameters)
    except NotebookError as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    if not args.quick and not args.notebooks and not parameters:  # the full run: publish it
        written = publish_notebooks(notebook_names())
        print(f"published {len(written)} executed notebooks in {written[0].parent}")
    return 0


def add_synth_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc synth`` and its options to ``commands``."""
    from ..data.synth_config import SCENE_CONTENTS

    synth = commands.add_parser("synth", help="render the synthetic 7-Scenes stand-in")
    synth.add_argument("--out", required=True, help="root folder to write (7-Scenes layout)")
    synth.add_argument("--scenes", nargs="+", help="scenes to render (default: all seven)")
    synth.add_argument("--quick", action="store_true", help="tiny version for tests (seconds)")
    synth.add_argument("--seed", type=int, default=DEFAULT_SEED)
    synth.add_argument("--frames", type=int, help="frames per sequence (stairs: half)")
    synth.add_argument("--width", type=int)
    synth.add_argument("--height", type=int)
    synth.add_argument("--blur-strength", type=float, help="exposure in frame intervals")
    synth.add_argument(
        "--noise", type=float, help="Gaussian noise sigma on [0, 1] encoded intensities (default 0)"
    )
    synth.add_argument(
        "--scene-content",
        choices=SCENE_CONTENTS,
        help="painted rooms with real rooms' edges (default) or tiled photographs",
    )
    synth.add_argument(
        "--exposure-gain", type=float, help="multiplies the rendered linear light (default 0.9)"
    )
    synth.add_argument(
        "--optics-blur", type=float, help="sigma of the optics' Gaussian blur, px (default 0.3)"
    )
    synth.add_argument(
        "--shot-noise",
        type=float,
        help="sensor noise variance per unit linear signal (default 2e-4)",
    )
    synth.add_argument(
        "--read-noise", type=float, help="sensor read-noise sigma in linear light (default 0.006)"
    )
    synth.add_argument(
        "--jpeg-quality", type=int, help="JPEG quality of the captured frames (default 0: no JPEG)"
    )
    synth.add_argument(
        "--previous-look",
        action="store_true",
        help="the stand-in's first look: tiled photographs, no camera model, "
        "noise 0.01 (other options given override it)",
    )
    synth.add_argument("--route-share", type=float,
                       help="part of each walk on a route shared by the scene's sequences "
                            "(0-1; default 0.9; 0: independent sequences)")  # fmt: skip
    synth.add_argument(
        "--supersample", type=int, help="rays per pixel side, averaged into each pixel (default 1)"
    )
    synth.add_argument("--workers", type=int, help="processes (default: one per core)")
    synth.add_argument("--overwrite", action="store_true", help="render even if up to date")
    synth.add_argument("--quiet", action="store_true", help="no progress bar")
    synth.set_defaults(handler=_synth, resume="run the same command again to render it in full")


def add_check_data_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc check-data`` and its options to ``commands``."""
    check = commands.add_parser("check-data", help="validate a 7-Scenes-layout root, print counts")
    check.add_argument("root")
    check.set_defaults(handler=_check_data)


def add_convert_tum_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc convert-tum`` and its options to ``commands``."""
    convert = commands.add_parser(
        "convert-tum", help="write a TUM RGB-D recording as a 7-Scenes scene (poses, split)"
    )
    convert.add_argument("source", help="recording folder (rgb.txt, groundtruth.txt, rgb/)")
    convert.add_argument("out", help="7-Scenes root to write the scene into")
    convert.add_argument("--scene", required=True, help="scene name, e.g. fr1_rpy")
    convert.add_argument(
        "--sequences",
        type=int,
        default=10,
        help="consecutive sequences to cut the frames into (default 10)",
    )
    convert.add_argument(
        "--test-every",
        type=int,
        default=4,
        help="every that many-th sequence is the test split (default 4)",
    )
    convert.add_argument(
        "--width", type=int, help="shrink the frames to this width, px (default: copy them)"
    )
    convert.add_argument("--overwrite", action="store_true", help="replace the scene folder")
    convert.set_defaults(handler=_convert_tum)


def add_run_notebooks_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc run-notebooks`` and its options to ``commands``."""
    run = commands.add_parser("run-notebooks", help="run the notebooks in order with papermill")
    run.add_argument("--quick", action="store_true", help="small sizes (as in the tests)")
    run.add_argument("--data-root", help="7-Scenes-layout root (default: the stand-in)")
    run.add_argument("--results-dir", help="default: results/ (build/quick/results with --quick)")
    run.add_argument("--figures-dir", help="default: figures/ (build/quick/figures with --quick)")
    run.add_argument("--device", help="auto (default: CUDA when present), cpu, cuda")
    run.add_argument("notebooks", nargs="*", help="notebook names (default: all, in order)")
    run.set_defaults(handler=_run_notebooks)
