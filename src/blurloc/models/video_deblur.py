"""Recurrent video deblurring (Sec. III.A.2, eq. 8-11), written for this package.

After the Recurrence-in-Recurrence network of Park et al. (2022), at CPU scale::

    f_t, h_t  = Recurrence(B_t, h_{t-1})                         (eq. 8)
    h~_t      = Recurrence~(h_t, h~_{t-1})                        (eq. 9)  auxiliary state
    f~_t      = w~_{t-1} * f~_{t-1} + w_t * f_t                   (eq. 10) adaptive blending
    L_t       = B_t + Rec(f_t, h_t, f~_t, h~_t)                   (eq. 11) residual output

The features live at quarter resolution (two stride-2 convolutions, for CPU speed; half
resolution with ``feature_stride=2``); the reconstructor upsamples by pixel shuffle (no
transposed convolution, so no checkerboard) and merges with shallow full-resolution features of
B_t (the detail a residual needs). The blending weights w_t and w~_{t-1} are per-pixel,
non-negative and sum to one (a softmax over two logits computed from the current and the
previous features). Flags switch off the auxiliary state, the blending or the recurrence itself
(then every frame is deblurred alone: the single-frame baseline). With ``align`` the recurrent
states follow the image before each frame: they are moved by the global translation of the
content between the previous and the current blurred frame, measured by phase correlation (no
parameters). With ``bounded_state`` (the default, and the shipped network's) the hidden and
auxiliary states pass through tanh, so that they stay within (-1, 1) however long the video;
without it nothing bounds them, and a network whose recurrence has become expansive in training
blows up on long videos. With ``wiener_input`` every frame is first deconvolved by the Wiener
filter (eq. 4) with its own blind line estimate (Section III.A.1) and a noise-aware NSR, and the
recurrent network refines the frame with that copy beside it as three more input channels (a
Wiener step before the learnt refinement). With ``blur_condition`` the network is told each
frame's blur as the package estimates it blind (Section III.A.1: length and angle of a line,
:func:`blur_descriptors`): a small perceptron turns the three numbers into a per-channel scale
and shift of the full-resolution and of the recurrent features (feature-wise modulation), so
that one network can apply a different restoration to each frame's blur.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np
import torch
import torch.nn.functional as F
from torch import nn

from ..blur import estimate_motion_blur
from ..deconv import deblur_blind
from ..stored import VIDEO_SWITCHES_ADDED, complete
from ..video_wiener import deblur_video_motion


@dataclass(frozen=True)
class VideoDeblurConfig:
    """Widths and switches of :class:`VideoDeblurNet`; ``feature_stride`` (4 or 2) is how much
    coarser than the frame the recurrent features are; ``align`` moves the recurrent states by
    the frame-to-frame translation (:func:`frame_translation`); ``bounded_state`` passes the
    hidden and auxiliary states (eq. 8-9) through tanh; ``wiener_input`` gives the network each
    frame's blind Wiener deconvolution (:func:`wiener_guides`) beside the frame, by eq. 4's
    constant NSR or, with ``wiener_gradient``, by the gradient regulariser
    (:func:`~blurloc.deconv.wiener_deconvolve`), or, with ``wiener_motion``, each frame
    deconvolved with the kernel of its own motion in the video (:func:`motion_guides`);
    ``blur_condition`` modulates the features by each frame's blind blur estimate
    (:func:`blur_descriptors`)."""

    channels: int = 32
    hidden: int = 24
    blocks: int = 4
    aux_state: bool = True
    blending: bool = True
    recurrent: bool = True
    feature_stride: int = 4
    align: bool = False
    bounded_state: bool = True
    wiener_input: bool = False
    blur_condition: bool = False
    wiener_gradient: bool = False
    wiener_motion: bool = False

    def __post_init__(self) -> None:
        if self.feature_stride not in (2, 4):
            raise ValueError(f"feature_stride must be 2 or 4, got {self.feature_stride}")
        if self.wiener_motion and not self.wiener_input:
            raise ValueError("wiener_motion chooses the Wiener copies the network reads: it "
                             "needs wiener_input")  # fmt: skip
        if self.wiener_motion and self.wiener_gradient:
            raise ValueError("wiener_motion and wiener_gradient choose different Wiener "
                             "copies: set one")  # fmt: skip

    def as_dict(self) -> dict:
        """The settings as a plain dict (stored in checkpoints).

        Returns
        -------
        dict
            Every field of the configuration.
        """
        return asdict(self)

    @classmethod
    def from_stored(cls, settings: Mapping[str, Any]) -> VideoDeblurConfig:
        """The configuration a checkpoint stored (:meth:`as_dict`).

        A switch added to the network after the checkpoint was made is absent from it and
        means off, whatever its default now (:data:`blurloc.stored.VIDEO_SWITCHES_ADDED`,
        the package's one rule for stored files: :mod:`blurloc.stored`).

        Parameters
        ----------
        settings : dict
            The stored settings.

        Returns
        -------
        VideoDeblurConfig

        Raises
        ------
        TypeError
            On a setting this network does not have.
        ValueError
            On a setting's value the network refuses (e.g. ``feature_stride``).

        References
        ----------
        The paper's eq. 8-11 (the parts the switches turn off).
        """
        return cls(**complete(settings, VIDEO_SWITCHES_ADDED))


class ResidualBlock(nn.Module):
    """conv-ReLU-conv with an identity shortcut."""

    def __init__(self, channels: int) -> None:
        super().__init__()
        self.conv1 = nn.Conv2d(channels, channels, 3, padding=1)
        self.conv2 = nn.Conv2d(channels, channels, 3, padding=1)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        r"""The block's output: the input plus a conv-ReLU-conv residual.

        .. math::

            y = x + W_2 * \mathrm{ReLU}(W_1 * x)

        Parameters
        ----------
        x : torch.Tensor
            (N, C, H, W).

        Returns
        -------
        torch.Tensor
            (N, C, H, W).

        References
        ----------
        He, Zhang, Ren and Sun, "Deep residual learning for image recognition", CVPR 2016.
        The paper's eq. 8-11 (the blocks of the recurrent cell).
        """
        return x + self.conv2(F.relu(self.conv1(x)))


def frame_translation(previous: torch.Tensor, current: torch.Tensor) -> torch.Tensor:
    r"""Global translation (dx, dy) in px of each frame against the previous one, by phase
    correlation: ``current(x) ≈ previous(x - shift)``.

    .. math::

        R = \frac{F\{c\}\, \overline{F\{p\}}}{|F\{c\}\, \overline{F\{p\}}|}, \qquad
        (\Delta x, \Delta y) = \arg\max_{x, y} F^{-1}\{R\}(x, y)

    The channel means of both frames, minus their means and Hann-windowed, are correlated in
    the Fourier domain with the magnitude normalised away (only the phase, which carries the
    shift, is kept); the correlation's peak is refined to a fraction of a pixel by a parabola
    through it and its two neighbours along each axis.

    Parameters
    ----------
    previous, current : torch.Tensor
        (N, C, H, W) frames.

    Returns
    -------
    torch.Tensor
        (N, 2) shifts (dx, dy), px, each within half the frame's size.

    References
    ----------
    Kuglin and Hines, "The phase correlation image alignment method", IEEE Conf. Cybernetics and
    Society 1975.
    The paper's Section III.A.2 (aligning the previous frame's state before eq. 8).
    """
    if previous.shape != current.shape or previous.ndim != 4:
        raise ValueError(f"frames must be two (N, C, H, W) tensors of one shape, got "
                         f"{tuple(previous.shape)} and {tuple(current.shape)}")  # fmt: skip
    height, width = current.shape[-2:]
    window = torch.outer(*(torch.hann_window(size, periodic=False, device=current.device)
                           for size in (height, width)))  # fmt: skip
    spectra = [torch.fft.rfft2((gray - gray.mean((-2, -1), keepdim=True)) * window)
               for gray in (previous.mean(1), current.mean(1))]  # fmt: skip
    cross = spectra[1] * spectra[0].conj()
    correlation = torch.fft.irfft2(cross / (cross.abs() + 1e-9), s=(height, width))
    peak = correlation.flatten(1).argmax(1)
    rows, columns = peak // width, peak % width
    shifts = []
    for index, size, step in ((columns, width, 1), (rows, height, width)):
        base = (rows * width + columns).unsqueeze(1)
        offsets = torch.stack([(index - 1) % size, index, (index + 1) % size], 1) - index[:, None]
        values = correlation.flatten(1).gather(1, base + offsets * step)
        left, middle, right = values.unbind(1)
        curvature = left - 2 * middle + right
        fraction = torch.where(curvature < 0, 0.5 * (left - right) / curvature.clamp(max=-1e-9),
                               torch.zeros_like(middle))  # fmt: skip
        whole = torch.where(index > size // 2, index - size, index).to(correlation.dtype)
        shifts.append(whole + fraction.clamp(-0.5, 0.5))
    return torch.stack(shifts, 1)


def shift_features(features: torch.Tensor, shift_px: torch.Tensor) -> torch.Tensor:
    r"""Move feature maps by a translation: ``out(x) = features(x - shift)``.

    .. math::

        \mathrm{out}(x, y) = \mathrm{features}(x - \Delta x,\; y - \Delta y)

    Parameters
    ----------
    features : torch.Tensor
        (N, C, h, w) maps.
    shift_px : torch.Tensor
        (N, 2) translation (dx, dy) of each map, in its own pixels (fractions allowed).

    Returns
    -------
    torch.Tensor
        (N, C, h, w), bilinearly interpolated; pixels moved in from outside repeat the border.

    References
    ----------
    Jaderberg, Simonyan, Zisserman and Kavukcuoglu, "Spatial transformer networks", NeurIPS
    2015 (differentiable bilinear resampling).
    The paper's Section III.A.2 (aligning the previous frame's state before eq. 8).
    """
    n, _, height, width = features.shape
    theta = features.new_zeros(n, 2, 3)
    theta[:, 0, 0] = theta[:, 1, 1] = 1.0
    theta[:, 0, 2] = -2.0 * shift_px[:, 0] / width
    theta[:, 1, 2] = -2.0 * shift_px[:, 1] / height
    grid = F.affine_grid(theta, list(features.shape), align_corners=False)
    return F.grid_sample(features, grid, padding_mode="border", align_corners=False)


def guide_regulariser(config: VideoDeblurConfig) -> str:
    """The regulariser of the Wiener copies a network reads (:func:`wiener_guides`):
    ``"gradient"`` with ``config.wiener_gradient``, else eq. 4's ``"constant"``."""
    return "gradient" if config.wiener_gradient else "constant"


