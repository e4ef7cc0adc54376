"""Training loops: seeds, progress bars, checkpoints, resume and device choice.

Pose regression (issue 5): see :class:`PoseTrainConfig` and :func:`train_pose`.

Video deblurring (issue 4): clips of T consecutive blurred frames with their sharp frames from
the stand-in's training sequences; random crops, flips and time reversal; Charbonnier loss
sqrt((L_t - S_t)^2 + eps^2) against the sharp frame; Adam with a cosine learning rate. The last
VALIDATION_FRACTION of every training sequence is held out as the validation split (a temporal
cut, so no validation frame sits inside a training clip).
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np
import torch
from tqdm.auto import tqdm

from .config import seed_everything
from .data.sevenscenes import (
    PoseSequenceDataset,
    SequenceFrames,
    list_scenes,
    load_split,
    read_image,
)
from .geometry import rotation_to_quaternion
from .metrics import pose_summary
from .models.pose import LearnedWeighting, PoseConfig, PoseRegressor, pose_loss
from .models.video_deblur import VideoDeblurConfig, VideoDeblurNet
from .video import mean_frame_psnr, restore_sequence, to_tensor

VALIDATION_FRACTION = 0.15
CHECKPOINT_FORMAT = "blurloc-video-deblur-1"


def choose_device(device: str = "auto") -> torch.device:
    """``auto``: CUDA when present, else CPU; otherwise the named device."""
    if device == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    return torch.device(device)


@dataclass
class VideoTrainConfig:
    """Settings of :func:`train_video_deblur` (defaults: about 3 minutes on 2 CPU cores)."""

    steps: int = 1200
    batch: int = 8
    clip_frames: int = 5
    crop: int = 64
    lr: float = 2e-3
    charbonnier_eps: float = 1e-3
    validate_every: int = 300
    seed: int = 0
    device: str = "auto"
    model: VideoDeblurConfig = field(default_factory=VideoDeblurConfig)


def _load_sequence(sequence: SequenceFrames, frames: list[int]) -> tuple[np.ndarray, np.ndarray]:
    blurred = np.stack([read_image(sequence.path(f, "color")) for f in frames])
    sharp = np.stack([read_image(sequence.path(f, "sharp")) for f in frames])
    return blurred, sharp


def load_video_splits(
    root: str | os.PathLike, scenes: list[str] | None = None
) -> dict[str, list[tuple[np.ndarray, np.ndarray]]]:
    """Blurred and sharp frames (uint8) of every sequence: ``train`` and ``validation`` (the
    last VALIDATION_FRACTION of each training sequence) and ``test``."""
    splits: dict[str, list] = {"train": [], "validation": [], "test": []}
    for scene in scenes or list_scenes(root):
        for sequence in load_split(root, scene, "train"):
            cut = len(sequence.frame_ids) - max(2, round(VALIDATION_FRACTION * len(sequence)))
            splits["train"].append(_load_sequence(sequence, sequence.frame_ids[:cut]))
            splits["validation"].append(_load_sequence(sequence, sequence.frame_ids[cut:]))
        for sequence in load_split(root, scene, "test"):
            splits["test"].append(_load_sequence(sequence, sequence.frame_ids))
    return splits


def _sample_clips(
    sequences: list[tuple[np.ndarray, np.ndarray]],
    config: VideoTrainConfig,
    rng: np.random.Generator,
) -> tuple[torch.Tensor, torch.Tensor]:
    """A batch of random clips: crops, flips and time reversal shared by blurred and sharp."""
    usable = [s for s in sequences if len(s[0]) >= config.clip_frames]
    if not usable:
        raise ValueError(f"no training sequence has {config.clip_frames} frames")
    blurred_batch, sharp_batch = [], []
    for _ in range(config.batch):
        blurred, sharp = usable[rng.integers(len(usable))]
        start = rng.integers(0, len(blurred) - config.clip_frames + 1)
        height, width = blurred.shape[1:3]
        crop_h, crop_w = min(config.crop, height), min(config.crop, width)
        top, left = rng.integers(0, height - crop_h + 1), rng.integers(0, width - crop_w + 1)
        window = (slice(start, start + config.clip_frames), slice(top, top + crop_h),
                  slice(left, left + crop_w))  # fmt: skip
        clip_b, clip_s = blurred[window], sharp[window]
        if rng.random() < 0.5:
            clip_b, clip_s = clip_b[:, :, ::-1], clip_s[:, :, ::-1]
        if rng.random() < 0.5:
            clip_b, clip_s = clip_b[:, ::-1], clip_s[:, ::-1]
        if rng.random() < 0.5:
            clip_b, clip_s = clip_b[::-1], clip_s[::-1]
        blurred_batch.append(clip_b)
        sharp_batch.append(clip_s)
    return to_tensor(np.stack(blurred_batch)), to_tensor(np.stack(sharp_batch))


def validation_psnr(
    model: VideoDeblurNet, sequences: list[tuple[np.ndarray, np.ndarray]], device: torch.device
) -> float:
    """Mean PSNR (dB, uint8 range) of the restored frames against the sharp ones."""
    return mean_frame_psnr([(restore_sequence(model, blurred, device), sharp)
                            for blurred, sharp in sequences])  # fmt: skip


def save_checkpoint(path: Path, payload: dict) -> None:
    """torch.save to a temporary file, then rename (a crash never leaves half a checkpoint)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_suffix(".tmp")
    torch.save(payload, temporary)
    os.replace(temporary, path)


