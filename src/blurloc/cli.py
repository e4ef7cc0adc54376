"""The ``blurloc`` command line: ``blurloc <command> --help`` for each command."""

from __future__ import annotations

import argparse
import json
import signal
import sys
import threading
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from .config import DEFAULT_SEED
from .files import check_output, image_files
from .images import IMAGE_SUFFIXES

#: Largest seed NumPy's legacy seeding accepts (2**32 - 1).
MAX_SEED = 2**32 - 1


def _check_seed(args: argparse.Namespace) -> None:
    """ValueError naming ``--seed`` when the command has one outside 0 to :data:`MAX_SEED`."""
    seed = getattr(args, "seed", None)
    if seed is not None and not 0 <= seed <= MAX_SEED:
        raise ValueError(f"--seed must be a whole number from 0 to {MAX_SEED}, got {seed}")


@contextmanager
def _warnings_to_stderr() -> Iterator[None]:
    """Print each warning raised inside the block as one ``warning:`` line on stderr."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield
        finally:
            for warning in caught:
                print(f"warning: {warning.message}", file=sys.stderr)


def _synth(args: argparse.Namespace) -> int:
    from .data.synth import SynthConfig, synthesize
    from .data.synth_config import PREVIOUS_LOOK

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
    from .data import check_data

    print(json.dumps(check_data(args.root, progress=sys.stderr.isatty())))
    return 0


def _convert_tum(args: argparse.Namespace) -> int:
    from .data.tum import convert_tum

    print(convert_tum(args.source, args.out, args.scene, sequences=args.sequences,
                      test_every=args.test_every, width=args.width,
                      overwrite=args.overwrite))  # fmt: skip
    return 0


def _run_notebooks(args: argparse.Namespace) -> int:
    from .errors import NotebookError
    from .publish import publish_notebooks
    from .runner import notebook_names, run_notebooks

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


def _blur_estimate(args: argparse.Namespace) -> int:
    from .blur import MIN_ANALYSIS_SIDE, detect_blur, estimate_motion_blur
    from .data import read_image

    for name in args.images:
        image = read_image(name)
        if min(image.shape[:2]) < MIN_ANALYSIS_SIDE:  # readable, but nothing to measure: null
            print(
                json.dumps(
                    {
                        "path": name,
                        "blurred": None,
                        "score": None,
                        "length_px": None,
                        "angle_deg": None,
                        "note": f"smaller than {MIN_ANALYSIS_SIDE} px",
                    }
                )
            )
            continue
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
        try:
            kernel = np.load(path, allow_pickle=False)
        except (ValueError, EOFError, OSError) as error:
            reason = ("it holds Python objects, not numbers" if "allow_pickle" in str(error)
                      else error)  # fmt: skip
            raise ValueError(f"{path}: not a numeric NumPy kernel ({reason})") from None
        if not isinstance(kernel, np.ndarray) or kernel.dtype.kind not in "biuf":
            raise ValueError(f"{path}: kernel must hold real numbers, found {kernel.dtype}")
    else:
        import cv2

        from .files import decode_image

        kernel = decode_image(path, cv2.IMREAD_GRAYSCALE | cv2.IMREAD_ANYDEPTH)
    try:
        return check_kernel(kernel)
    except ValueError as error:
        raise ValueError(f"{path}: {error}") from error


def _check_length(length: float, shape: tuple[int, ...], path: Path) -> None:
    """Refuse a blur length whose kernel (an odd square of about length + 4 px) would not fit
    inside the image."""
    short = min(shape[:2])
    limit = 2 * ((short - 1) // 2) - 2
    if length > limit:
        raise ValueError(f"{path}: --length {length:g} px is too long for this "
                         f"{shape[1]}x{shape[0]} image; at most {limit} px (the kernel must fit "
                         "inside the image)")  # fmt: skip


def _check_kernel_fits(name: str, kernel, shape: tuple[int, ...], path: Path) -> None:
    """Refuse a kernel file whose kernel is larger than the image."""
    from .blur import check_kernel

    try:
        check_kernel(kernel, shape)
    except ValueError as error:
        raise ValueError(f"{name}: {error} of {path}") from error


def _deblur(args: argparse.Namespace) -> int:
    import math
    from functools import partial

    from .batch_deblur import deblur_files

    source, target = Path(args.input), Path(args.output)
    if (args.length is None) != (args.angle is None):
        raise ValueError("give both --length and --angle, or neither")
    if args.kernel and args.length is not None:
        raise ValueError("give --kernel or --length/--angle, not both")
    if args.nsr is not None and not (math.isfinite(args.nsr) and args.nsr > 0):
        raise ValueError(f"--nsr must be a finite number > 0, got {args.nsr}")
    if args.length is not None and not (math.isfinite(args.length) and args.length > 0):
        raise ValueError(f"--length must be a finite number of pixels > 0, got {args.length}")
    if args.angle is not None and not math.isfinite(args.angle):
        raise ValueError(f"--angle must be a finite number of degrees, got {args.angle}")
    if source.is_dir():
        pairs = [(p, target / p.name) for p in image_files(source)]
        if not pairs:
            raise ValueError(f"{source}: no images in this folder")
        names = [p.name for p, _ in pairs]
    elif source.is_file():
        if target.suffix.lower() not in IMAGE_SUFFIXES and not target.is_dir():
            raise ValueError(f"{target}: output must be an image file ending in "
                             f"{', '.join(IMAGE_SUFFIXES)}")  # fmt: skip
        pairs, names = [(source, target)], None
    else:
        raise ValueError(f"{source}: no such file or folder")
    check_output(target, source, args.kernel, names=names, overwrite=args.overwrite)
    kernel = _load_kernel(Path(args.kernel)) if args.kernel else None
    line = None if args.length is None else (args.length, args.angle)
    check = (partial(_check_length, args.length) if line is not None
             else partial(_check_kernel_fits, args.kernel, kernel) if kernel is not None
             else None)  # fmt: skip
    for path_in, path_out, lost in deblur_files(pairs, kernel, line, args.nsr, check):
        if lost:
            print(f"warning: {path_out}: {path_out.suffix} stores 8-bit colour only; the "
                  f"{' and '.join(lost)} of {path_in} is not kept (write .png or .tif to keep "
                  "it)", file=sys.stderr)  # fmt: skip
        print(path_out)
    return 0


def _train_video_deblur(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from .experiments.photo_video import add_photo_videos
    from .train.config import VideoTrainConfig
    from .train.loop import choose_device
    from .train.video import load_video_splits, train_video_deblur

    config = VideoTrainConfig(seed=args.seed, device=args.device)
    config = replace(
        config,
        **{
            k: v
            for k, v in {"steps": args.steps, "batch": args.batch, "crop": args.crop}.items()
            if v is not None
        },
    )
    choose_device(config.device)  # a bad --device is named before the frames are read
    check_output(args.out, args.data, names=())
    if args.validation_per_scene < 0:
        raise ValueError(f"--validation-per-scene must be >= 0 (0: all), got "
                         f"{args.validation_per_scene}")  # fmt: skip
    if args.photo_videos < 0:
        raise ValueError(f"--photo-videos must be >= 0, got {args.photo_videos}")
    splits = load_video_splits(
        args.data,
        args.scenes,
        with_test=False,
        validation_per_scene=args.validation_per_scene or None,
    )
    splits = add_photo_videos(splits, args.photo_videos)
    with _warnings_to_stderr():
        history = train_video_deblur(splits, args.out, config, progress=not args.quiet,
                                     restart=args.restart)  # fmt: skip
    print(json.dumps({"checkpoint": str(Path(args.out) / "best.pt"),
                      "best_val_psnr_db": round(max(history["val_psnr"]), 3),
                      "steps": history["step"][-1]}))  # fmt: skip
    return 0


def _deblur_video(args: argparse.Namespace) -> int:
    from .data.frames import list_frames, read_frames
    from .files import image_header, write_image_file
    from .inference import DEFAULT_CHECKPOINT, load_video_deblur, restore_frames

    model = load_video_deblur(args.checkpoint or DEFAULT_CHECKPOINT)
    paths = list_frames(args.input)
    target = Path(args.output)
    check_output(target, args.input, args.checkpoint, names=[p.name for p in paths],
                 overwrite=args.overwrite)  # fmt: skip
    for path in paths:  # the network restores 8-bit RGB: refuse what it would change
        header = image_header(path)
        if (header.bit_depth, header.channels) != (8, 3):
            raise ValueError(f"{path}: {header.describe()} frame; deblur-video restores 8-bit "
                             "RGB frames only and would change it (convert the frames, or use "
                             "`blurloc deblur`, which keeps depth and channels)")  # fmt: skip
    target.mkdir(parents=True, exist_ok=True)
    restored = restore_frames(model, read_frames(paths))  # streamed: one chunk held at a time
    for path, frame in zip(paths, restored, strict=True):
        write_image_file(target / path.name, frame)
    print(json.dumps({"frames": len(paths), "output": str(target)}))
    return 0


def _train_pose(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from .models.pose import PoseConfig
    from .train.config import PoseTrainConfig
    from .train.pose import train_pose

    root = _input_root(args.data, args.input)
    check_output(args.out, args.data, root, names=())
    config = PoseTrainConfig(seed=args.seed, device=args.device,
                             model=PoseConfig(head=args.head, encoder=args.encoder))  # fmt: skip
    overrides = {"epochs": args.epochs, "resize": args.resize, "crop": args.crop,
                 "lr": args.lr, "batch": args.batch, "window": args.window}  # fmt: skip
    if args.windows_per_epoch is not None:  # 0: one pass over every window per epoch
        overrides["windows_per_epoch"] = args.windows_per_epoch or None
    config = replace(config, **{k: v for k, v in overrides.items() if v is not None},
                     learned_weighting=args.learned_weighting,
                     fixed_crop=args.fixed_crop)  # fmt: skip
    history = train_pose(root, args.scene, args.out, config, progress=not args.quiet,
                         restart=args.restart)  # fmt: skip
    print(json.dumps({"checkpoint": str(Path(args.out) / "best.pt"),
                      "epochs": history["epoch"][-1],
                      "val_position_m": round(min(history["val_position_m"]), 4)}))  # fmt: skip
    return 0


def _input_root(data: str, condition: str) -> Path:
    """The root a pose command reads: ``data`` for blurred/sharp input, or the deblurred copy
    notebook 03 writes (``results/deblurred/<wiener|rnn>``) when ``data`` holds none."""
    root = Path(data)
    if condition in ("wiener", "rnn"):
        from .config import RESULTS_DIR

        deblurred = root / "deblurred" / condition
        root = deblurred if deblurred.is_dir() else RESULTS_DIR / "deblurred" / condition
        if not root.is_dir():
            raise ValueError(f"{root}: no {condition}-deblurred frames; run notebook 03 first")
    return root


def _eval_pose(args: argparse.Namespace) -> int:
    check_output(args.out, args.model, args.data, overwrite=args.overwrite)
    import warnings

    import numpy as np

    from .data import load_split
    from .inference import load_pose_model, predict_poses
    from .metrics import pose_summary
    from .trajectory import quaternions_to_poses, write_tum

    path = Path(args.model) / "best.pt" if Path(args.model).is_dir() else Path(args.model)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model, config = load_pose_model(path, scene=args.scene)
    for warning in caught:
        print(f"warning: {warning.message}", file=sys.stderr)
    sequences = load_split(args.data, args.scene, "test")
    if not sequences:
        raise ValueError(f"{args.data}/{args.scene}: no TestSplit sequences")
    pair = predict_poses(model, sequences, config)
    write_tum(args.out, np.arange(len(pair)),
              quaternions_to_poses(pair.estimate_positions, pair.estimate_quaternions))  # fmt: skip
    print(json.dumps(pose_summary(pair, config.beta)))
    return 0


def _pose_error(args: argparse.Namespace) -> int:
    from .trajectory import compare_trajectories

    if not args.max_difference > 0:  # also refuses NaN
        raise ValueError(f"--max-difference must be a positive number of seconds, got "
                         f"{args.max_difference}")  # fmt: skip
    with _warnings_to_stderr():
        errors = compare_trajectories(args.ground_truth, args.estimate, args.max_difference)
    print(json.dumps(errors))
    return 0


#: Help of the ``--overwrite`` option of the commands that write files.
OVERWRITE_HELP = "replace output files of the same names (refused without it)"
#: What a trainer's interruption line says.
RESUME_TRAINING = ("--out keeps the last finished epoch or validation and history.json; run the "
                   "same command again to resume")  # fmt: skip


def _add_synth_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc synth`` and its options to ``commands``."""
    from .data.synth_config import SCENE_CONTENTS

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


