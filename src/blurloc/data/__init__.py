"""Data: the 7-Scenes-layout reader, folders of video frames, and the synthetic stand-in that is
written in that layout. Torch-free."""

from ..errors import DataError
from .sevenscenes import (
    SequenceFrames,
    check_data,
    list_scenes,
    load_split,
    read_depth,
    read_image,
    read_pose,
    read_split,
    split_one_sequence,
    validation_root,
)

__all__ = [
    "DataError",
    "SequenceFrames",
    "check_data",
    "list_scenes",
    "load_split",
    "read_depth",
    "read_image",
    "read_pose",
    "read_split",
    "split_one_sequence",
    "validation_root",
]
