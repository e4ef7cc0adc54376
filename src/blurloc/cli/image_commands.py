"""``blurloc`` subcommands for images and videos: blur-estimate, deblur, train-video-deblur,
deblur-video."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..files import check_output, image_files
from ..images import IMAGE_SUFFIXES
from .common import OVERWRITE_HELP, add_training_options, warnings_to_stderr


def _blur_estimate(args: argparse.Namespace) -> int:
    from ..blur import MIN_ANALYSIS_SIDE, detect_blur, estimate_motion_blur
    from ..data import read_image

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

    from ..blur import check_kernel

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

        from ..files import decode_image

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
    from ..blur import check_kernel

    try:
        check_kernel(kernel, shape)
    except ValueError as error:
        raise ValueError(f"{name}: {error} of {path}") from error


def _deblur(args: argparse.Namespace) -> int:
    import math
    from functools import partial

    from ..batch_deblur import deblur_files

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

    from ..experiments.photo_video import add_photo_videos
    from ..train.config import VideoTrainConfig
    from ..train.loop import choose_device
    from ..train.video import (
        load_video_splits,
        train_video_deblur,
        with_motion_deconvolution,
    )

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
    for root in args.data:
        check_output(args.out, root, names=())
    if args.validation_per_scene < 0:
        raise ValueError(f"--validation-per-scene must be >= 0 (0: all), got "
                         f"{args.validation_per_scene}")  # fmt: skip
    if args.photo_videos < 0:
        raise ValueError(f"--photo-videos must be >= 0, got {args.photo_videos}")
    if any(sigma < 0 for sigma in args.photo_noise):
        raise ValueError(f"--photo-noise must be >= 0, got {args.photo_noise}")
    if args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    splits = {"train": [], "validation": []}
    for root in args.data:
        for name, videos in load_video_splits(root, args.scenes, with_test=False,
                                              validation_per_scene=args.validation_per_scene
                                              or None).items():  # fmt: skip
            splits[name] = splits.get(name, []) + videos
    splits = add_photo_videos(splits, args.photo_videos, noise_sigmas=tuple(args.photo_noise))
    if args.input == "motion":
        splits = {name: with_motion_deconvolution(videos, args.workers, not args.quiet)
                  for name, videos in splits.items()}  # fmt: skip
    with warnings_to_stderr():
        history = train_video_deblur(splits, args.out, config, progress=not args.quiet,
                                     restart=args.restart)  # fmt: skip
    print(json.dumps({"checkpoint": str(Path(args.out) / "best.pt"),
                      "best_val_psnr_db": round(max(history["val_psnr"]), 3),
                      "steps": history["step"][-1]}))  # fmt: skip
    return 0


def _deblur_video(args: argparse.Namespace) -> int:
    import numpy as np

    from ..data.frames import list_frames, read_frames
    from ..files import image_header, write_image_file
    from ..inference import (
        DEFAULT_CHECKPOINT,
        MOTION_CHECKPOINT,
        MotionNetworkRestorer,
        load_video_deblur,
        restore_frames,
    )
    from ..video_wiener import deblur_video_motion

    by_motion = args.method in ("motion-network", "motion")
    if args.method == "motion" and args.checkpoint:
        raise ValueError("--checkpoint is for the methods with a network; --method motion has "
                         "none")  # fmt: skip
    for option, value in (("--exposure-share", args.exposure_share), ("--grid", args.grid),
                          ("--boundary", args.boundary)):  # fmt: skip
        if value is not None and not by_motion:
            raise ValueError(f"{option} is for --method motion-network or motion")
    if args.exposure_share is not None and not args.exposure_share > 0:
        raise ValueError(f"--exposure-share must be > 0, got {args.exposure_share}")
    if args.grid is not None and args.grid < 1:
        raise ValueError(f"--grid must be >= 1, got {args.grid}")
    shipped = MOTION_CHECKPOINT if args.method == "motion-network" else DEFAULT_CHECKPOINT
    checkpoint = args.checkpoint or shipped
    # a damaged checkpoint stops before any frame is read
    model = None if args.method == "motion" else load_video_deblur(checkpoint)
    paths = list_frames(args.input)
    target = Path(args.output)
    check_output(target, args.input, args.checkpoint, names=[p.name for p in paths],
                 overwrite=args.overwrite)  # fmt: skip
    for path in paths:  # every method restores 8-bit RGB: refuse what it would change
        header = image_header(path)
        if (header.bit_depth, header.channels) != (8, 3):
            raise ValueError(f"{path}: {header.describe()} frame; deblur-video restores 8-bit "
                             "RGB frames only and would change it (convert the frames, or use "
                             "`blurloc deblur`, which keeps depth and channels)")  # fmt: skip
    if by_motion:  # the whole video in memory: each frame's path needs its neighbours
        given = {"grid": args.grid, "boundary": args.boundary}
        options = {name: value for name, value in given.items() if value is not None}
        video = np.stack(list(read_frames(paths)))
        if args.method == "motion":
            restored = deblur_video_motion(video, args.exposure_share, **options)
        else:
            restored = MotionNetworkRestorer(checkpoint, exposure_share=args.exposure_share,
                                             **options)(video)  # fmt: skip
    else:
        restored = restore_frames(model, read_frames(paths))  # streamed: one chunk at a time
    target.mkdir(parents=True, exist_ok=True)
    for path, frame in zip(paths, restored, strict=True):
        write_image_file(target / path.name, frame)
    print(json.dumps({"frames": len(paths), "output": str(target)}))
    return 0


def add_blur_estimate_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc blur-estimate`` and its options to ``commands``."""
    estimate = commands.add_parser(
        "blur-estimate", help="detect motion blur, estimate its length and angle (JSON lines)"
    )
    estimate.add_argument("images", nargs="+", help="image files")
    estimate.set_defaults(handler=_blur_estimate)