def to_tensor(frames: np.ndarray) -> torch.Tensor:
    """uint8 frames (..., H, W, 3) as a float tensor (..., 3, H, W) in [-1, 1].

    Parameters
    ----------
    frames : numpy.ndarray
        uint8, channels last.

    Returns
    -------
    torch.Tensor
        float32, channels before height and width, ``frames / 127.5 - 1``.
    """
    tensor = torch.from_numpy(np.ascontiguousarray(frames)).float().div_(127.5).sub_(1.0)
    return tensor.movedim(-1, -3)


def frames_from_tensor(tensor: torch.Tensor) -> np.ndarray:
    """Float tensor (..., 3, H, W) in [-1, 1] as uint8 frames (..., H, W, 3) (rounded, clipped).

    Parameters
    ----------
    tensor : torch.Tensor
        Network output, any device.

    Returns
    -------
    numpy.ndarray
        uint8, channels last.
    """
    image = tensor.detach().float().movedim(-3, -1).add(1.0).mul(127.5).round().clamp(0, 255)
    return image.to(torch.uint8).cpu().numpy()


def network_guides(frames: torch.Tensor, config: VideoDeblurConfig) -> torch.Tensor:
    """The Wiener copies a network with ``wiener_input`` reads beside ``frames``: those of
    :func:`motion_guides` with ``config.wiener_motion``, else :func:`wiener_guides` by the
    regulariser of :func:`guide_regulariser`.

    Parameters
    ----------
    frames : torch.Tensor
        (N, T, 3, H, W) blurred frames in [-1, 1].
    config : VideoDeblurConfig
        The network's settings.

    Returns
    -------
    torch.Tensor
        (N, T, 3, H, W) in [-1, 1], on the device of ``frames``.
    """
    if config.wiener_motion:
        return motion_guides(frames)
    return wiener_guides(frames, guide_regulariser(config))


