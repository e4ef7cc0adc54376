"""Folders of video frames: a 7-Scenes sequence (``frame-*.color.png``) or any folder of
images, listed in name order and read one frame at a time (never a whole video at once)."""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from pathlib import Path

import numpy as np

from ..errors import DataError
from ..files import image_files
from .sevenscenes import read_image


def list_frames(folder: str | os.PathLike) -> list[Path]:
    """The frame files of a video folder, in name order.

    Parameters
    ----------
    folder : str or os.PathLike
        A 7-Scenes sequence folder (its ``frame-*.color.png`` only) or a folder of images
        (:func:`blurloc.files.image_files`).

    Returns
    -------
    list of pathlib.Path
        At least two files.

    Raises
    ------
    ValueError
        Naming the folder: it is missing, or holds no frame or a single one.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"{folder}: no such folder")
    paths = image_files(folder)
    if not paths:
        raise ValueError(f"{folder}: no frames (frame-*.color.png or images) in this folder")
    if len(paths) < 2:
        raise ValueError(f"{folder}: one frame only; a video needs at least 2")
    return paths


def read_frames(paths: Iterable[os.PathLike]) -> Iterator[np.ndarray]:
    """Decode frames one at a time, checking that they share the first frame's size.

    Parameters
    ----------
    paths : iterable of os.PathLike
        Image files, in time order.

    Yields
    ------
    numpy.ndarray
        (H, W, 3) RGB uint8 frames.

    Raises
    ------
    ValueError
        Naming the file: it cannot be read, or its size differs from the first frame's.
    """
    first = None
    for path in paths:
        try:
            frame = read_image(path)
        except DataError as error:
            raise ValueError(str(error)) from error
        if first is None:
            first = (Path(path).name, frame.shape)
        elif frame.shape != first[1]:
            raise ValueError(f"{path}: frame size {frame.shape[1]}x{frame.shape[0]} differs "
                             f"from {first[1][1]}x{first[1][0]} of {first[0]}")  # fmt: skip
        yield frame
