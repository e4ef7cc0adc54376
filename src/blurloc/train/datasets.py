"""The torch Dataset of the pose trainer and the in-memory frame cache both trainers read from.

The 7-Scenes reader itself (:mod:`blurloc.data.sevenscenes`) is torch-free.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from pathlib import Path

import cv2
import numpy as np
import torch
from torch.utils.data import Dataset

from ..data.sevenscenes import SequenceFrames, read_image
from ..errors import DataError
from ..geometry import rotation_to_quaternion

#: Default bound of a :class:`FrameCache`, bytes (2 GiB: all 43,000 frames of 7-Scenes at the
#: pose trainer's 64 px short side take 0.7 GB).
CACHE_BYTES = 2 * 1024**3


class FrameCache:
    """Decoded and resized uint8 frames kept in memory, so each file is decoded once per run.

    The cache holds at most ``max_bytes`` of pixels; frames met once it is full are decoded
    again on every use (nothing is evicted, so what is cached never changes during a run).
    A sequence's poses are kept too (128 bytes a frame, not counted in the bound).

    Parameters
    ----------
    max_bytes : int
        Bound of the pixels held, bytes (default :data:`CACHE_BYTES`).
    """

    def __init__(self, max_bytes: int = CACHE_BYTES) -> None:
        if max_bytes < 0:
            raise ValueError(f"max_bytes must be >= 0, got {max_bytes}")
        self.max_bytes = max_bytes
        self.bytes = 0
        self._frames: dict[tuple[Path, int | None], np.ndarray] = {}
        self._poses: dict[tuple[Path, tuple[int, ...]], np.ndarray] = {}

    def __len__(self) -> int:
        return len(self._frames)

    def get(self, path: str | os.PathLike, short_side: int | None = None) -> np.ndarray:
        """The frame at ``path`` as RGB uint8, resized so its short side is ``short_side``.

        Parameters
        ----------
        path : str or os.PathLike
            Image file.
        short_side : int, optional
            Short side after resizing, px (area interpolation when shrinking); None keeps the
            size.

        Returns
        -------
        numpy.ndarray
            (H, W, 3) uint8; the cached array itself (do not modify it).
        """
        key = (Path(path), short_side)
        image = self._frames.get(key)
        if image is None:
            image = read_image(key[0])
            if short_side is not None:
                image = resize_short_side(image, short_side)
            if self.bytes + image.nbytes <= self.max_bytes:
                self._frames[key] = image
                self.bytes += image.nbytes
        return image

    def poses(self, sequence: SequenceFrames) -> np.ndarray:
        """The camera-to-world poses of ``sequence``, read and validated once.

        Parameters
        ----------
        sequence : SequenceFrames
            The frames whose poses are wanted.

        Returns
        -------
        numpy.ndarray
            (N, 4, 4) poses (:meth:`SequenceFrames.poses`); the cached array itself (do not
            modify it).
        """
        key = (sequence.folder, sequence.frame_ids)
        if key not in self._poses:
            self._poses[key] = sequence.poses()
        return self._poses[key]


def resize_short_side(image: np.ndarray, short_side: int) -> np.ndarray:
    """Resize ``image`` so that its short side is ``short_side`` px (aspect kept).

    Parameters
    ----------
    image : numpy.ndarray
        (H, W, ...) image.
    short_side : int
        Target short side, px.

    Returns
    -------
    numpy.ndarray
        The resized image (area interpolation when shrinking, bilinear when enlarging); the
        input itself when it already has that size.
    """
    height, width = image.shape[:2]
    scale = short_side / min(height, width)
    if scale == 1:
        return image
    size = (max(1, round(width * scale)), max(1, round(height * scale)))
    interpolation = cv2.INTER_AREA if scale < 1 else cv2.INTER_LINEAR
    return cv2.resize(image, size, interpolation=interpolation)


class PoseSequenceDataset(Dataset):
    """Windows of consecutive frames with their poses, preprocessed as in the paper (Sec. III.E).

    Frames are resized so the short side is ``resize`` px, cropped at the centre or at a random
    place shared by the whole window, and mapped to [-1, 1]. Each frame is decoded and resized
    once, into ``cache``.

    Parameters
    ----------
    sequences : sequence of SequenceFrames
        The sequences windows are cut from (each at least ``window`` frames long).
    window : int
        Frames per item, T.
    stride : int
        Frames between the starts of consecutive windows inside a sequence.
    resize : int
        Short side after resizing, px.
    crop : int or (int, int) or None
        Square crop side, or (height, width), px; None keeps the resized frame.
    random_crop : bool
        Crop at a random place (torch's generator) instead of the centre.
    kinds : iterable of str
        Images returned: ``color``, and ``sharp`` on the stand-in.
    cache : FrameCache, optional
        Decoded frames shared with other readers of the same run (a new one when None).

    Raises
    ------
    DataError
        If no sequence is given or one is shorter than the window.

    Notes
    -----
    Each item is a dict of tensors: ``<kind>`` (T, 3, H, W) in [-1, 1], ``position`` (T, 3,
    metres), ``quaternion`` (T, 4; w, x, y, z with w >= 0), ``pose`` (T, 4, 4), and the
    ``sequence`` and ``frame`` (window start) indices.
    """

    def __init__(
        self,
        sequences: Sequence[SequenceFrames],
        window: int = 1,
        stride: int = 1,
        resize: int = 128,
        crop: int | tuple[int, int] | None = 112,
        random_crop: bool = False,
        kinds: Iterable[str] = ("color",),
        cache: FrameCache | None = None,
    ) -> None:
        if window < 1 or stride < 1:
            raise ValueError(f"window and stride must be >= 1, got {window} and {stride}")
        if not sequences:
            raise DataError("no sequences given")
        self.sequences = list(sequences)
        self.window, self.stride, self.resize = window, stride, resize
        self.crop = (crop, crop) if isinstance(crop, int) else crop
        self.random_crop = random_crop
        self.kinds = tuple(kinds)
        self.cache = cache if cache is not None else FrameCache()
        self._poses = [self.cache.poses(seq) for seq in self.sequences]
        self._quaternions = [rotation_to_quaternion(poses[:, :3, :3]) for poses in self._poses]
        self.index: list[tuple[int, int]] = []
        for s, seq in enumerate(self.sequences):
            if len(seq) < window:
                raise DataError(
                    f"{seq.folder}: {len(seq)} frames, shorter than the window ({window})"
                )
            self.index += [(s, start) for start in range(0, len(seq) - window + 1, stride)]

    def __len__(self) -> int:
        return len(self.index)

    def _image(self, path: Path) -> np.ndarray:
        return self.cache.get(path, self.resize)

    def _crop_box(self, height: int, width: int) -> tuple[int, int, int, int]:
        if self.crop is None:
            return 0, 0, height, width
        crop_h, crop_w = self.crop
        if crop_h > height or crop_w > width:
            raise ValueError(f"crop {self.crop} larger than the resized image {height}x{width}")
        if self.random_crop:
            top = int(torch.randint(0, height - crop_h + 1, ()))
            left = int(torch.randint(0, width - crop_w + 1, ()))
        else:
            top, left = (height - crop_h) // 2, (width - crop_w) // 2
        return top, left, crop_h, crop_w

    def __getitem__(self, item: int) -> dict[str, torch.Tensor]:
        s, start = self.index[item]
        sequence = self.sequences[s]
        frame_ids = sequence.frame_ids[start : start + self.window]
        out: dict[str, torch.Tensor] = {}
        box = None
        for kind in self.kinds:
            images = [self._image(sequence.path(i, kind)) for i in frame_ids]
            if box is None:
                box = self._crop_box(*images[0].shape[:2])
            top, left, h, w = box
            stack = np.stack([im[top : top + h, left : left + w] for im in images])
            tensor = torch.from_numpy(stack).permute(0, 3, 1, 2).float()
            out[kind] = tensor / 127.5 - 1.0
        poses = self._poses[s][start : start + self.window]
        out["pose"] = torch.from_numpy(poses).float()
        out["position"] = torch.from_numpy(poses[:, :3, 3]).float()
        quaternions = self._quaternions[s][start : start + self.window]
        out["quaternion"] = torch.from_numpy(quaternions).float()
        out["sequence"] = torch.tensor(s)
        out["frame"] = torch.tensor(start)
        return out