def motion_guides(frames: torch.Tensor) -> torch.Tensor:
    r"""Each video deconvolved with the kernels of its own motion between frames.

    .. math::

        W_t = F^{-1}\left\{ \frac{\overline{F\{c_t\}}}{|F\{c_t\}|^2 + \lambda_t |D(f)|^2}
        \, F\{B_t\} \right\}

    with :math:`c_t` the kernel of the path frame t's image took during its exposure, measured
    from the shifts between neighbouring frames (:func:`~blurloc.video_wiener.
    deblur_video_motion` with its defaults). A one-frame video has no motion to measure and is
    its own copy. Computed on the 8-bit frames (rounded from the input), without gradients.

    Parameters
    ----------
    frames : torch.Tensor
        (N, T, 3, H, W) blurred frames in [-1, 1].

    Returns
    -------
    torch.Tensor
        (N, T, 3, H, W) deconvolved frames in [-1, 1], on the device of ``frames``.

    References
    ----------
    Dong, Roth and Schiele, "Deep Wiener deconvolution: Wiener meets deep learning for image
    deblurring", NeurIPS 2020 (a Wiener step before a learnt refinement). Not in the paper,
    whose eq. 8-11 network reads the blurred frames alone.
    """
    with torch.no_grad():
        images = frames_from_tensor(frames)
        if images.shape[1] > 1:
            images = np.stack([deblur_video_motion(video) for video in images])
    return to_tensor(images).to(frames.device)