def add_deblur_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc deblur`` and its options to ``commands``."""
    deblur = commands.add_parser(
        "deblur", help="Wiener deblurring of an image or a folder (blind without a kernel)"
    )
    deblur.add_argument("input", help="image file, or folder of images")
    deblur.add_argument("output", help="image file, or folder (same names as in the input)")
    deblur.add_argument("--kernel", help="blur kernel as .npy or a gray image (normalised)")
    deblur.add_argument("--length", type=float, help="linear motion blur length, px")
    deblur.add_argument("--angle", type=float, help="its angle, degrees CCW from horizontal")
    deblur.add_argument("--nsr", type=float,
                        help="noise-to-signal ratio of eq. 4; blind: the weight of blind "
                             "deblurring's regulariser (default: estimated)")  # fmt: skip
    deblur.add_argument("--overwrite", action="store_true", help=OVERWRITE_HELP)
    deblur.set_defaults(handler=_deblur)


def add_train_video_deblur_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc train-video-deblur`` and its options to ``commands``."""
    train = commands.add_parser(
        "train-video-deblur", help="train the recurrent deblurring network on a stand-in root"
    )
    train.add_argument(
        "--data",
        required=True,
        nargs="+",
        help="stand-in roots (they need sharp frames), their sequences pooled",
    )
    train.add_argument(
        "--input",
        choices=("blurred", "motion"),
        default="blurred",
        help="what the network learns to restore: blurred (default) frames, as the paper's "
        "network; or motion: every video first deconvolved by its own motion (the exposure "
        "share read from it), as deblur-video's default method feeds the network",
    )
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
        "per --photo-noise value (half as many to the validation; default 0)",
    )
    train.add_argument("--photo-noise", type=float, nargs="+", default=[0.01],
                       help="sensor noise of the photo videos, one set per value (default "
                            "0.01; 0: none)")  # fmt: skip
    train.add_argument("--workers", type=int, default=2,
                       help="processes that deconvolve videos at once with --input motion "
                            "(default 2)")  # fmt: skip
    add_training_options(train)
    train.set_defaults(handler=_train_video_deblur)


def add_deblur_video_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc deblur-video`` and its options to ``commands``."""
    video = commands.add_parser(
        "deblur-video",
        help="deblur a video folder: kernels from its own motion, then the recurrent network",
    )
    video.add_argument("input", help="7-Scenes sequence folder or folder of images")
    video.add_argument("output", help="folder for the deblurred frames (same names)")
    video.add_argument(
        "--method",
        choices=("motion-network", "network", "motion"),
        default="motion-network",
        help="motion-network (default): Wiener deconvolution of each frame by the path its image "
        "took during the exposure, from the video's own motion, then the recurrent network over "
        "the deconvolved frames; network: the recurrent network alone (the paper's method); "
        "motion: the deconvolution alone (both motion methods hold the video in memory)",
    )
    video.add_argument("--exposure-share", type=float,
                       help="with the motion methods: exposure time over frame interval "
                            "(default: read from the video where its frames' blurs differ, "
                            "blur.calibrate_exposure_share, else 1.0, that of frames averaged "
                            "the GoPro way; 0.5 for a 180-degree shutter)")  # fmt: skip
    video.add_argument("--grid", type=int,
                       help="with the motion methods: kernels per side of a grid over each "
                            "frame, for a camera that turns about its optical axis or moves "
                            "along it (default 3; 1: one kernel per frame)")  # fmt: skip
    video.add_argument("--boundary", choices=("unknown", "mirror"),
                       help="with the motion methods: the image beyond the frame solved for as "
                            "unknown (default), or a mirror of the frame (several times "
                            "faster, rings at the border where the camera pans)")  # fmt: skip
    video.add_argument("--checkpoint",
                       help="network checkpoint (default: the shipped one of the method: trained "
                            "on deconvolved frames for motion-network, on blurred frames for "
                            "network)")  # fmt: skip
    video.add_argument("--overwrite", action="store_true", help=OVERWRITE_HELP)
    video.set_defaults(handler=_deblur_video)