def _add_check_data_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc check-data`` and its options to ``commands``."""
    check = commands.add_parser("check-data", help="validate a 7-Scenes-layout root, print counts")
    check.add_argument("root")
    check.set_defaults(handler=_check_data)


def _add_convert_tum_parser(commands: argparse._SubParsersAction) -> None:
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


def _add_blur_estimate_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc blur-estimate`` and its options to ``commands``."""
    estimate = commands.add_parser(
        "blur-estimate", help="detect motion blur, estimate its length and angle (JSON lines)"
    )
    estimate.add_argument("images", nargs="+", help="image files")
    estimate.set_defaults(handler=_blur_estimate)


def _add_deblur_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc deblur`` and its options to ``commands``."""
    deblur = commands.add_parser(
        "deblur", help="Wiener deblurring of an image or a folder (blind without a kernel)"
    )
    deblur.add_argument("input", help="image file, or folder of images")
    deblur.add_argument("output", help="image file, or folder (same names as in the input)")
    deblur.add_argument("--kernel", help="blur kernel as .npy or a gray image (normalised)")
    deblur.add_argument("--length", type=float, help="linear motion blur length, px")
    deblur.add_argument("--angle", type=float, help="its angle, degrees CCW from horizontal")
    deblur.add_argument("--nsr", type=float, help="noise-to-signal ratio (default: estimated)")
    deblur.add_argument("--overwrite", action="store_true", help=OVERWRITE_HELP)
    deblur.set_defaults(handler=_deblur)


def _add_train_video_deblur_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc train-video-deblur`` and its options to ``commands``."""
    train = commands.add_parser(
        "train-video-deblur", help="train the recurrent deblurring network on a stand-in root"
    )
    train.add_argument("--data", required=True, help="stand-in root (needs sharp frames)")
    train.add_argument("--out", required=True, help="folder for best.pt, last.pt, history.json")
    train.add_argument("--scenes", nargs="+", help="scenes to train on (default: all)")
    train.add_argument("--steps", type=int, help="optimiser steps (default 1200)")
    train.add_argument("--batch", type=int, help="clips per step (default 8)")
    train.add_argument("--crop", type=int, help="crop size in px (default 64)")
    train.add_argument(
        "--validation-per-scene",
        type=int,
        default=1,
        help="validate on the last 15 %% of that many training sequences per "
        "scene (default 1; 0: all)",
    )
    train.add_argument(
        "--photo-videos",
        type=int,
        default=0,
        help="add that many GoPro-style videos made from photographs to the training videos "
        "(half as many to the validation; default 0)",
    )
    train.add_argument("--seed", type=int, default=DEFAULT_SEED)
    train.add_argument("--device", default="auto", help="auto (CUDA when present), cpu, cuda")
    train.add_argument(
        "--restart",
        action="store_true",
        help="start afresh, replacing a run with other settings in --out",
    )
    train.add_argument("--quiet", action="store_true", help="no progress bar")
    train.set_defaults(handler=_train_video_deblur, resume=RESUME_TRAINING)