def wiener_guides(frames: torch.Tensor, regulariser: str = "constant") -> torch.Tensor:
    r"""Each frame deconvolved by the Wiener filter (eq. 4) with its own blind blur estimate.

    .. math::

        W_t = F^{-1}\left\{ \frac{\overline{F\{\hat{c}_t\}}}{|F\{\hat{c}_t\}|^2 +
        \mathrm{NSR}_t} \, F\{B_t\} \right\}

    with :math:`\hat{c}_t` the straight line of the frame's blind estimate (length and angle,
    :func:`~blurloc.blur.estimate_motion_blur`; 1 px, the identity, for a frame without blur)
    and :math:`\mathrm{NSR}_t` from the frame's noise level (:func:`~blurloc.deconv.estimate_nsr`),
    by :func:`~blurloc.deconv.deblur_blind` without its gate, with ``regulariser`` (eq. 4's
    constant NSR by default, the guides that networks stored before the choice existed were
    trained on; with ``"gradient"`` the NSR is :math:`\lambda |D(f)|^2`): every frame is
    deconvolved, and
    the network that reads the copy decides how far to trust it. Computed on the 8-bit frames
    (rounded from the input), without gradients.

    Parameters
    ----------
    frames : torch.Tensor
        (N, T, 3, H, W) blurred frames in [-1, 1]; H and W at least 16.
    regulariser : str
        ``"constant"`` (eq. 4) or ``"gradient"`` (:func:`~blurloc.deconv.wiener_deconvolve`).

    Returns
    -------
    torch.Tensor
        (N, T, 3, H, W) deconvolved frames in [-1, 1], on the device of ``frames``.

    References
    ----------
    Dong, Roth and Schiele, "Deep Wiener deconvolution: Wiener meets deep learning for image
    deblurring", NeurIPS 2020 (a Wiener step before a learnt refinement). The paper's Section
    III.A.1 and eq. 4.
    """
    with torch.no_grad():
        images = frames_from_tensor(frames)
        restored = np.stack([deblur_blind(image, threshold=0.0, gated=False,
                                          regulariser=regulariser)
                             for image in images.reshape(-1, *images.shape[2:])])  # fmt: skip
    return to_tensor(restored.reshape(images.shape)).to(frames.device)


