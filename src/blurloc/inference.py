"""Using trained networks: load any checkpoint of the package safely, restore a video with the
recurrent deblurring network (eq. 8-11), alone or after deconvolving each frame by the video's own
motion, predict camera poses with the pose regressor.

Every checkpoint is read by :func:`blurloc.checkpoints.load_checkpoint` (tensors and plain data
only: a crafted file cannot run code); every failure is a ``ValueError`` naming the file.
"""

from __future__ import annotations

import functools
import os
import warnings
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from .checkpoints import load_checkpoint
from .data.sevenscenes import SequenceFrames
from .models.pose import PoseConfig, PoseRegressor
from .models.video_deblur import (
    VideoDeblurConfig,
    VideoDeblurNet,
    frames_from_tensor,
    to_tensor,
)
from .poses import PosePair
from .train.config import PoseTrainConfig
from .train.datasets import FrameCache, PoseSequenceDataset
from .video_wiener import BOUNDARY, LOCAL_GRID, deblur_video_motion

#: The trained video network shipped with the package, the paper's: it restores blurred frames
#: (docs/cli.md, "Command line", gives the command that makes it).
DEFAULT_CHECKPOINT = Path(__file__).with_name("weights") / "video_deblur.pt"
#: The same network trained on frames deconvolved by their video's own motion, shipped for
#: :class:`MotionNetworkRestorer` (``train-video-deblur --input motion``, docs/cli.md).
MOTION_CHECKPOINT = Path(__file__).with_name("weights") / "motion_network.pt"
#: Pixels restored at once by :func:`restore_frames` (bounds its memory for large frames).
CHUNK_PIXELS = 2**22


def _build(path: Path, model: torch.nn.Module, state: dict) -> None:
    """Load ``state`` into ``model``; ValueError naming ``path`` when it does not fit."""
    try:
        model.load_state_dict(state)
    except (RuntimeError, TypeError, KeyError) as error:
        raise ValueError(f"{path}: weights do not fit the stored configuration") from error


def load_video_deblur(path: str | os.PathLike, device: str = "cpu") -> VideoDeblurNet:
    """The video-deblurring network stored in a checkpoint, in eval mode.

    Parameters
    ----------
    path : str or os.PathLike
        A ``video-deblur`` checkpoint (e.g. :data:`DEFAULT_CHECKPOINT` or a run's ``best.pt``).
    device : str
        Device of the returned network.

    Returns
    -------
    VideoDeblurNet

    Raises
    ------
    ValueError
        Naming the file, for any problem (see :func:`~blurloc.checkpoints.load_checkpoint`).
    """
    path = Path(path)
    payload = load_checkpoint(path, "video-deblur", device)
    try:
        model = VideoDeblurNet(VideoDeblurConfig.from_stored(payload["model_config"]))
    except (KeyError, TypeError, ValueError) as error:
        raise ValueError(f"{path}: damaged network configuration ({error})") from None
    _build(path, model, payload["model"])
    return model.to(device).eval()


@dataclass(frozen=True)
class VideoRestorer:
    """The video network of a checkpoint as a picklable function of a whole video.

    Calling it restores one uint8 (T, H, W, 3) video (:func:`restore_sequence`, eq. 8-11). Only
    the checkpoint's path travels to a worker process; each process loads the network on its
    first call and keeps it (so :func:`blurloc.experiments.video.write_deblurred_root` can
    spread sequences over processes).

    Parameters
    ----------
    checkpoint : str or os.PathLike
        A ``video-deblur`` checkpoint (e.g. :data:`DEFAULT_CHECKPOINT`).
    device : str
        Where the network runs.
    """

    checkpoint: str | os.PathLike
    device: str = "cpu"

    def __call__(self, blurred: np.ndarray) -> np.ndarray:
        """``blurred`` (uint8 (T, H, W, 3), T >= 2) restored, same shape and dtype."""
        model = _loaded_video_deblur(str(self.checkpoint), self.device)
        return restore_sequence(model, blurred, self.device)


