"""Camera pose regression (Sec. III.B): a CNN encoder per frame → a recurrent head → pose.

The encoder is a ResNet written here, with torchvision's module names (``conv1``, ``bn1``,
``layer1``…``layer4``, blocks with ``conv1/bn1/conv2/bn2/downsample``), so ImageNet weights of
torchvision's resnet18/34, saved by the user to a local file, load with
:func:`load_encoder_weights` (nothing is ever downloaded). The head is an LSTM (the paper's
choice), a bidirectional LSTM, a GRU, or none (each frame alone: the PoseNet-style baseline).
Output: position (3, metres, camera-to-world) and a unit quaternion (w, x, y, z) with w >= 0.
"""

from __future__ import annotations

import os
from dataclasses import asdict, dataclass
from pathlib import Path

import torch
import torch.nn.functional as F
from torch import nn

#: Encoder shapes: (blocks per stage, widths per stage).
ENCODERS = {
    "small": ((1, 1, 1, 1), (16, 32, 64, 128)),
    "resnet18": ((2, 2, 2, 2), (64, 128, 256, 512)),
    "resnet34": ((3, 4, 6, 3), (64, 128, 256, 512)),
}
HEADS = ("lstm", "bilstm", "gru", "none")


@dataclass(frozen=True)
class PoseConfig:
    """Architecture of :class:`PoseRegressor`."""

    encoder: str = "small"
    head: str = "lstm"
    hidden: int = 128
    dropout: float = 0.6

    def __post_init__(self) -> None:
        if self.encoder not in ENCODERS:
            raise ValueError(f"encoder must be one of {sorted(ENCODERS)}, got {self.encoder!r}")
        if self.head not in HEADS:
            raise ValueError(f"head must be one of {HEADS}, got {self.head!r}")

    def as_dict(self) -> dict:
        """Plain dict (stored in checkpoints)."""
        return asdict(self)


class BasicBlock(nn.Module):
    """ResNet basic block (two 3x3 convolutions with batch norm, identity or 1x1 shortcut)."""

    def __init__(self, inputs: int, outputs: int, stride: int) -> None:
        super().__init__()
        self.conv1 = nn.Conv2d(inputs, outputs, 3, stride, 1, bias=False)
        self.bn1 = nn.BatchNorm2d(outputs)
        self.conv2 = nn.Conv2d(outputs, outputs, 3, 1, 1, bias=False)
        self.bn2 = nn.BatchNorm2d(outputs)
        self.downsample = None
        if stride != 1 or inputs != outputs:
            self.downsample = nn.Sequential(
                nn.Conv2d(inputs, outputs, 1, stride, bias=False), nn.BatchNorm2d(outputs)
            )

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        shortcut = x if self.downsample is None else self.downsample(x)
        out = F.relu(self.bn1(self.conv1(x)))
        return F.relu(self.bn2(self.conv2(out)) + shortcut)


class ResNetEncoder(nn.Module):
    """ResNet trunk: 7x7/2 convolution, 3x3/2 max pool, four stages, global average pool."""

    def __init__(self, name: str = "small") -> None:
        super().__init__()
        blocks, widths = ENCODERS[name]
        self.conv1 = nn.Conv2d(3, widths[0], 7, 2, 3, bias=False)
        self.bn1 = nn.BatchNorm2d(widths[0])
        self.maxpool = nn.MaxPool2d(3, 2, 1)
        inputs = widths[0]
        for index, (count, width) in enumerate(zip(blocks, widths, strict=True)):
            stride = 1 if index == 0 else 2
            layer = [BasicBlock(inputs, width, stride)]
            layer += [BasicBlock(width, width, 1) for _ in range(count - 1)]
            setattr(self, f"layer{index + 1}", nn.Sequential(*layer))
            inputs = width
        self.features = inputs

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        x = self.maxpool(F.relu(self.bn1(self.conv1(x))))
        x = self.layer4(self.layer3(self.layer2(self.layer1(x))))
        return x.mean(dim=(2, 3))


