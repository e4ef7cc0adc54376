"""Training the recurrent video-deblurring network (eq. 8-11).

Clips of ``clip_frames`` consecutive blurred frames with their sharp frames from the stand-in's
training sequences; random crops, flips and time reversal; Charbonnier loss
sqrt((L_t - S_t)^2 + eps^2) against the sharp frame; Adam with a cosine learning rate. The end
of every training sequence (:func:`~blurloc.train.loop.validation_cut`) is held out for
validation. A network with ``wiener_input`` reads Wiener copies of the training frames, and one
with ``blur_condition`` their blind blur descriptors, both computed once on whole frames. A
network for :class:`~blurloc.inference.MotionNetworkRestorer` trains on the training videos
deconvolved by their own motion (:func:`with_motion_deconvolution`).
"""

from __future__ import annotations

import os
import time
import warnings
from dataclasses import replace
from functools import partial
from pathlib import Path

import numpy as np
import torch
from tqdm.auto import tqdm

from ..checkpoints import CHECKPOINT_FORMATS, save_checkpoint
from ..config import seed_everything
from ..data.sevenscenes import SequenceFrames, list_scenes, load_split, read_image
from ..inference import frames_from_tensor, restore_sequence, to_tensor
from ..metrics import mean_frame_psnr
from ..models.video_deblur import (
    VideoDeblurConfig,
    VideoDeblurNet,
    blur_descriptors,
    network_guides,
)
from ..video_wiener import deblur_video_motion
from .config import VideoTrainConfig
from .loop import (
    choose_device,
    fixed_threads,
    parallel_map,
    resume_state,
    validation_cut,
    write_history,
)

#: Bound of the frames :func:`load_video_splits` holds in memory, bytes.
VIDEO_CACHE_BYTES = 4 * 1024**3

Video = tuple[np.ndarray, np.ndarray]


def load_video_splits(
    root: str | os.PathLike,
    scenes: list[str] | None = None,
    max_bytes: int = VIDEO_CACHE_BYTES,
    frames_per_sequence: int | None = None,
    validation_per_scene: int | None = None,
    with_test: bool = True,
) -> dict[str, list[Video]]:
    """Blurred and sharp frames of every sequence, decoded once for a whole training run.

    The trainer draws random clips from every training sequence at every step, so the frames
    stay in memory as uint8: 2 x frames x H x W x 3 bytes (the whole default stand-in, 43,000
    frames of 160x120, would take 5 GB; its first 250 frames per sequence 1.3 GB), at most
    ``max_bytes``. The validation part of a training sequence is its end
    (:func:`~blurloc.train.loop.validation_cut` of its whole length: 150 of 1000 frames), so
    that validation runs the recurrence over as many frames as the sequence allows, whatever
    part of the sequence is trained on.

    Parameters
    ----------
    root : str or os.PathLike
        A stand-in root (it needs the sharp frames).
    scenes : list of str, optional
        Scenes to read (default: all).
    max_bytes : int
        Bound of the memory the frames may take, bytes (default :data:`VIDEO_CACHE_BYTES`).
    frames_per_sequence : int, optional
        Train on the first that many frames before each validation part, and read only the
        first that many frames of every test sequence (all when None).
    validation_per_scene : int, optional
        Validate on the ends of only the first that many training sequences of each scene
        (all when None): fewer, long validation sequences cost as much as many short ones.
    with_test : bool
        Read the test sequences too (a training needs only ``train`` and ``validation``; the
        whole default stand-in's training split takes 3 GB).

    Returns
    -------
    dict
        ``train``, ``validation`` (the ends of training sequences) and ``test`` (empty without
        ``with_test``): lists of (blurred, sharp) pairs of uint8 (T, H, W, 3) arrays.

    Raises
    ------
    ValueError
        If the frames would take more than ``max_bytes`` (naming the root), if
        ``validation_per_scene`` is not positive, or if a file is bad.
    """
    if validation_per_scene is not None and validation_per_scene < 1:
        raise ValueError(f"validation_per_scene must be >= 1, got {validation_per_scene}")
    parts: list[tuple[str, SequenceFrames, tuple[int, ...]]] = []
    for scene in scenes or list_scenes(root):
        for number, sequence in enumerate(load_split(root, scene, "train")):
            frames = sequence.frame_ids
            cut = len(frames) - validation_cut(len(frames))
            parts.append(("train", sequence, frames[:cut][:frames_per_sequence]))
            if validation_per_scene is None or number < validation_per_scene:
                parts.append(("validation", sequence, frames[cut:]))
        if with_test:
            parts += [("test", sequence, sequence.frame_ids[:frames_per_sequence])
                      for sequence in load_split(root, scene, "test")]  # fmt: skip
    if parts:
        _, first, frames = parts[0]
        height, width = read_image(first.path(frames[0])).shape[:2]
        needed = 2 * sum(len(frames) for _, _, frames in parts) * height * width * 3
        if needed > max_bytes:
            raise ValueError(f"{root}: its frames take {needed / 1e9:.1f} GB in memory, more "
                             f"than {max_bytes / 1e9:.1f} GB: train on fewer --scenes")  # fmt: skip
    splits: dict[str, list[Video]] = {"train": [], "validation": [], "test": []}
    for split, sequence, frames in parts:
        splits[split].append(_read_video(sequence, frames))
    return splits