@dataclass(frozen=True)
class MotionNetworkRestorer:
    r"""Each frame deconvolved by its own motion in the video, then the recurrent network.

    .. math::

        L_t = \mathrm{RNN}\big(\tilde{x}_t, h_{t-1}\big)

    with :math:`\tilde{x}_t` frame t deconvolved with the kernels of the path its image took
    during the exposure (:func:`~blurloc.video_wiener.deblur_video_motion`: the blur removed)
    and the recurrent network of eq. 8-11 (state :math:`h_t`) run over the deconvolved video
    (:func:`restore_sequence`: it refines them and removes noise that the deconvolution
    amplified). A Wiener step before a learnt refinement, as in Dong, Roth and Schiele's deep
    Wiener deconvolution (NeurIPS 2020); the paper's network reads the blurred frames alone.
    Picklable, like :class:`VideoRestorer`.

    Parameters
    ----------
    checkpoint : str or os.PathLike
        A ``video-deblur`` checkpoint (default :data:`MOTION_CHECKPOINT`, trained on deconvolved
        frames; :data:`DEFAULT_CHECKPOINT`, trained on blurred ones, also runs).
    device : str
        Where the network runs.
    exposure_share : float or None
        Exposure time over frame interval (default None: read from the video,
        :func:`~blurloc.blur.video_motion.calibrate_exposure_share`).
    grid : int
        Kernels per side of each frame's grid (:func:`~blurloc.video_wiener.deblur_video_motion`).
    boundary : str
        ``"unknown"`` or ``"mirror"`` (:func:`~blurloc.video_wiener.deblur_video_motion`).

    Examples
    --------
    >>> from blurloc.experiments.photo_video import photo_video
    >>> import skimage
    >>> blurred, sharp = photo_video(skimage.data.coffee(), frames=4, step_px=2.0)
    >>> MotionNetworkRestorer()(blurred).shape
    (4, 120, 160, 3)
    """

    checkpoint: str | os.PathLike = MOTION_CHECKPOINT
    device: str = "cpu"
    exposure_share: float | None = None
    grid: int = LOCAL_GRID
    boundary: str = BOUNDARY

    def __call__(self, blurred: np.ndarray) -> np.ndarray:
        """``blurred`` (uint8 (T, H, W, 3), T >= 2) restored, same shape and dtype."""
        deconvolved = deblur_video_motion(blurred, self.exposure_share, grid=self.grid,
                                          boundary=self.boundary)  # fmt: skip
        return VideoRestorer(self.checkpoint, self.device)(deconvolved)


@functools.cache
def _loaded_video_deblur(path: str, device: str) -> VideoDeblurNet:
    """:func:`load_video_deblur`, once per process and checkpoint."""
    return load_video_deblur(path, device)


def load_pose_model(
    path: str | os.PathLike, device: str = "cpu", scene: str | None = None
) -> tuple[PoseRegressor, PoseTrainConfig]:
    """The pose regressor stored in a checkpoint (eval mode) and its training settings.

    Parameters
    ----------
    path : str or os.PathLike
        A ``pose`` checkpoint (a ``train-pose`` run's ``best.pt``).
    device : str
        Device of the returned network.
    scene : str, optional
        The scene the model is about to be used on: a warning names both scenes when the model
        was trained on another one.

    Returns
    -------
    model : PoseRegressor
    config : PoseTrainConfig
        The settings it was trained with (crop, window, frame kind...).

    Raises
    ------
    ValueError
        Naming the file, for any problem (see :func:`~blurloc.checkpoints.load_checkpoint`).
    """
    path = Path(path)
    payload = load_checkpoint(path, "pose", device)
    try:
        settings = dict(payload["train_config"])
        model_config = PoseConfig(**settings.pop("model"))
        config = PoseTrainConfig(**settings, model=model_config)
    except (KeyError, TypeError, ValueError) as error:
        raise ValueError(f"{path}: damaged training settings ({error})") from None
    model = PoseRegressor(model_config)
    _build(path, model, payload["model"])
    trained_on = payload.get("scene")
    if scene is not None and trained_on is not None and trained_on != scene:
        warnings.warn(f"{path}: a model trained on scene {trained_on!r}, used on scene "
                      f"{scene!r}", stacklevel=2)  # fmt: skip
    return model.to(device).eval(), config