def load_encoder_weights(encoder: ResNetEncoder, path: str | os.PathLike) -> list[str]:
    """Load ImageNet weights from a local state-dict file (e.g. torchvision's resnet34, saved
    with ``torch.save(model.state_dict(), path)``); the classifier (``fc.*``) is skipped.
    Returns the encoder keys the file did not provide; ValueError naming the file when it is
    missing, not a state dict of tensors, or of another shape."""
    if not Path(path).is_file():
        raise ValueError(f"{path}: encoder weights file is missing")
    try:
        state = torch.load(path, map_location="cpu", weights_only=True)
    except Exception:  # torch raises several types for damaged, foreign or pickled files
        raise ValueError(f"{path}: not a state dict of tensors (damaged, or it holds other "
                         "objects)") from None  # fmt: skip
    if not isinstance(state, dict) or not all(isinstance(v, torch.Tensor) for v in state.values()):
        raise ValueError(f"{path}: not a state dict of tensors")
    state = {k: v for k, v in state.items() if not k.startswith("fc.")}
    own = encoder.state_dict()
    wrong = [k for k, v in state.items() if k in own and own[k].shape != v.shape]
    if wrong:
        raise ValueError(f"{path}: weights do not fit this encoder (e.g. {wrong[0]})")
    result = encoder.load_state_dict(state, strict=False)
    return list(result.missing_keys)


class PoseRegressor(nn.Module):
    """CNN features per frame → recurrent head → position + unit quaternion (w >= 0)."""

    def __init__(self, config: PoseConfig | None = None) -> None:
        super().__init__()
        self.config = config = config or PoseConfig()
        self.encoder = ResNetEncoder(config.encoder)
        features = self.encoder.features
        self.dropout = nn.Dropout(config.dropout)
        if config.head == "none":
            self.recurrent = None
            out = features
        else:
            kind = nn.GRU if config.head == "gru" else nn.LSTM
            self.recurrent = kind(features, config.hidden, batch_first=True,
                                  bidirectional=config.head == "bilstm")  # fmt: skip
            out = config.hidden * (2 if config.head == "bilstm" else 1)
        self.position = nn.Linear(out, 3)
        self.rotation = nn.Linear(out, 4)

    def forward(self, frames: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """frames (N, T, 3, H, W) in [-1, 1] → position (N, T, 3), quaternion (N, T, 4)."""
        if frames.ndim != 5 or frames.shape[2] != 3:
            raise ValueError(f"frames must be (N, T, 3, H, W), got {tuple(frames.shape)}")
        n, t = frames.shape[:2]
        features = self.encoder(frames.flatten(0, 1)).unflatten(0, (n, t))
        if self.recurrent is not None:
            features, _ = self.recurrent(features)
        features = self.dropout(features)
        quaternion = F.normalize(self.rotation(features), dim=-1)
        quaternion = quaternion * torch.where(quaternion[..., :1] < 0, -1.0, 1.0)
        return self.position(features), quaternion


def pose_loss(
    position: torch.Tensor,
    quaternion: torch.Tensor,
    true_position: torch.Tensor,
    true_quaternion: torch.Tensor,
    beta: float = 0.8,
) -> torch.Tensor:
    """Eq. 14: ||c - c^||_2 + beta ||q - q^ / ||q^|| ||_2, averaged over frames. The paper's
    beta is 0.8. Both quaternions are in the w >= 0 hemisphere, so q and -q do not differ."""
    unit = F.normalize(quaternion, dim=-1)
    return ((position - true_position).norm(dim=-1)
            + beta * (unit - true_quaternion).norm(dim=-1)).mean()  # fmt: skip


class LearnedWeighting(nn.Module):
    """The learnable loss weighting of PoseNet/MapNet/AtLoc:
    exp(-s_x) ||t - t^|| + s_x + exp(-s_q) ||q - q^|| + s_q, initial s_x = 0, s_q = -3."""

    def __init__(self, s_x: float = 0.0, s_q: float = -3.0) -> None:
        super().__init__()
        self.s_x = nn.Parameter(torch.tensor(s_x))
        self.s_q = nn.Parameter(torch.tensor(s_q))

    def forward(self, position, quaternion, true_position, true_quaternion) -> torch.Tensor:
        """The weighted loss, averaged over frames."""
        position_error = (position - true_position).norm(dim=-1).mean()
        rotation_error = (F.normalize(quaternion, dim=-1) - true_quaternion).norm(dim=-1).mean()
        return (torch.exp(-self.s_x) * position_error + self.s_x
                + torch.exp(-self.s_q) * rotation_error + self.s_q)  # fmt: skip
