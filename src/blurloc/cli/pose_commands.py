"""``blurloc`` subcommands for camera poses: train-pose, eval-pose, pose-error."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from ..files import check_output
from .common import OVERWRITE_HELP, add_training_options, warnings_to_stderr


def _train_pose(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from ..models.pose import PoseConfig
    from ..train.config import PoseTrainConfig
    from ..train.pose import train_pose

    root = _input_root(args.data, args.input)
    check_output(args.out, args.data, root, names=())
    config = PoseTrainConfig(seed=args.seed, device=args.device,
                             model=PoseConfig(head=args.head, encoder=args.encoder,
                                              pretrained=args.pretrained))  # fmt: skip
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
        from ..config import RESULTS_DIR

        deblurred = root / "deblurred" / condition
        root = deblurred if deblurred.is_dir() else RESULTS_DIR / "deblurred" / condition
        if not root.is_dir():
            raise ValueError(f"{root}: no {condition}-deblurred frames; run notebook 03 first")
    return root


def _eval_pose(args: argparse.Namespace) -> int:
    check_output(args.out, args.model, args.data, overwrite=args.overwrite)

    import numpy as np

    from ..data import load_split
    from ..inference import load_pose_model, predict_poses
    from ..metrics import pose_summary
    from ..trajectory import quaternions_to_poses, write_tum

    path = Path(args.model) / "best.pt" if Path(args.model).is_dir() else Path(args.model)
    with warnings_to_stderr():
        model, config = load_pose_model(path, scene=args.scene)
    sequences = load_split(args.data, args.scene, "test")
    if not sequences:
        raise ValueError(f"{args.data}/{args.scene}: no TestSplit sequences")
    pair = predict_poses(model, sequences, config)
    write_tum(args.out, np.arange(len(pair)),
              quaternions_to_poses(pair.estimate_positions, pair.estimate_quaternions))  # fmt: skip
    print(json.dumps(pose_summary(pair, config.beta)))
    return 0


def _pose_error(args: argparse.Namespace) -> int:
    from ..trajectory import compare_trajectories

    if not args.max_difference > 0:  # also refuses NaN
        raise ValueError(f"--max-difference must be a positive number of seconds, got "
                         f"{args.max_difference}")  # fmt: skip
    with warnings_to_stderr():
        errors = compare_trajectories(args.ground_truth, args.estimate, args.max_difference)
    print(json.dumps(errors))
    return 0


def add_train_pose_parser(commands: argparse._SubParsersAction) -> None:
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
    pose.add_argument("--encoder", choices=("small", "resnet18", "resnet34", "efficientnet_lite0"),
                      default="small")  # fmt: skip
    pose.add_argument(
        "--pretrained",
        action="store_true",
        help="start the encoder from ImageNet weights that install with the package "
        "(efficientnet_lite0 only)",
    )
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
    add_training_options(pose)
    pose.set_defaults(handler=_train_pose)


def add_eval_pose_parser(commands: argparse._SubParsersAction) -> None:
    """Add ``blurloc eval-pose`` and its options to ``commands``."""
    evaluate = commands.add_parser("eval-pose", help="predict a scene's test frames (TUM file)")
    evaluate.add_argument("--data", required=True)
    evaluate.add_argument("--scene", required=True)
    evaluate.add_argument("--model", required=True, help="checkpoint or train-pose --out folder")
    evaluate.add_argument("--out", required=True, help="TUM file to write")
    evaluate.add_argument("--overwrite", action="store_true", help=OVERWRITE_HELP)
    evaluate.set_defaults(handler=_eval_pose)


def add_pose_error_parser(commands: argparse._SubParsersAction) -> None:
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