def predict_poses(
    model: PoseRegressor,
    sequences: list[SequenceFrames],
    config: PoseTrainConfig,
    device: torch.device | str = "cpu",
    cache: FrameCache | None = None,
) -> PosePair:
    """The model's pose for every frame of ``sequences`` beside the reference pose.

    Recurrent heads see non-overlapping windows of ``config.window`` frames (the last window
    of a sequence ends at its last frame), centre crops of frames resized as in training.

    Parameters
    ----------
    model : PoseRegressor
    sequences : list of SequenceFrames
        Each at least ``config.window`` frames long.
    config : PoseTrainConfig
        The model's training settings (window, resize, crop, frame kind).
    device : torch.device or str
        Where the model runs.
    cache : FrameCache, optional
        Decoded frames shared with other readers of the same run.

    Returns
    -------
    PosePair
        Reference and estimated poses, in sequence order, then frame order.

    Raises
    ------
    ValueError
        If a sequence is shorter than the window (naming its folder).
    """
    window = config.window
    short = [s for s in sequences if len(s) < window]
    if short:
        raise ValueError(f"{short[0].folder}: {len(short[0])} frames, shorter than the window "
                         f"({window})")  # fmt: skip
    dataset = PoseSequenceDataset(sequences, window=window, stride=window, resize=config.resize,
                                  crop=config.crop, kinds=(config.image,), cache=cache)  # fmt: skip
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
                    predicted.setdefault(key, (item["position"][k].numpy(),
                                               item["quaternion"][k].numpy(),
                                               position[k].cpu().numpy(),
                                               quaternion[k].cpu().numpy()))  # fmt: skip
    keys = sorted(predicted)
    return PosePair(*(np.stack([predicted[k][c] for k in keys]) for c in range(4)))


def restore_frames(
    model: VideoDeblurNet,
    frames: Iterable[np.ndarray],
    device: torch.device | str = "cpu",
    chunk: int = 32,
) -> Iterator[np.ndarray]:
    """Deblur a stream of video frames in time order, carrying the recurrent state (eq. 8-11).

    Frames are read from ``frames`` and restored in chunks of at most ``chunk`` frames and
    :data:`CHUNK_PIXELS` pixels, so at most one chunk is held at a time, whatever the video's
    length.

    Parameters
    ----------
    model : VideoDeblurNet
    frames : iterable of numpy.ndarray
        uint8 (H, W, 3) frames of one size (e.g. :func:`blurloc.data.frames.read_frames`).
    device : torch.device or str
        Where the network runs.
    chunk : int
        Most frames restored at once.

    Yields
    ------
    numpy.ndarray
        The restored uint8 (H, W, 3) frames, one per input frame, in order.
    """
    device = torch.device(device)
    model = model.to(device).eval()
    state, pending, size = None, [], chunk
    with torch.inference_mode():
        for frame in frames:
            if not pending and state is None:
                size = max(1, min(chunk, CHUNK_PIXELS // (frame.shape[0] * frame.shape[1])))
            pending.append(frame)
            if len(pending) == size:
                output, state = model(to_tensor(np.stack(pending))[None].to(device), state)
                pending = []
                yield from frames_from_tensor(output[0])
        if pending:
            output, _ = model(to_tensor(np.stack(pending))[None].to(device), state)
            yield from frames_from_tensor(output[0])


def restore_sequence(
    model: VideoDeblurNet,
    blurred: np.ndarray,
    device: torch.device | str = "cpu",
    chunk: int = 32,
) -> np.ndarray:
    """Deblur one whole video held in memory (see :func:`restore_frames`).

    Parameters
    ----------
    model : VideoDeblurNet
    blurred : numpy.ndarray
        uint8 (T, H, W, 3), T >= 2.
    device : torch.device or str
        Where the network runs.
    chunk : int
        Most frames restored at once (the state is carried between chunks).

    Returns
    -------
    numpy.ndarray
        uint8 (T, H, W, 3).

    Raises
    ------
    ValueError
        If ``blurred`` is not a (T, H, W, 3) video of at least 2 frames.
    """
    if blurred.ndim != 4 or blurred.shape[-1] != 3:
        raise ValueError(f"a video must be uint8 frames (T, H, W, 3), got {blurred.shape}")
    if len(blurred) < 2:
        raise ValueError("a video needs at least 2 frames (got 1): use a single-image method")
    return np.stack(list(restore_frames(model, blurred, device, chunk)))
