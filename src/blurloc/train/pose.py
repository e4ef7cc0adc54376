"""Training the camera-pose regressor (Sec. III.B-E) on one scene with the loss of eq. 14."""

from __future__ import annotations

import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch
from tqdm.auto import tqdm

from ..checkpoints import CHECKPOINT_FORMATS, save_checkpoint
from ..config import seed_everything
from ..data.sevenscenes import SequenceFrames, load_split
from ..geometry import rotation_to_quaternion
from ..inference import predict_poses
from ..metrics import pose_summary
from ..models.pose import LearnedWeighting, PoseRegressor, pose_loss
from .config import PoseTrainConfig
from .datasets import FrameCache, PoseSequenceDataset
from .loop import (
    choose_device,
    fixed_threads,
    resume_state,
    validation_cut,
    write_history,
)


def split_validation(
    sequences: list[SequenceFrames],
) -> tuple[list[SequenceFrames], list[SequenceFrames]]:
    """Training sequences cut in time: the end of each (:func:`~.loop.validation_cut`) for
    validation.

    Parameters
    ----------
    sequences : list of SequenceFrames
        A scene's training sequences.

    Returns
    -------
    train, validation : list of SequenceFrames
        The beginning and the end of every sequence.
    """
    train, validation = [], []
    for sequence in sequences:
        cut = len(sequence.frame_ids) - validation_cut(len(sequence))
        train.append(replace(sequence, frame_ids=sequence.frame_ids[:cut]))
        validation.append(replace(sequence, frame_ids=sequence.frame_ids[cut:]))
    return train, validation


def train_pose(
    root: str | os.PathLike,
    scene: str,
    out_dir: str | os.PathLike,
    config: PoseTrainConfig | None = None,
    progress: bool = True,
    restart: bool = False,
    stop_after: int | None = None,
    cache: FrameCache | None = None,
) -> dict:
    """Train a :class:`~blurloc.models.pose.PoseRegressor` on a scene's training split.

    The loss is eq. 14 (or the learned weighting); the epoch with the lowest median validation
    position + orientation/10 error is kept (``best.pt``), ``last.pt`` holds the state to
    resume from. Each frame is decoded and resized once per run (a
    :class:`~.datasets.FrameCache` shared by the training and validation sets, bounded by
    :data:`~.datasets.CACHE_BYTES`). A run in ``out_dir`` with the same settings resumes where
    it stopped, with the same numbers as an uninterrupted run.

    Parameters
    ----------
    root : str or os.PathLike
        A 7-Scenes-layout root.
    scene : str
        The scene (its TrainSplit minus the validation cut is trained on).
    out_dir : str or os.PathLike
        The run folder.
    config : PoseTrainConfig, optional
        Settings (defaults when None).
    progress : bool
        Show a progress bar.
    restart : bool
        Start afresh even if ``out_dir`` holds a run with other settings (replacing it).
    stop_after : int, optional
        End this call after that many epochs (a later call resumes).
    cache : FrameCache, optional
        Decoded frames shared with other runs on the same frames (a new one when None).

    Returns
    -------
    dict
        History: ``epoch``, ``train_loss``, ``val_position_m`` and ``val_orientation_deg``
        (medians, eq. 12-13), ``seconds``, one entry per epoch.

    Raises
    ------
    ValueError
        If the scene has no training sequences, ``out_dir`` holds another model kind, a damaged
        checkpoint, or a run with other settings (without ``restart``); or the device is not
        available.
    """
    config = config or PoseTrainConfig()
    out_dir = Path(out_dir)
    device = choose_device(config.device)
    settings = {"train_config": config.settings(), "scene": scene}
    resumed = resume_state(out_dir, "pose", settings, restart, device)
    sequences = load_split(root, scene, "train")
    if not sequences:
        raise ValueError(f"{Path(root) / scene}: no training sequences")
    with fixed_threads(config.threads):
        return _train(
            sequences, scene, out_dir, config, device, resumed, progress, stop_after, cache
        )


def _training_loader(
    train_sequences: list[SequenceFrames], config: PoseTrainConfig, cache: FrameCache
) -> torch.utils.data.DataLoader:
    """Random windows of the training sequences, ``config.batch`` per step.

    The single-frame head (``head == "none"``) sees single frames, ``window`` times as many per
    step, so that both heads train on the same frames for the same number of steps.
    """
    single = config.model.head == "none"
    dataset = PoseSequenceDataset(
        train_sequences, window=1 if single else config.window,
        stride=1 if single else config.stride, resize=config.resize, crop=config.crop,
        random_crop=not config.fixed_crop, kinds=(config.image,), cache=cache,
    )  # fmt: skip
    frames_per_item = config.window if single else 1
    batch = config.batch * frames_per_item
    per_epoch = len(dataset)
    if config.windows_per_epoch is not None:
        per_epoch = config.windows_per_epoch * frames_per_item
    sampler = torch.utils.data.RandomSampler(dataset, num_samples=per_epoch)
    return torch.utils.data.DataLoader(dataset, batch_size=batch, sampler=sampler,
                                       drop_last=per_epoch > batch)  # fmt: skip