def _read_video(sequence: SequenceFrames, frames: tuple[int, ...]) -> Video:
    """The blurred and the sharp frames of part of a sequence."""
    return sequence.images("color", frames), sequence.images("sharp", frames)


def _sample_clips(
    sequences: list[tuple[np.ndarray, ...]], config: VideoTrainConfig, rng: np.random.Generator
) -> list[torch.Tensor]:
    """A batch of random clips: crops, flips and time reversal shared by every part of a
    sequence's tuple (blurred, sharp and, for a network with ``wiener_input``, the Wiener
    copies of the blurred frames, as (T, H, W, 3) videos; for one with ``blur_condition``, the
    frames' (T, 3) blur descriptors, cut in time only, whose third value a mirror negates:
    :func:`~blurloc.models.video_deblur.blur_descriptor`)."""
    usable = [s for s in sequences if len(s[0]) >= config.clip_frames]
    if not usable:
        raise ValueError(f"no training sequence has {config.clip_frames} frames")
    batches: list[list[np.ndarray]] = [[] for _ in usable[0]]
    for _ in range(config.batch):
        videos = usable[rng.integers(len(usable))]
        start = rng.integers(0, len(videos[0]) - config.clip_frames + 1)
        height, width = videos[0].shape[1:3]
        crop_h, crop_w = min(config.crop, height), min(config.crop, width)
        top, left = rng.integers(0, height - crop_h + 1), rng.integers(0, width - crop_w + 1)
        window = (slice(start, start + config.clip_frames), slice(top, top + crop_h),
                  slice(left, left + crop_w))  # fmt: skip
        clips = [video[window] if video.ndim == 4 else video[window[0]] for video in videos]
        for axis in (2, 1):  # left-right, then up-down mirror
            if rng.random() < 0.5:
                clips = [np.flip(clip, axis) if clip.ndim == 4 else clip * _MIRRORED
                         for clip in clips]  # fmt: skip
        if rng.random() < 0.5:
            clips = [clip[::-1] for clip in clips]
        for batch, clip in zip(batches, clips, strict=True):
            batch.append(clip)
    return [to_tensor(np.stack(batch)) if batch[0].ndim == 4
            else torch.from_numpy(np.stack(batch).astype(np.float32))
            for batch in batches]  # fmt: skip


#: What a mirror image does to a blur descriptor: negates its third value.
_MIRRORED = np.float32([1.0, 1.0, -1.0])


def with_wiener_guides(
    videos: list[tuple[np.ndarray, ...]], config: VideoDeblurConfig
) -> list[tuple[np.ndarray, ...]]:
    """Training videos with the Wiener copy of every blurred frame, computed once on whole
    frames and whole videos (:func:`~blurloc.models.video_deblur.network_guides`), so that a
    crop of a clip reads the copy its whole frame gives (with ``wiener_motion`` the motion of
    the whole video: at inference a network restoring a video in chunks measures each chunk's
    motion alone, so its first and last frames' paths are extrapolated).

    Parameters
    ----------
    videos : list of (blurred, sharp, ...)
        uint8 (T, H, W, 3) pairs, possibly with more parts.
    config : VideoDeblurConfig
        The network's settings (which copies it reads).

    Returns
    -------
    list of (blurred, sharp, ..., guides)
        ``guides`` uint8 (T, H, W, 3), the Wiener copies of ``blurred``, appended.
    """
    return [(*video, frames_from_tensor(network_guides(to_tensor(video[0])[None], config)[0]))
            for video in videos]  # fmt: skip


