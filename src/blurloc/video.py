"""Deblurring whole videos: the recurrent network over a sequence, evaluation per scene against
the stand-in's sharp frames, and deblurred copies of a root in the 7-Scenes layout (so the pose
stage reads them with the same reader)."""

from __future__ import annotations

import os
import shutil
from collections.abc import Callable
from pathlib import Path

import cv2
import numpy as np
import torch
from tqdm.auto import tqdm

from .data.sevenscenes import SPLIT_FILES, DataError, list_scenes, load_split, read_image
from .deconv import deblur_blind
from .images import IMAGE_SUFFIXES, as_float_image
from .metrics import psnr, ssim
from .models.video_deblur import VideoDeblurNet

#: The trained network shipped with the package (see README for the command that makes it).
DEFAULT_CHECKPOINT = Path(__file__).with_name("weights") / "video_deblur.pt"


def to_tensor(frames: np.ndarray) -> torch.Tensor:
    """uint8 frames (..., H, W, 3) → float tensor (..., 3, H, W) in [-1, 1]."""
    tensor = torch.from_numpy(np.ascontiguousarray(frames)).float().div_(127.5).sub_(1.0)
    return tensor.movedim(-1, -3)


def to_uint8(tensor: torch.Tensor) -> np.ndarray:
    """Float tensor (..., 3, H, W) in [-1, 1] → uint8 frames (..., H, W, 3)."""
    image = tensor.detach().float().movedim(-3, -1).add(1.0).mul(127.5).round().clamp(0, 255)
    return image.to(torch.uint8).cpu().numpy()


def restore_sequence(
    model: VideoDeblurNet,
    blurred: np.ndarray,
    device: torch.device | str = "cpu",
    chunk: int = 32,
) -> np.ndarray:
    """Deblur one video (uint8 (T, H, W, 3), T >= 2) in time order, carrying the recurrent
    state from chunk to chunk; returns uint8 frames of the same shape."""
    if blurred.ndim != 4 or blurred.shape[-1] != 3:
        raise ValueError(f"a video must be uint8 frames (T, H, W, 3), got {blurred.shape}")
    if len(blurred) < 2:
        raise ValueError("a video needs at least 2 frames (got 1): use a single-image method")
    device = torch.device(device)
    model = model.to(device).eval()
    state, restored = None, []
    with torch.inference_mode():
        for start in range(0, len(blurred), chunk):
            clip = to_tensor(blurred[start : start + chunk])[None].to(device)
            output, state = model(clip, state)
            restored.append(to_uint8(output[0]))
    return np.concatenate(restored)


def mean_frame_psnr(pairs: list[tuple[np.ndarray, np.ndarray]]) -> float:
    """Mean over all frames of the PSNR (eq. 6, data range 255) of each (video, sharp video)
    pair of uint8 (T, H, W, 3) arrays."""
    return float(np.mean([psnr(truth, frame, 255.0) for video, sharp in pairs
                          for frame, truth in zip(video, sharp, strict=True)]))  # fmt: skip


def read_frame_folder(folder: str | os.PathLike) -> tuple[list[Path], np.ndarray]:
    """The frames of a video folder in name order: a 7-Scenes sequence (``frame-*.color.png``)
    or any folder of images. All frames must share one size; ValueError names the culprit."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"{folder}: no such folder")
    paths = sorted(folder.glob("frame-*.color.png"))
    if not paths:
        paths = sorted(p for p in folder.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
    if not paths:
        raise ValueError(f"{folder}: no frames (frame-*.color.png or images) in this folder")
    frames = []
    for path in paths:
        try:
            frame = read_image(path)
        except DataError as error:
            raise ValueError(str(error)) from error
        if frames and frame.shape != frames[0].shape:
            raise ValueError(
                f"{path}: frame size {frame.shape[1]}x{frame.shape[0]} differs from "
                f"{frames[0].shape[1]}x{frames[0].shape[0]} of {paths[0].name}"
            )
        frames.append(frame)
    if len(frames) < 2:
        raise ValueError(f"{folder}: one frame only; a video needs at least 2")
    return paths, np.stack(frames)


def wiener_sequence(blurred: np.ndarray) -> np.ndarray:
    """Blind Wiener deblurring (issue 3) of every frame of a uint8 video, frame by frame."""
    return np.stack([deblur_blind(frame) for frame in blurred])


def evaluate_video_deblurring(
    root: str | os.PathLike,
    methods: dict[str, Callable[[np.ndarray], np.ndarray]],
    split: str = "test",
    progress: bool = False,
) -> list[dict]:
    """PSNR and SSIM (data range 1) of every frame restored by each method (a function of the
    whole uint8 sequence) against the stand-in's sharp frame. One row per frame and method."""
    rows = []
    sequences = [s for scene in list_scenes(root) for s in load_split(root, scene, split)]
    for sequence in tqdm(sequences, disable=not progress, desc=f"evaluate {split}"):
        blurred = np.stack([read_image(sequence.path(f, "color")) for f in sequence.frame_ids])
        sharp = [as_float_image(read_image(sequence.path(f, "sharp"))) for f in sequence.frame_ids]
        for name, method in methods.items():
            restored = method(blurred)
            for index, frame in enumerate(sequence.frame_ids):
                estimate = as_float_image(restored[index])
                rows.append({
                    "scene": sequence.scene, "sequence": sequence.number, "frame": frame,
                    "method": name, "psnr_db": psnr(sharp[index], estimate, 1.0),
                    "ssim": ssim(sharp[index], estimate, 1.0),
                })  # fmt: skip
    return rows


def write_deblurred_root(
    root: str | os.PathLike,
    out_root: str | os.PathLike,
    method: Callable[[np.ndarray], np.ndarray],
    progress: bool = False,
) -> Path:
    """Copy of a 7-Scenes-layout root with every colour frame replaced by ``method``'s output
    (a function of the whole uint8 sequence); poses, splits and stand-in sharp frames are
    carried over, so the pose stage reads it like the original."""
    root, out_root = Path(root), Path(out_root)
    sequences = [(scene, s) for scene in list_scenes(root) for split in SPLIT_FILES
                 for s in load_split(root, scene, split)]  # fmt: skip
    for scene in list_scenes(root):
        (out_root / scene).mkdir(parents=True, exist_ok=True)
        for name in SPLIT_FILES.values():
            shutil.copyfile(root / scene / name, out_root / scene / name)
    for scene, sequence in tqdm(sequences, disable=not progress, desc="write deblurred"):
        folder = out_root / scene / sequence.folder.name
        folder.mkdir(parents=True, exist_ok=True)
        blurred = np.stack([read_image(sequence.path(f, "color")) for f in sequence.frame_ids])
        restored = method(blurred)
        for index, frame in enumerate(sequence.frame_ids):
            target = folder / sequence.path(frame, "color").name
            cv2.imwrite(str(target), restored[index][..., ::-1])
            for kind in ("pose", "sharp"):
                source = sequence.path(frame, kind)
                if source.is_file():
                    shutil.copyfile(source, folder / source.name)
    return out_root