def load_video_deblur(path: str | os.PathLike, device: str = "cpu") -> VideoDeblurNet:
    """The network stored in a checkpoint, in eval mode; ValueError if the file is missing or
    is not a video-deblurring checkpoint of this package."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: checkpoint file is missing")
    try:
        payload = torch.load(path, map_location=device, weights_only=True)
    except Exception as error:  # torch raises several types for damaged files
        raise ValueError(f"{path}: not a readable checkpoint ({error})") from error
    if not isinstance(payload, dict) or payload.get("format") != CHECKPOINT_FORMAT:
        raise ValueError(f"{path}: not a blurloc video-deblurring checkpoint")
    model = VideoDeblurNet(VideoDeblurConfig(**payload["model_config"]))
    try:
        model.load_state_dict(payload["model"])
    except RuntimeError as error:
        raise ValueError(f"{path}: weights do not fit the stored configuration") from error
    return model.to(device).eval()


def train_video_deblur(
    splits: dict[str, list[tuple[np.ndarray, np.ndarray]]],
    out_dir: str | os.PathLike,
    config: VideoTrainConfig | None = None,
    progress: bool = True,
    resume: bool = True,
    stop_after: int | None = None,
) -> dict:
    """Train :class:`VideoDeblurNet` on ``splits['train']`` and keep the checkpoint with the best
    validation PSNR (``best.pt``; ``last.pt`` every validation, for resuming). ``stop_after``
    ends this call at the first validation after that many steps (a later call resumes).
    Returns the
    history: steps, training loss (mean over each validation interval), validation PSNR and
    seconds."""
    config = config or VideoTrainConfig()
    out_dir = Path(out_dir)
    device = choose_device(config.device)
    seed_everything(config.seed)
    rng = np.random.default_rng(config.seed)
    model = VideoDeblurNet(config.model).to(device)
    optimiser = torch.optim.Adam(model.parameters(), lr=config.lr)
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(optimiser, config.steps, 1e-2 * config.lr)
    history = {"step": [], "train_loss": [], "val_psnr": [], "seconds": []}
    step, best, elapsed = 0, -np.inf, 0.0
    last = out_dir / "last.pt"
    if resume and last.is_file():
        payload = torch.load(last, map_location=device, weights_only=False)
        if payload.get("train_config") == _plain(config):
            model.load_state_dict(payload["model"])
            optimiser.load_state_dict(payload["optimiser"])
            schedule.load_state_dict(payload["schedule"])
            step, history, best = payload["step"], payload["history"], payload["best"]
            rng.bit_generator.state = payload["rng"]
            torch.set_rng_state(payload["torch_rng"])
            elapsed = history["seconds"][-1] if history["seconds"] else 0.0
    losses, started = [], time.perf_counter() - elapsed
    bar = tqdm(total=config.steps, initial=step, disable=not progress, desc="video deblur")
    first_step = step
    while step < config.steps:
        model.train()
        blurred, sharp = _sample_clips(splits["train"], config, rng)
        restored, _ = model(blurred.to(device))
        loss = torch.sqrt((restored - sharp.to(device)) ** 2 + config.charbonnier_eps**2).mean()
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        schedule.step()
        losses.append(loss.item())
        step += 1
        bar.update()
        if step % config.validate_every == 0 or step == config.steps:
            psnr_db = validation_psnr(model, splits["validation"], device)
            history["step"].append(step)
            history["train_loss"].append(float(np.mean(losses)))
            history["val_psnr"].append(psnr_db)
            history["seconds"].append(time.perf_counter() - started)
            losses = []
            bar.set_postfix(val_psnr=f"{psnr_db:.2f}")
            payload = {
                "format": CHECKPOINT_FORMAT, "model_config": config.model.as_dict(),
                "model": model.state_dict(), "step": step, "history": history,
                "train_config": _plain(config), "val_psnr": psnr_db,
            }  # fmt: skip
            if psnr_db > best:
                best = psnr_db
                save_checkpoint(out_dir / "best.pt", payload)
            save_checkpoint(last, {**payload, "optimiser": optimiser.state_dict(),
                                   "schedule": schedule.state_dict(), "best": best,
                                   "rng": rng.bit_generator.state,
                                   "torch_rng": torch.get_rng_state()})  # fmt: skip
            if stop_after is not None and step - first_step >= stop_after:
                break
    bar.close()
    (out_dir / "history.json").write_text(json.dumps(history, indent=1))
    return history


def _plain(config: VideoTrainConfig | PoseTrainConfig) -> dict:
    """The training settings as plain data (device excluded: resuming may change it)."""
    settings = asdict(config)
    settings.pop("device")
    return settings


# --- camera pose regression (issue 5) ---------------------------------------------------------


@dataclass
class PoseTrainConfig:
    """Settings of :func:`train_pose`. The paper's: images resized to 256 and cropped to 224,
    Adam, lr 5e-5, weight decay 3e-4, 50 epochs, batch 64, dropout 0.6, beta 0.8. CPU-scale
    defaults here (a 1000-frame scene in minutes on 2 cores): 64 px short side, 56 px crops,
    a small ResNet, lr 1e-3 (lr 5e-5 barely moves in 15 epochs), 15 epochs, batch 16 windows
    of 4 frames; weight decay, dropout and beta as in the paper. ``image`` is the frame kind read
    (``color``; ``sharp`` on the stand-in for the upper bound)."""

    resize: int = 64
    crop: int = 56
    window: int = 4
    stride: int = 2
    batch: int = 16
    epochs: int = 15
    lr: float = 1e-3
    weight_decay: float = 3e-4
    beta: float = 0.8
    learned_weighting: bool = False
    image: str = "color"
    seed: int = 0
    device: str = "auto"
    model: PoseConfig = field(default_factory=PoseConfig)


POSE_CHECKPOINT_FORMAT = "blurloc-pose-1"


def split_validation(sequences: list[SequenceFrames]) -> tuple[list, list]:
    """Training sequences cut in time: the last VALIDATION_FRACTION of each for validation."""
    train, validation = [], []
    for sequence in sequences:
        cut = len(sequence.frame_ids) - max(1, round(VALIDATION_FRACTION * len(sequence)))
        train.append(replace(sequence, frame_ids=sequence.frame_ids[:cut]))
        validation.append(replace(sequence, frame_ids=sequence.frame_ids[cut:]))
    return train, validation


def _pose_dataset(sequences, config: PoseTrainConfig) -> PoseSequenceDataset:
    """Training windows (single frames for the head-less baseline), random crops."""
    single = config.model.head == "none"
    return PoseSequenceDataset(
        sequences, window=1 if single else config.window, stride=1 if single else config.stride,
        resize=config.resize, crop=config.crop, random_crop=True, kinds=(config.image,),
    )


def predict_poses(
    model: PoseRegressor, sequences: list[SequenceFrames], config: PoseTrainConfig,
    device: torch.device | str = "cpu",
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Predicted and true positions and quaternions for every frame of ``sequences`` (in
    sequence order, then frame order). Recurrent heads see non-overlapping windows of
    ``config.window`` frames (the last window of a sequence ends at its last frame)."""
    window = config.window
    short = [s for s in sequences if len(s) < window]
    if short:
        raise ValueError(f"{short[0].folder}: {len(short[0])} frames, shorter than the window "
                         f"({window})")  # fmt: skip
    dataset = PoseSequenceDataset(sequences, window=window, stride=window, resize=config.resize,
                                  crop=config.crop, kinds=(config.image,))  # fmt: skip
    for index, sequence in enumerate(sequences):
        if len(sequence) % window:
            dataset.index.append((index, len(sequence) - window))
    model = model.to(device).eval()
    predicted: dict[tuple[int, int], tuple] = {}
    with torch.inference_mode():
        for start in range(0, len(dataset), 32):
            items = [dataset[i] for i in range(start, min(start + 32, len(dataset)))]
            frames = torch.stack([item[config.image] for item in items]).to(device)
            positions, quaternions = model(frames)
            for item, position, quaternion in zip(items, positions, quaternions, strict=True):
                for k in range(window):
                    key = (int(item["sequence"]), int(item["frame"]) + k)  # frame: window start
                    predicted.setdefault(key, (position[k].cpu().numpy(),
                                               quaternion[k].cpu().numpy(),
                                               item["position"][k].numpy(),
                                               item["quaternion"][k].numpy()))  # fmt: skip
    keys = sorted(predicted)
    columns = [np.stack([predicted[k][c] for k in keys]) for c in range(4)]
    return columns[0], columns[1], columns[2], columns[3]