def with_blur_descriptors(videos: list[tuple[np.ndarray, ...]]) -> list[tuple[np.ndarray, ...]]:
    """Training videos with the blind blur descriptor of every blurred frame, estimated once on
    whole frames (:func:`~blurloc.models.video_deblur.blur_descriptors`), as the network
    estimates them at inference; a video that already carries descriptors (a (T, 3) part, e.g.
    the blur it was made with) keeps them.

    Parameters
    ----------
    videos : list of (blurred, sharp, ...)
        uint8 (T, H, W, 3) pairs, possibly with more parts.

    Returns
    -------
    list of (blurred, sharp, ..., descriptors)
        ``descriptors`` float32 (T, 3), appended where a video has none.
    """
    return [video if any(part.ndim == 2 for part in video)
            else (*video, blur_descriptors(to_tensor(video[0])[None])[0].numpy())
            for video in videos]  # fmt: skip


def with_motion_deconvolution(
    videos: list[tuple[np.ndarray, ...]], workers: int = 1, progress: bool = False
) -> list[tuple[np.ndarray, ...]]:
    """Training videos with every blurred video replaced by its deconvolution by its own motion,
    as :class:`~blurloc.inference.MotionNetworkRestorer` feeds the network: each frame by the
    kernels of the path its image took during the exposure, the exposure share read from the
    video (:func:`~blurloc.video_wiener.deblur_video_motion` with ``exposure_share=None``), each
    video as a whole.

    Parameters
    ----------
    videos : list of (blurred, sharp, ...)
        uint8 (T, H, W, 3) pairs (T >= 2), possibly with more parts.
    workers : int
        Processes that deconvolve videos at once (each with one PyTorch thread).
    progress : bool
        Show a progress bar.

    Returns
    -------
    list of (deconvolved, sharp, ...)
        The first part of every video replaced, the others kept.
    """
    deconvolve = partial(deblur_video_motion, exposure_share=None)  # picklable for the workers
    restored = parallel_map(deconvolve, [video[0] for video in videos], workers)
    return [(frames, *video[1:]) for frames, video in
            zip(tqdm(restored, total=len(videos), disable=not progress, desc="deconvolve"),
                videos, strict=True)]  # fmt: skip


def validation_psnr(model: VideoDeblurNet, sequences: list[Video], device: torch.device) -> float:
    """Mean PSNR of the restored validation frames against the sharp ones.

    Parameters
    ----------
    model : VideoDeblurNet
    sequences : list of (blurred, sharp)
        uint8 (T, H, W, 3) pairs, each restored as one video.
    device : torch.device

    Returns
    -------
    float
        Mean over all frames of the PSNR (eq. 6, data range 255), dB.
    """
    return mean_frame_psnr([(restore_sequence(model, blurred, device), sharp)
                            for blurred, sharp in sequences])  # fmt: skip


def train_video_deblur(
    splits: dict[str, list[Video]],
    out_dir: str | os.PathLike,
    config: VideoTrainConfig | None = None,
    progress: bool = True,
    restart: bool = False,
    stop_after: int | None = None,
) -> dict:
    """Train :class:`~blurloc.models.video_deblur.VideoDeblurNet` and keep its best validation.

    ``best.pt`` holds the network with the best validation PSNR, ``last.pt`` (written at every
    validation) the state to resume from. A run in ``out_dir`` with the same settings and as
    many training and validation sequences and frames resumes where it stopped, with the same
    numbers as an uninterrupted run (a network is never continued on other training videos, nor
    a best network chosen on other validation frames).

    Parameters
    ----------
    splits : dict
        From :func:`load_video_splits` (``train`` and ``validation`` are used). A training
        video may carry a third part, its (T, 3) blur descriptors (e.g. the true blur it was
        made with), which a network with ``blur_condition`` then reads instead of its blind
        estimates (:func:`with_blur_descriptors`).
    out_dir : str or os.PathLike
        The run folder.
    config : VideoTrainConfig, optional
        Settings (defaults when None). A crop larger than the longest side of the training
        frames is clamped to it, with a warning, and recorded clamped.
    progress : bool
        Show a progress bar.
    restart : bool
        Start afresh even if ``out_dir`` holds a run with other settings (replacing it).
    stop_after : int, optional
        End this call at the first validation after that many steps (a later call resumes).

    Returns
    -------
    dict
        History: ``step``, ``train_loss`` (mean over each validation interval), ``val_psnr``
        (dB) and ``seconds``, one entry per validation.

    Raises
    ------
    ValueError
        If ``out_dir`` holds another model kind, a damaged checkpoint, or a run with other
        settings (without ``restart``); or the device is not available.
    """
    config = _crop_that_runs(config or VideoTrainConfig(), splits["train"])
    out_dir = Path(out_dir)
    device = choose_device(config.device)
    counts = {split: {"sequences": len(splits[split]),
                      "frames": sum(len(video[0]) for video in splits[split])}
              for split in ("train", "validation")}  # fmt: skip
    settings = {"train_config": config.settings(), **counts}
    resumed = resume_state(out_dir, "video-deblur", settings, restart, device)
    with fixed_threads(config.threads):
        return _train(splits, out_dir, config, settings, device, resumed, progress, stop_after)


