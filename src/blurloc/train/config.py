"""Settings of the two trainers, checked on construction and stored in their checkpoints."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

from ..models.pose import PoseConfig
from ..models.video_deblur import VideoDeblurConfig

#: Intra-op CPU threads used while training: fixed, so that one seed gives the same numbers
#: whatever the machine (2: the reference machine's cores).
TRAIN_THREADS = 2


def _check_positive(config: object, names: tuple[str, ...]) -> None:
    """ValueError naming the command-line option of the first setting that is not > 0."""
    for name in names:
        value = getattr(config, name)
        if not value > 0:
            raise ValueError(f"--{name.replace('_', '-')} must be > 0, got {value}")
    if config.seed < 0:
        raise ValueError(f"--seed must be >= 0, got {config.seed}")


@dataclass
class VideoTrainConfig:
    """Settings of :func:`blurloc.train.video.train_video_deblur`.

    Defaults take about 3 minutes on 2 CPU cores. ``steps`` optimiser steps on ``batch`` clips
    of ``clip_frames`` frames cropped to ``crop`` px; Adam at ``lr`` with a cosine schedule;
    Charbonnier loss with ``charbonnier_eps``; a validation every ``validate_every`` steps;
    ``threads`` intra-op CPU threads (fixed for reproducible numbers); ``device`` ``auto``,
    ``cpu`` or ``cuda``.

    Raises
    ------
    ValueError
        On construction, naming the option, when a count or size is not positive.
    """

    steps: int = 1200
    batch: int = 8
    clip_frames: int = 5
    crop: int = 64
    lr: float = 2e-3
    charbonnier_eps: float = 1e-3
    validate_every: int = 300
    seed: int = 0
    threads: int = TRAIN_THREADS
    device: str = "auto"
    model: VideoDeblurConfig = field(default_factory=VideoDeblurConfig)

    def __post_init__(self) -> None:
        _check_positive(self, ("steps", "batch", "clip_frames", "crop", "lr", "charbonnier_eps",
                               "validate_every", "threads"))  # fmt: skip
        if self.clip_frames < 2:
            raise ValueError(f"--clip-frames must be >= 2 (a clip is a video), got "
                             f"{self.clip_frames}")  # fmt: skip

    def settings(self) -> dict:
        """The settings as plain data, as stored in checkpoints (device excluded: a run may
        resume on another device)."""
        return _plain(self)


@dataclass
class PoseTrainConfig:
    """Settings of :func:`blurloc.train.pose.train_pose`.

    The paper's: images resized to 256 and cropped to 224, Adam, lr 5e-5, weight decay 3e-4,
    50 epochs, batch 64, dropout 0.6, beta 0.8. CPU-scale defaults here (a 1000-frame scene in
    minutes on 2 cores): 64 px short side, 56 px crops, a small ResNet, lr 1e-3 (lr 5e-5 barely
    moves in 15 epochs) decayed per step by a cosine to 1 % of it, batch 16 windows of 4
    frames; weight decay, dropout and beta as in the paper. Training crops lie at a random place
    of the resized frame, shared by a window's frames (the paper's augmentation), or with
    ``fixed_crop`` at the centre, where the test crops lie: a random crop shifts the image as a
    turn of the camera would, while the pose it is trained towards stays. ``image`` is the frame
    kind read (``color``; ``sharp`` on the stand-in for the upper bound); ``threads`` intra-op
    CPU threads (fixed for reproducible numbers).

    The budget is fixed in optimiser steps, not in passes over the data: an epoch is
    ``windows_per_epoch`` windows drawn at random (without replacement until every window was
    drawn) from all windows of ``window`` frames starting every ``stride`` frames, so a
    1000-frame scene and a 7000-frame one cost the same (8 epochs of 512 windows: 256 steps,
    about 10 s on 2 cores). ``windows_per_epoch=None`` makes an epoch one pass over every
    window. The single-frame head (``model.head="none"``) takes ``window`` times as many single
    frames per epoch and per batch, so both heads make the same steps on the same number of
    frames.

    Raises
    ------
    ValueError
        On construction, naming the option, when a count or size is not positive or the crop
        exceeds the resized image.
    """

    resize: int = 64
    crop: int = 56
    window: int = 4
    stride: int = 1
    batch: int = 16
    epochs: int = 8
    windows_per_epoch: int | None = 512
    lr: float = 1e-3
    weight_decay: float = 3e-4
    beta: float = 0.8
    learned_weighting: bool = False
    fixed_crop: bool = False
    image: str = "color"
    seed: int = 0
    threads: int = TRAIN_THREADS
    device: str = "auto"
    model: PoseConfig = field(default_factory=PoseConfig)

    def __post_init__(self) -> None:
        _check_positive(self, ("resize", "crop", "window", "stride", "batch", "epochs", "lr",
                               "threads"))  # fmt: skip
        if self.windows_per_epoch is not None and self.windows_per_epoch < 1:
            raise ValueError(f"--windows-per-epoch must be > 0, got {self.windows_per_epoch}")
        if self.crop > self.resize:
            raise ValueError(f"--crop ({self.crop}) must not exceed --resize ({self.resize})")
        if self.weight_decay < 0 or self.beta < 0:
            raise ValueError("weight_decay and beta must be >= 0")

    def settings(self) -> dict:
        """The settings as plain data, as stored in checkpoints (device excluded: a run may
        resume on another device)."""
        return _plain(self)


def _plain(config: VideoTrainConfig | PoseTrainConfig) -> dict:
    settings = asdict(config)
    settings.pop("device")
    return settings