#: Number of values that describe one frame's blur (:func:`blur_descriptor`).
DESCRIPTOR_SIZE = 3


def blur_descriptor(length_px: float, angle_deg: float) -> np.ndarray:
    r"""Three numbers that describe a line blur, as :class:`VideoDeblurNet` reads it.

    .. math::

        d = \left(\frac{L}{8},\; w \cos 2\theta,\; w \sin 2\theta\right), \qquad
        w = \frac{L}{L + 2}

    The angle enters doubled, since a line at :math:`\theta` and at :math:`\theta + 180°` is
    the same blur, and weighted by :math:`w`, which fades the direction of a short blur (whose
    angle an estimate hardly knows) towards none. A mirror image of the frame (left-right or
    up-down) negates the third value and keeps the others.

    Parameters
    ----------
    length_px : float
        Blur length L, px (>= 0).
    angle_deg : float
        Blur direction :math:`\theta`, degrees counter-clockwise from the image's horizontal
        axis (the conventions of :mod:`blurloc.blur.estimation`).

    Returns
    -------
    numpy.ndarray
        float32 (3,).

    Raises
    ------
    ValueError
        If the length is negative or either value is not finite.

    References
    ----------
    Perez, Strub, de Vries, Dumoulin and Courville, "FiLM: visual reasoning with a general
    conditioning layer", AAAI 2018 (a network conditioned on a few numbers).
    The paper's Section III.A.1 (the line blur's length and angle).
    """
    if not (np.isfinite(length_px) and np.isfinite(angle_deg)) or length_px < 0:
        raise ValueError(f"a blur needs a finite length >= 0 and a finite angle, got "
                         f"{length_px} px at {angle_deg} degrees")  # fmt: skip
    weight = length_px / (length_px + 2.0)
    doubled = np.radians(2.0 * angle_deg)
    return np.float32([length_px / 8.0, weight * np.cos(doubled), weight * np.sin(doubled)])


def blur_descriptors(frames: torch.Tensor) -> torch.Tensor:
    r"""Each frame's blind blur estimate as the network reads it (:func:`blur_descriptor`).

    .. math::

        d_t = \mathrm{descriptor}(\hat{L}_t, \hat{\theta}_t)

    with :math:`(\hat{L}_t, \hat{\theta}_t)` the line that
    :func:`~blurloc.blur.estimate_motion_blur` finds in frame :math:`B_t` (no detection step:
    a sharp frame's estimate is short, which the descriptor carries). Computed on the 8-bit
    frames (rounded from the input), without gradients.

    Parameters
    ----------
    frames : torch.Tensor
        (N, T, 3, H, W) blurred frames in [-1, 1]; H and W at least 16.

    Returns
    -------
    torch.Tensor
        (N, T, 3) float32 descriptors, on the device of ``frames``.

    References
    ----------
    The paper's Section III.A.1 (blind estimation of the blur's length and angle).
    """
    with torch.no_grad():
        images = frames.detach().float().movedim(-3, -1).add(1.0).mul(127.5).round().clamp(0, 255)
        images = images.to(torch.uint8).cpu().numpy()
        estimates = (estimate_motion_blur(image) for image in images.reshape(-1, *images.shape[2:]))
        values = np.stack([blur_descriptor(e.length_px, e.angle_deg) for e in estimates])
    return torch.from_numpy(values.reshape(*images.shape[:2], DESCRIPTOR_SIZE)).to(frames.device)


