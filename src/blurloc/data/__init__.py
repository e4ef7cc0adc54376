"""Data: the 7-Scenes-layout reader and the synthetic stand-in that is written in that layout."""

from .sevenscenes import (
    DataError,
    PoseSequenceDataset,
    SequenceFrames,
    check_data,
    list_scenes,
    load_split,
    read_depth,
    read_image,
    read_pose,
    read_split,
)

__all__ = [
    "DataError",
    "PoseSequenceDataset",
    "SequenceFrames",
    "check_data",
    "list_scenes",
    "load_split",
    "read_depth",
    "read_image",
    "read_pose",
    "read_split",
]