def _add_deblur_video_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc deblur-video`` and its options to ``commands``."""
    video = commands.add_parser(
        "deblur-video", help="deblur a video folder with the recurrent network"
    )
    video.add_argument("input", help="7-Scenes sequence folder or folder of images")
    video.add_argument("output", help="folder for the deblurred frames (same names)")
    video.add_argument("--checkpoint", help="network checkpoint (default: the shipped one)")
    video.add_argument("--overwrite", action="store_true", help=OVERWRITE_HELP)
    video.set_defaults(handler=_deblur_video)


def _add_train_pose_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc train-pose`` and its options to ``commands``."""
    pose = commands.add_parser("train-pose", help="train camera pose regression on one scene")
    pose.add_argument("--data", required=True, help="7-Scenes-layout root")
    pose.add_argument("--scene", required=True)
    pose.add_argument("--out", required=True, help="folder for best.pt, last.pt, history.json")
    pose.add_argument(
        "--input",
        choices=("blurred", "wiener", "rnn", "sharp"),
        default="blurred",
        help="frames to train on (wiener/rnn: deblurred copies from notebook 03)",
    )
    pose.add_argument("--head", choices=("lstm", "bilstm", "gru", "none"), default="lstm")
    pose.add_argument("--encoder", choices=("small", "resnet18", "resnet34"), default="small")
    pose.add_argument("--epochs", type=int)
    pose.add_argument(
        "--windows-per-epoch",
        type=int,
        help="windows drawn per epoch (0: every window once; default 512)",
    )
    pose.add_argument("--resize", type=int, help="short side in px (paper: 256)")
    pose.add_argument("--crop", type=int, help="square crop in px (paper: 224)")
    pose.add_argument("--lr", type=float)
    pose.add_argument("--batch", type=int)
    pose.add_argument("--window", type=int, help="frames per training sequence")
    pose.add_argument(
        "--learned-weighting",
        action="store_true",
        help="learnable s_x, s_q loss weights instead of eq. 14's beta",
    )
    pose.add_argument(
        "--fixed-crop",
        action="store_true",
        help="train on centre crops, as tested, instead of random ones",
    )
    pose.add_argument("--seed", type=int, default=DEFAULT_SEED)
    pose.add_argument("--device", default="auto")
    pose.add_argument(
        "--restart",
        action="store_true",
        help="start afresh, replacing a run with other settings in --out",
    )
    pose.add_argument("--quiet", action="store_true", help="no progress bar")
    pose.set_defaults(handler=_train_pose, resume=RESUME_TRAINING)


