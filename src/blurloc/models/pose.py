"""Camera pose regression (Sec. III.B): a CNN encoder per frame → a recurrent head → pose.

The encoder is a ResNet written here, with torchvision's module names (``conv1``, ``bn1``,
``layer1``…``layer4``, blocks with ``conv1/bn1/conv2/bn2/downsample``), so ImageNet weights of
torchvision's resnet18/34, saved by the user to a local file, load with
:func:`load_encoder_weights` (nothing is ever downloaded). It is written here rather than taken
from torchvision because torchvision's wheels for this torch are built against CUDA torch and do
not import beside the CPU build, and because the ``"small"`` encoder (widths 16-128) is not a
width torchvision's basic-block ResNet offers. The ``"efficientnet_lite0"`` encoder
(:mod:`.efficientnet`) is the one whose ImageNet weights install with the package (``pretrained``
loads them when the regressor is built). The head is an LSTM (the paper's
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

from .efficientnet import EfficientNetLite0, load_imagenet_weights

#: Encoder shapes: (blocks per stage, widths per stage).
ENCODERS = {
    "small": ((1, 1, 1, 1), (16, 32, 64, 128)),
    "resnet18": ((2, 2, 2, 2), (64, 128, 256, 512)),
    "resnet34": ((3, 4, 6, 3), (64, 128, 256, 512)),
}
#: Encoders of :mod:`.efficientnet`, whose ImageNet weights install with the package.
PRETRAINABLE_ENCODERS = ("efficientnet_lite0",)
HEADS = ("lstm", "bilstm", "gru", "none")


@dataclass(frozen=True)
class PoseConfig:
    """Architecture of :class:`PoseRegressor`.

    ``pretrained`` starts the encoder from ImageNet weights that install with the package
    (only encoders of :data:`PRETRAINABLE_ENCODERS`); otherwise it starts at random.
    """

    encoder: str = "small"
    head: str = "lstm"
    hidden: int = 128
    dropout: float = 0.6
    pretrained: bool = False

    def __post_init__(self) -> None:
        known = sorted(ENCODERS) + list(PRETRAINABLE_ENCODERS)
        if self.encoder not in known:
            raise ValueError(f"encoder must be one of {known}, got {self.encoder!r}")
        if self.pretrained and self.encoder not in PRETRAINABLE_ENCODERS:
            raise ValueError(f"pretrained weights install only for {PRETRAINABLE_ENCODERS}, "
                             f"not for encoder {self.encoder!r}")  # fmt: skip
        if self.head not in HEADS:
            raise ValueError(f"head must be one of {HEADS}, got {self.head!r}")

    def as_dict(self) -> dict:
        """The settings as a plain dict (stored in checkpoints).

        Returns
        -------
        dict
            ``encoder``, ``head``, ``hidden``, ``dropout`` and ``pretrained``.
        """
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
        r"""The block's output for a feature map.

        .. math::

            y = \mathrm{ReLU}\bigl(\mathrm{BN}(W_2 * \mathrm{ReLU}(\mathrm{BN}(W_1 * x)))
            + \mathrm{shortcut}(x)\bigr)

        Parameters
        ----------
        x : torch.Tensor
            (N, C_in, H, W).

        Returns
        -------
        torch.Tensor
            (N, C_out, H / stride, W / stride).

        References
        ----------
        He, Zhang, Ren and Sun, "Deep residual learning for image recognition", CVPR 2016.
        The paper's Section III.B (the CNN that extracts each frame's features).
        """
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
        r"""One feature vector per image: the ResNet trunk, then global average pooling.

        .. math::

            \phi(I) = \frac{1}{hw} \sum_{i, j} \mathrm{layer4}(\cdots \mathrm{layer1}(
            \mathrm{maxpool}(\mathrm{ReLU}(\mathrm{BN}(W * I)))))_{:, i, j}

        Parameters
        ----------
        x : torch.Tensor
            (N, 3, H, W) images in [-1, 1].

        Returns
        -------
        torch.Tensor
            (N, features).

        References
        ----------
        He, Zhang, Ren and Sun, "Deep residual learning for image recognition", CVPR 2016.
        The paper's Section III.B (the CNN that extracts each frame's features).
        """
        x = self.maxpool(F.relu(self.bn1(self.conv1(x))))
        x = self.layer4(self.layer3(self.layer2(self.layer1(x))))
        return x.mean(dim=(2, 3))


def load_encoder_weights(encoder: ResNetEncoder, path: str | os.PathLike) -> list[str]:
    """Load ImageNet weights into the encoder from a local state-dict file.

    The file is e.g. torchvision's resnet18/34 saved with ``torch.save(model.state_dict(),
    path)``; it is read with ``weights_only=True`` and its classifier (``fc.*``) is skipped, as
    the paper's ResNet34 is pre-trained on ImageNet (Section III.D) and the pose layers are not.

    Parameters
    ----------
    encoder : ResNetEncoder
        The encoder to fill (its module names are torchvision's).
    path : str or os.PathLike
        The state-dict file.

    Returns
    -------
    list of str
        The encoder keys the file did not provide.

    Raises
    ------
    ValueError
        Naming the file, when it is missing, not a state dict of tensors, or a weight's shape
        does not fit the encoder.

    References
    ----------
    He, Zhang, Ren and Sun, "Deep residual learning for image recognition", CVPR 2016.
    Deng et al., "ImageNet: a large-scale hierarchical image database", CVPR 2009.
    """
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
        if config.encoder == "efficientnet_lite0":
            self.encoder = EfficientNetLite0(classifier=False)
            if config.pretrained:
                load_imagenet_weights(self.encoder)
        else:
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
        r"""Camera poses of every frame of a batch of frame windows.

        .. math::

            \phi_t = \mathrm{CNN}(I_t), \quad h_t = \mathrm{RNN}(\phi_t, h_{t-1}), \quad
            \hat{C}_t = W_c h_t + b_c, \quad
            \hat{q}_t = \pm \frac{W_q h_t + b_q}{\lVert W_q h_t + b_q \rVert}

        with the sign chosen so that :math:`w \ge 0` (dropout on :math:`h_t` while training; without
        a recurrent head :math:`h_t = \phi_t`, PoseNet's single-frame regression).

        Parameters
        ----------
        frames : torch.Tensor
            (N, T, 3, H, W) in [-1, 1].

        Returns
        -------
        position : torch.Tensor
            (N, T, 3), metres, camera-to-world.
        quaternion : torch.Tensor
            (N, T, 4), unit, (w, x, y, z) with w >= 0.

        Raises
        ------
        ValueError
            If ``frames`` is not (N, T, 3, H, W).

        References
        ----------
        Kendall, Grimes and Cipolla, "PoseNet: a convolutional network for real-time 6-DOF camera
        relocalization", ICCV 2015.
        Walch, Hazirbas, Leal-Taixé, Sattler, Hilsenbeck and Cremers, "Image-based localization
        using LSTMs for structured feature correlation", ICCV 2017.
        Hochreiter and Schmidhuber, "Long short-term memory", Neural Computation 9(8), 1997.
        Cho et al., "Learning phrase representations using RNN encoder-decoder for statistical
        machine translation", EMNLP 2014 (GRU).
        The paper's Section III.B.
        """
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
    r"""The pose loss of eq. 14, averaged over frames.

    .. math::

        \mathrm{loss}(I) = \lVert \hat{C} - C_{gt} \rVert_2
        + \beta \left\lVert \frac{\hat{q}}{\lVert \hat{q} \rVert} - q_{gt} \right\rVert_2

    The paper prints eq. 14 without :math:`\beta` but names it, with the value 0.8; it normalises
    the ground-truth quaternion, which is unit already here, and this normalises the estimate.
    Both quaternions are in the w >= 0 hemisphere, so q and -q do not differ.

    Parameters
    ----------
    position, quaternion : torch.Tensor
        Estimated positions (..., 3), metres, and quaternions (..., 4).
    true_position, true_quaternion : torch.Tensor
        Reference positions (..., 3) and unit quaternions (..., 4), w >= 0.
    beta : float
        :math:`\beta`, the weight of the orientation term.

    Returns
    -------
    torch.Tensor
        The scalar loss.

    References
    ----------
    Kendall, Grimes and Cipolla, "PoseNet: a convolutional network for real-time 6-DOF camera
    relocalization", ICCV 2015. Eq. 14 of the paper.
    """
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
        r"""The loss with learnt weights of its position and orientation terms, frame mean.

        .. math::

            \mathcal{L} = e^{-s_x} \lVert \hat{t} - t \rVert_2 + s_x
            + e^{-s_q} \left\lVert \frac{\hat{q}}{\lVert \hat{q} \rVert} - q \right\rVert_2 + s_q

        Parameters
        ----------
        position, quaternion : torch.Tensor
            Estimated positions (..., 3) and quaternions (..., 4).
        true_position, true_quaternion : torch.Tensor
            Reference positions (..., 3) and unit quaternions (..., 4), w >= 0.

        Returns
        -------
        torch.Tensor
            The scalar loss (it includes :math:`s_x + s_q`, so it can be negative).

        References
        ----------
        Kendall and Cipolla, "Geometric loss functions for camera pose regression with deep
        learning", CVPR 2017. The paper's eq. 14 with its β learnt instead of fixed.
        The paper's Section III.B and eq. 14.
        """
        position_error = (position - true_position).norm(dim=-1).mean()
        rotation_error = (F.normalize(quaternion, dim=-1) - true_quaternion).norm(dim=-1).mean()
        return (torch.exp(-self.s_x) * position_error + self.s_x
                + torch.exp(-self.s_q) * rotation_error + self.s_q)  # fmt: skip