def _crop_that_runs(config: VideoTrainConfig, videos: list[Video]) -> VideoTrainConfig:
    """``config`` with its crop clamped to the longest side of the training frames, warning
    when it changes: a clip is cut to ``min(crop, side)`` along each side, so the clamped value
    crops the same clips and is what the checkpoints record."""
    longest = max((max(video[0].shape[1:3]) for video in videos), default=config.crop)
    if config.crop <= longest:
        return config
    warnings.warn(f"--crop {config.crop} is larger than the training frames ({longest} px at "
                  f"most); {longest} is used and recorded", stacklevel=3)  # fmt: skip
    return replace(config, crop=longest)


def _train(
    splits: dict[str, list[Video]], out_dir: Path, config: VideoTrainConfig, settings: dict,
    device: torch.device, resumed: dict | None, progress: bool, stop_after: int | None,
) -> dict:  # fmt: skip
    """The loop of :func:`train_video_deblur`, from scratch or from ``resumed``."""
    seed_everything(config.seed)
    rng = np.random.default_rng(config.seed)
    model = VideoDeblurNet(config.model).to(device)
    optimiser = torch.optim.Adam(model.parameters(), lr=config.lr)
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(optimiser, config.steps, 1e-2 * config.lr)
    history = {"step": [], "train_loss": [], "val_psnr": [], "seconds": []}
    step, best, elapsed = 0, -np.inf, 0.0
    if resumed is not None:
        model.load_state_dict(resumed["model"])
        optimiser.load_state_dict(resumed["optimiser"])
        schedule.load_state_dict(resumed["schedule"])
        step, history, best = resumed["step"], resumed["history"], resumed["best"]
        rng.bit_generator.state = resumed["rng"]
        torch.set_rng_state(resumed["torch_rng"])
        elapsed = history["seconds"][-1] if history["seconds"] else 0.0
    videos = splits["train"]
    if config.model.blur_condition:  # first: every video then holds its descriptors third
        videos = with_blur_descriptors(videos)
    if config.model.wiener_input:
        videos = with_wiener_guides(videos, config.model)
    losses, started = [], time.perf_counter() - elapsed
    bar = tqdm(total=config.steps, initial=step, disable=not progress, desc="video deblur")
    first_step = step
    while step < config.steps:
        model.train()
        blurred, sharp, *extras = _sample_clips(videos, config, rng)
        parts = {"guides" if part.ndim == 5 else "blur": part.to(device) for part in extras}
        restored, _ = model(blurred.to(device), **parts)
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
                "format": CHECKPOINT_FORMATS["video-deblur"],
                "model_config": config.model.as_dict(), "model": model.state_dict(),
                "step": step, "history": history, **settings, "val_psnr": psnr_db,
            }  # fmt: skip
            if psnr_db > best:
                best = psnr_db
                save_checkpoint(out_dir / "best.pt", payload)
            save_checkpoint(out_dir / "last.pt", {
                **payload, "optimiser": optimiser.state_dict(), "schedule": schedule.state_dict(),
                "best": best, "rng": rng.bit_generator.state, "torch_rng": torch.get_rng_state(),
            })  # fmt: skip
            write_history(out_dir, history)  # beside last.pt: kept when interrupted
            if stop_after is not None and step - first_step >= stop_after:
                break
    bar.close()
    write_history(out_dir, history)
    return history