def _add_eval_pose_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc eval-pose`` and its options to ``commands``."""
    evaluate = commands.add_parser("eval-pose", help="predict a scene's test frames (TUM file)")
    evaluate.add_argument("--data", required=True)
    evaluate.add_argument("--scene", required=True)
    evaluate.add_argument("--model", required=True, help="checkpoint or train-pose --out folder")
    evaluate.add_argument("--out", required=True, help="TUM file to write")
    evaluate.add_argument("--overwrite", action="store_true", help=OVERWRITE_HELP)
    evaluate.set_defaults(handler=_eval_pose)


def _add_pose_error_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc pose-error`` and its options to ``commands``."""
    error = commands.add_parser("pose-error", help="errors between two trajectories (JSON)")
    error.add_argument("ground_truth", help="TUM file or 7-Scenes sequence folder")
    error.add_argument("estimate", help="TUM file or 7-Scenes sequence folder")
    error.add_argument(
        "--max-difference",
        type=float,
        default=0.01,
        help="largest stamp difference of a matched pair (seconds, > 0)",
    )
    error.set_defaults(handler=_pose_error)


def _add_run_notebooks_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc run-notebooks`` and its options to ``commands``."""
    run = commands.add_parser("run-notebooks", help="run the notebooks in order with papermill")
    run.add_argument("--quick", action="store_true", help="small sizes (as in the tests)")
    run.add_argument("--data-root", help="7-Scenes-layout root (default: the stand-in)")
    run.add_argument("--results-dir", help="default: results/ (build/quick/results with --quick)")
    run.add_argument("--figures-dir", help="default: figures/ (build/quick/figures with --quick)")
    run.add_argument("--device", help="auto (default: CUDA when present), cpu, cuda")
    run.add_argument("notebooks", nargs="*", help="notebook names (default: all, in order)")
    run.set_defaults(handler=_run_notebooks)


#: Each subcommand's parser builder, in the order ``blurloc --help`` lists them.
_PARSER_BUILDERS = (
    _add_synth_parser,
    _add_check_data_parser,
    _add_convert_tum_parser,
    _add_blur_estimate_parser,
    _add_deblur_parser,
    _add_train_video_deblur_parser,
    _add_deblur_video_parser,
    _add_train_pose_parser,
    _add_eval_pose_parser,
    _add_pose_error_parser,
    _add_run_notebooks_parser,
)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every subcommand."""
    parser = argparse.ArgumentParser(prog="blurloc", description=__doc__)
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


if __name__ == "__main__":
    sys.exit(main())