def load_pose_model(
    path: str | os.PathLike, device: str = "cpu"
) -> tuple[PoseRegressor, PoseTrainConfig]:
    """A pose checkpoint's model (eval mode) and training settings; ValueError when the file is
    missing or not a pose checkpoint of this package."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: checkpoint file is missing")
    payload = torch.load(path, map_location=device, weights_only=False)
    if not isinstance(payload, dict) or payload.get("format") != POSE_CHECKPOINT_FORMAT:
        raise ValueError(f"{path}: not a blurloc pose checkpoint")
    settings = dict(payload["train_config"])
    model_config = PoseConfig(**settings.pop("model"))
    config = PoseTrainConfig(**settings, model=model_config)
    model = PoseRegressor(model_config)
    model.load_state_dict(payload["model"])
    return model.to(device).eval(), config


def train_pose(
    root: str | os.PathLike,
    scene: str,
    out_dir: str | os.PathLike,
    config: PoseTrainConfig | None = None,
    progress: bool = True,
    resume: bool = True,
    stop_after: int | None = None,
) -> dict:
    """Train a :class:`PoseRegressor` on a scene's TrainSplit (minus the validation cut) with
    the loss of eq. 14 (or the learned weighting); keep the epoch with the lowest median
    validation position + orientation error (``best.pt``), ``last.pt`` for resuming;
    ``stop_after`` ends this call after that many epochs (a later call resumes). Returns
    the history (epoch, train_loss, val_position_m, val_orientation_deg, seconds)."""
    config = config or PoseTrainConfig()
    out_dir = Path(out_dir)
    device = choose_device(config.device)
    seed_everything(config.seed)
    sequences = load_split(root, scene, "train")
    if not sequences:
        raise ValueError(f"{root}/{scene}: no training sequences")
    train_sequences, validation = split_validation(sequences)
    dataset = _pose_dataset(train_sequences, config)
    loader = torch.utils.data.DataLoader(dataset, batch_size=config.batch, shuffle=True,
                                         drop_last=len(dataset) > config.batch)  # fmt: skip
    model = PoseRegressor(config.model).to(device)
    with torch.no_grad():  # start from the mean training pose
        poses = np.concatenate([s.poses() for s in train_sequences])
        model.position.bias.copy_(torch.as_tensor(poses[:, :3, 3].mean(axis=0)))
        quaternions = rotation_to_quaternion(poses[:, :3, :3])
        model.rotation.bias.copy_(torch.as_tensor(quaternions.mean(axis=0)))
    weighting = LearnedWeighting().to(device) if config.learned_weighting else None
    parameters = list(model.parameters()) + (list(weighting.parameters()) if weighting else [])
    optimiser = torch.optim.Adam(parameters, lr=config.lr, weight_decay=config.weight_decay)
    history = {"epoch": [], "train_loss": [], "val_position_m": [], "val_orientation_deg": [],
               "seconds": []}  # fmt: skip
    epoch, best = 0, np.inf
    settings = _plain(config)
    last = out_dir / "last.pt"
    if resume and last.is_file():
        payload = torch.load(last, map_location=device, weights_only=False)
        stored_head = payload.get("train_config", {}).get("model", {}).get("head")
        if stored_head != config.model.head:
            raise ValueError(f"{last}: a checkpoint of head {stored_head!r}, not "
                             f"{config.model.head!r}: restart or use another folder")
        if payload.get("train_config") == settings:
            model.load_state_dict(payload["model"])
            optimiser.load_state_dict(payload["optimiser"])
            if weighting is not None:
                weighting.load_state_dict(payload["weighting"])
            epoch, history, best = payload["epoch"], payload["history"], payload["best"]
            torch.set_rng_state(payload["torch_rng"])
    started = time.perf_counter() - (history["seconds"][-1] if history["seconds"] else 0.0)
    bar = tqdm(total=config.epochs, initial=epoch, disable=not progress, desc=f"pose {scene}")
    first_epoch = epoch
    while epoch < config.epochs:
        if stop_after is not None and epoch - first_epoch >= stop_after:
            break
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
            losses.append(loss.item())
        epoch += 1
        shortest = min(len(s) for s in validation)
        p, q, tp, tq = predict_poses(model, validation, replace(config, window=min(
            config.window, shortest)), device)  # fmt: skip
        summary = pose_summary(tp, tq, p, q, config.beta)
        history["epoch"].append(epoch)
        history["train_loss"].append(float(np.mean(losses)))
        history["val_position_m"].append(summary["position_m"]["median"])
        history["val_orientation_deg"].append(summary["orientation_deg"]["median"])
        history["seconds"].append(time.perf_counter() - started)
        bar.update()
        score = summary["position_m"]["median"] + summary["orientation_deg"]["median"] / 10.0
        payload = {"format": POSE_CHECKPOINT_FORMAT, "train_config": settings,
                   "model": model.state_dict(), "epoch": epoch, "history": history,
                   "scene": scene}  # fmt: skip
        if score < best:
            best = score
            save_checkpoint(out_dir / "best.pt", payload)
        save_checkpoint(last, {**payload, "optimiser": optimiser.state_dict(), "best": best,
                               "weighting": weighting.state_dict() if weighting else None,
                               "torch_rng": torch.get_rng_state()})  # fmt: skip
    bar.close()
    (out_dir / "history.json").write_text(json.dumps(history, indent=1))
    return history