class VideoDeblurNet(nn.Module):
    """The recurrent deblurring network; frames in [-1, 1], (N, T, 3, H, W) → same shape."""

    def __init__(self, config: VideoDeblurConfig | None = None) -> None:
        super().__init__()
        self.config = config = config or VideoDeblurConfig()
        self.stride = config.feature_stride
        c, h = config.channels, config.hidden
        s = c // 2
        inputs = 6 if config.wiener_input else 3
        self.encode_full = nn.Sequential(nn.Conv2d(inputs, s, 3, padding=1), nn.ReLU())
        self.encode = nn.Sequential(
            nn.Conv2d(s, s, 3, stride=2, padding=1), nn.ReLU(),
            nn.Conv2d(s, c, 3, stride=self.stride // 2, padding=1), nn.ReLU(),
        )  # fmt: skip
        # eq. 8: features of B_t merged with the previous hidden state
        self.recur = nn.Sequential(
            nn.Conv2d(c + h, c, 3, padding=1), nn.ReLU(),
            *[ResidualBlock(c) for _ in range(config.blocks)],
        )  # fmt: skip
        self.to_hidden = nn.Conv2d(c, h, 3, padding=1)
        if config.aux_state:  # eq. 9
            self.aux = nn.Sequential(
                nn.Conv2d(2 * h, h, 3, padding=1), nn.ReLU(),
                nn.Conv2d(h, h, 3, padding=1),
            )  # fmt: skip
        if config.blending:  # eq. 10: two logits per pixel from current and previous features
            self.attend = nn.Sequential(
                nn.Conv2d(2 * c, c // 2, 3, padding=1), nn.ReLU(),
                nn.Conv2d(c // 2, 2, 3, padding=1),
            )  # fmt: skip
        merged = c + h + (c if config.blending else 0) + (h if config.aux_state else 0)
        self.reconstruct = nn.Sequential(  # eq. 11, back to full resolution by pixel shuffle
            nn.Conv2d(merged, c, 3, padding=1), nn.ReLU(),
            ResidualBlock(c),
            nn.Conv2d(c, s * self.stride**2, 3, padding=1),
            nn.PixelShuffle(self.stride),
        )  # fmt: skip
        self.output = nn.Sequential(  # merged with full-resolution features of B_t
            nn.Conv2d(2 * s, s, 3, padding=1), nn.ReLU(),
            nn.Conv2d(s, 3, 3, padding=1),
        )  # fmt: skip
        if config.blur_condition:  # per-channel scale and shift of the features from the blur
            self.modulate = nn.Sequential(
                nn.Linear(DESCRIPTOR_SIZE, c), nn.ReLU(), nn.Linear(c, 2 * (s + c)),
            )  # fmt: skip
            nn.init.zeros_(self.modulate[-1].weight)  # starts as no modulation
            nn.init.zeros_(self.modulate[-1].bias)
        self.last_attention: list[torch.Tensor] = []

    def forward(
        self,
        frames: torch.Tensor,
        state: tuple | None = None,
        keep_attention: bool = False,
        guides: torch.Tensor | None = None,
        blur: torch.Tensor | None = None,
    ) -> tuple[torch.Tensor, tuple]:
        r"""Deblur a clip frame by frame in time order (eq. 8-11).

        .. math::

            f_t, h_t = \mathrm{Recurrence}(B_t, h_{t-1}), \qquad
            \tilde{h}_t = \widetilde{\mathrm{Recurrence}}(h_t, \tilde{h}_{t-1}),

            \tilde{f}_t = \tilde{w}_{t-1} \tilde{f}_{t-1} + w_t f_t, \quad
            (w_t, \tilde{w}_{t-1}) = \mathrm{softmax}(\mathrm{Attend}(f_t, \tilde{f}_{t-1})),

            L_t = B_t + \mathrm{Reconstructor}(f_t, h_t, \tilde{f}_t, \tilde{h}_t)

        (with ``wiener_input`` the encoder reads :math:`B_t` and its Wiener copy :math:`W_t`
        (:func:`network_guides`) stacked as six channels; with ``blur_condition`` the
        full-resolution features and the features entering the recurrence are each scaled and
        shifted per channel, :math:`f \mapsto (1 + \gamma_t) f + \beta_t`, with
        :math:`(\gamma_t, \beta_t)` = MLP(:math:`d_t`) of the frame's blur descriptor
        (:func:`blur_descriptors`); with ``bounded_state``, :math:`h_t` and
        :math:`\tilde{h}_t` pass through tanh; switched-off parts drop out of the sums). Any H, W:
        frames are padded by replication to a multiple of the feature stride and cropped back.

        Parameters
        ----------
        frames : torch.Tensor
            (N, T, 3, H, W) blurred frames :math:`B_t` in [-1, 1].
        state : tuple, optional
            The state returned with the previous clip of the same videos (h, h~, f~ and the last
            frame); None starts a video.
        keep_attention : bool
            Keep the blending weights :math:`w_t` of eq. 10 in ``last_attention``.
        guides : torch.Tensor, optional
            (N, T, 3, H, W) Wiener copies of ``frames`` for a network with ``wiener_input``
            (e.g. computed once on whole frames before cropping them); default
            :func:`network_guides` of ``frames`` (with ``wiener_motion``, the motion of this
            clip alone: pass copies made on the whole video where clips are cut from one).
            Ignored without ``wiener_input``.
        blur : torch.Tensor, optional
            (N, T, 3) blur descriptors of ``frames`` for a network with ``blur_condition``
            (e.g. estimated once on whole frames before cropping them, mirrored with them);
            default :func:`blur_descriptors` of ``frames``. Ignored without
            ``blur_condition``.

        Returns
        -------
        restored : torch.Tensor
            (N, T, 3, H, W) restored frames :math:`L_t`.
        state : tuple
            The recurrent state to pass with the next clip.

        Raises
        ------
        ValueError
            If ``frames`` is not (N, T, 3, H, W), ``guides`` is not of its shape, or ``blur``
            is not (N, T, 3).

        References
        ----------
        Park, Nah and Lee, "Recurrence-in-recurrence networks for video deblurring", BMVC 2022.
        Nah, Son and Lee, "Recurrent neural networks with intra-frame iterations for video
        deblurring", CVPR 2019.
        Shi et al., "Real-time single image and video super-resolution using an efficient
        sub-pixel convolutional neural network", CVPR 2016 (pixel shuffle).
        The paper's eq. 8-11.
        """
        if frames.ndim != 5 or frames.shape[2] != 3:
            raise ValueError(f"frames must be (N, T, 3, H, W), got {tuple(frames.shape)}")
        n, t, _, height, width = frames.shape
        pad_h, pad_w = (-height) % self.stride, (-width) % self.stride
        config = self.config
        stacked = frames
        if config.wiener_input:
            if guides is None:
                guides = network_guides(frames, config)
            if guides.shape != frames.shape:
                raise ValueError(f"guides must have the frames' shape {tuple(frames.shape)}, "
                                 f"got {tuple(guides.shape)}")  # fmt: skip
            stacked = torch.cat([frames, guides.to(frames)], 2)
        if config.blur_condition:
            blur = blur_descriptors(frames) if blur is None else blur
            if tuple(blur.shape) != (n, t, DESCRIPTOR_SIZE):
                raise ValueError(f"blur must be (N, T, {DESCRIPTOR_SIZE}), got "
                                 f"{tuple(blur.shape)}")  # fmt: skip
            scale, shift = self.modulate(blur.to(frames)).chunk(2, dim=-1)
        padded = F.pad(stacked.flatten(0, 1), (0, pad_w, 0, pad_h), mode="replicate")
        padded = padded.unflatten(0, (n, t))
        hidden, aux, blended, previous = state if state is not None else (None,) * 4
        outputs, self.last_attention = [], []
        for step in range(t):
            inputs = padded[:, step]
            blurred = inputs[:, :3]
            if config.align and config.recurrent and previous is not None and hidden is not None:
                with torch.no_grad():
                    moved = frame_translation(previous, blurred) / self.stride
                hidden, aux, blended = (None if part is None else shift_features(part, moved)
                                        for part in (hidden, aux, blended))  # fmt: skip
            previous = blurred
            full = self.encode_full(inputs)
            if config.blur_condition:
                width_full = full.shape[1]
                full = _modulated(full, scale[:, step, :width_full], shift[:, step, :width_full])
            features = self.encode(full)
            if config.blur_condition:
                features = _modulated(features, scale[:, step, width_full:],
                                      shift[:, step, width_full:])  # fmt: skip
            if hidden is None or not config.recurrent:
                hidden = features.new_zeros(n, config.hidden, *features.shape[-2:])
            features = self.recur(torch.cat([features, hidden], 1))
            hidden = self.to_hidden(features)
            if config.bounded_state:
                hidden = torch.tanh(hidden)
            parts = [features, hidden]
            if config.aux_state:
                if aux is None or not config.recurrent:
                    aux = torch.zeros_like(hidden)
                aux = self.aux(torch.cat([hidden, aux], 1))
                if config.bounded_state:
                    aux = torch.tanh(aux)
                parts.append(aux)
            if config.blending:
                if blended is None or not config.recurrent:
                    blended = features
                else:
                    weights = torch.softmax(self.attend(torch.cat([features, blended], 1)), 1)
                    blended = weights[:, :1] * features + weights[:, 1:] * blended
                    if keep_attention:
                        self.last_attention.append(weights[:, :1].detach())
                parts.append(blended)
            residual = self.output(torch.cat([self.reconstruct(torch.cat(parts, 1)), full], 1))
            outputs.append(blurred + residual)
        restored = torch.stack(outputs, 1)[..., :height, :width]
        return restored, (hidden, aux, blended, previous)


def _modulated(features: torch.Tensor, scale: torch.Tensor, shift: torch.Tensor) -> torch.Tensor:
    """(N, C, H, W) features scaled by 1 + ``scale`` and shifted by ``shift``, both (N, C)."""
    return features * (1.0 + scale[..., None, None]) + shift[..., None, None]


def parameter_count(model: nn.Module) -> int:
    r"""Number of trainable parameters of a network.

    .. math::

        P = \sum_{\theta \in \Theta,\ \theta \text{ trainable}} |\theta|

    Parameters
    ----------
    model : torch.nn.Module
        Any network.

    Returns
    -------
    int
        The count.
    """
    return sum(p.numel() for p in model.parameters() if p.requires_grad)


def matched_blocks(config: VideoDeblurConfig, parameters: int) -> VideoDeblurConfig:
    r"""``config`` with the number of residual blocks in eq. 8's recurrence whose parameter
    count lies nearest to ``parameters``.

    .. math::

        \hat{b} = \arg\min_{1 \le b \le b_0 + 8} \bigl| P(\text{config with } b \text{ blocks})
        - P^\ast \bigr|

    An ablation that removes a part of the network (the auxiliary state of eq. 9, the blending
    of eq. 10, the recurrence) also removes its parameters; given the blocks back, the ablated
    network competes with the full one at (nearly) equal capacity, so that a difference
    between them is the part's, not the parameter count's.

    Parameters
    ----------
    config : VideoDeblurConfig
        The variant (its ``blocks`` is replaced).
    parameters : int
        The count to match, e.g. ``parameter_count(VideoDeblurNet())``.

    Returns
    -------
    VideoDeblurConfig
        The variant with 1 to ``config.blocks + 8`` blocks, whichever is nearest.

    Raises
    ------
    ValueError
        If ``parameters`` is not positive.

    References
    ----------
    The paper's eq. 8-10 (the parts an ablation removes).
    """
    if parameters < 1:
        raise ValueError(f"parameters must be positive, got {parameters}")
    candidates = [replace(config, blocks=blocks) for blocks in range(1, config.blocks + 9)]
    return min(candidates, key=lambda c: abs(parameter_count(VideoDeblurNet(c)) - parameters))