def _model_at_mean_pose(
    config: PoseTrainConfig, train_sequences: list[SequenceFrames], cache: FrameCache,
    device: torch.device,
) -> PoseRegressor:  # fmt: skip
    """A new regressor whose output biases are the mean training position and quaternion."""
    model = PoseRegressor(config.model).to(device)
    with torch.no_grad():
        poses = np.concatenate([cache.poses(s) for s in train_sequences])
        model.position.bias.copy_(torch.as_tensor(poses[:, :3, 3].mean(axis=0)))
        quaternions = rotation_to_quaternion(poses[:, :3, :3])
        model.rotation.bias.copy_(torch.as_tensor(quaternions.mean(axis=0)))
    return model


def _train_epoch(
    model: PoseRegressor, weighting: LearnedWeighting | None, loader: torch.utils.data.DataLoader,
    optimiser: torch.optim.Optimizer, schedule: torch.optim.lr_scheduler.LRScheduler,
    config: PoseTrainConfig, device: torch.device,
) -> list[float]:  # fmt: skip
    """One pass over ``loader`` (eq. 14's loss, or the learnt weighting); the step losses."""
    model.train()
    losses = []
    for batch in loader:
        frames = batch[config.image].to(device)
        position, quaternion = model(frames)
        true_position = batch["position"].to(device).float()
        true_quaternion = batch["quaternion"].to(device).float()
        if weighting is None:
            loss = pose_loss(position, quaternion, true_position, true_quaternion, config.beta)
        else:
            loss = weighting(position, quaternion, true_position, true_quaternion)
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        schedule.step()
        losses.append(loss.item())
    return losses


def _train(
    sequences: list[SequenceFrames], scene: str, out_dir: Path, config: PoseTrainConfig,
    device: torch.device, resumed: dict | None, progress: bool, stop_after: int | None,
    cache: FrameCache | None,
) -> dict:  # fmt: skip
    """The loop of :func:`train_pose`, from scratch or from ``resumed``."""
    seed_everything(config.seed)
    train_sequences, validation = split_validation(sequences)
    cache = cache if cache is not None else FrameCache()
    loader = _training_loader(train_sequences, config, cache)
    validation_config = replace(config, window=min(config.window, *map(len, validation)))
    model = _model_at_mean_pose(config, train_sequences, cache, device)
    weighting = LearnedWeighting().to(device) if config.learned_weighting else None
    parameters = list(model.parameters()) + (list(weighting.parameters()) if weighting else [])
    optimiser = torch.optim.Adam(parameters, lr=config.lr, weight_decay=config.weight_decay)
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(  # per step, to 1 % of lr at the end
        optimiser, config.epochs * len(loader), 1e-2 * config.lr
    )
    history = {"epoch": [], "train_loss": [], "val_position_m": [], "val_orientation_deg": [],
               "seconds": []}  # fmt: skip
    epoch, best = 0, np.inf
    if resumed is not None:
        model.load_state_dict(resumed["model"])
        optimiser.load_state_dict(resumed["optimiser"])
        schedule.load_state_dict(resumed["schedule"])
        if weighting is not None:
            weighting.load_state_dict(resumed["weighting"])
        epoch, history, best = resumed["epoch"], resumed["history"], resumed["best"]
        torch.set_rng_state(resumed["torch_rng"])
    started = time.perf_counter() - (history["seconds"][-1] if history["seconds"] else 0.0)
    bar = tqdm(total=config.epochs, initial=epoch, disable=not progress, desc=f"pose {scene}")
    first_epoch = epoch
    while epoch < config.epochs:
        if stop_after is not None and epoch - first_epoch >= stop_after:
            break
        losses = _train_epoch(model, weighting, loader, optimiser, schedule, config, device)
        epoch += 1
        pair = predict_poses(model, validation, validation_config, device, cache)
        summary = pose_summary(pair, config.beta)
        history["epoch"].append(epoch)
        history["train_loss"].append(float(np.mean(losses)))
        history["val_position_m"].append(summary["position_m"]["median"])
        history["val_orientation_deg"].append(summary["orientation_deg"]["median"])
        history["seconds"].append(time.perf_counter() - started)
        bar.update()
        score = summary["position_m"]["median"] + summary["orientation_deg"]["median"] / 10.0
        payload = {"format": CHECKPOINT_FORMATS["pose"], "train_config": config.settings(),
                   "model": model.state_dict(), "epoch": epoch, "history": history,
                   "scene": scene}  # fmt: skip
        if score < best:
            best = score
            save_checkpoint(out_dir / "best.pt", payload)
        save_checkpoint(out_dir / "last.pt", {
            **payload, "optimiser": optimiser.state_dict(), "schedule": schedule.state_dict(),
            "best": best,
            "weighting": weighting.state_dict() if weighting else None,
            "torch_rng": torch.get_rng_state(),
        })  # fmt: skip
        write_history(out_dir, history)  # beside last.pt: kept when interrupted
    bar.close()
    write_history(out_dir, history)
    return history
