"""The Wiener step before the recurrent network (``VideoDeblurConfig.wiener_input``)."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest
import skimage.data
import torch

from blurloc.blur import blur_image, motion_kernel
from blurloc.experiments.photo_video import photo_video
from blurloc.inference import DEFAULT_CHECKPOINT, frames_from_tensor, load_video_deblur, to_tensor
from blurloc.metrics import psnr
from blurloc.models.video_deblur import (
    VideoDeblurConfig,
    VideoDeblurNet,
    motion_guides,
    network_guides,
    wiener_guides,
)
from blurloc.train.config import VideoTrainConfig
from blurloc.train.video import load_video_splits, train_video_deblur
from blurloc.video_wiener import deblur_video_motion

TINY = VideoDeblurConfig(channels=8, hidden=4, blocks=1, wiener_input=True)


def line_blurred_video(length_px: float = 9.0) -> tuple[np.ndarray, np.ndarray]:
    """Two 160x120 frames of a photograph, sharp and blurred by a horizontal line, no noise."""
    sharp = cv2.resize(skimage.data.astronaut(), (160, 120), interpolation=cv2.INTER_AREA)
    blurred = np.clip(np.rint(255 * blur_image(sharp, motion_kernel(length_px, 0.0))), 0, 255)
    return np.stack([blurred.astype(np.uint8)] * 2), np.stack([sharp] * 2)


def test_wiener_guides_undo_a_line_blur_of_a_photograph() -> None:
    blurred, sharp = line_blurred_video()
    guides = frames_from_tensor(wiener_guides(to_tensor(blurred)[None])[0])
    assert guides.shape == blurred.shape
    assert psnr(sharp[0], guides[0], 255.0) > psnr(sharp[0], blurred[0], 255.0) + 1.0


def test_wiener_guides_with_the_gradient_regulariser_undo_the_blur() -> None:
    blurred, sharp = line_blurred_video()
    frames = to_tensor(blurred)[None]
    gradient = frames_from_tensor(wiener_guides(frames, "gradient")[0])
    constant = frames_from_tensor(wiener_guides(frames)[0])
    assert psnr(sharp[0], gradient[0], 255.0) > psnr(sharp[0], blurred[0], 255.0) + 1.0
    assert not np.array_equal(gradient, constant)


def test_the_network_reads_the_copy_of_its_regulariser() -> None:
    torch.manual_seed(0)
    network = VideoDeblurNet(VideoDeblurConfig(channels=8, hidden=4, blocks=1, wiener_input=True,
                                               wiener_gradient=True)).eval()  # fmt: skip
    frames = to_tensor(line_blurred_video()[0][:, :40, :48])[None]
    with torch.no_grad():
        computed, _ = network(frames)
        given, _ = network(frames, guides=wiener_guides(frames, "gradient"))
        other, _ = network(frames, guides=wiener_guides(frames, "constant"))
    torch.testing.assert_close(computed, given)
    assert (other - given).abs().max() > 1e-5


def test_wiener_input_network_reads_the_copy_and_keeps_the_frame_size() -> None:
    torch.manual_seed(0)
    network = VideoDeblurNet(TINY).eval()
    assert network.encode_full[0].in_channels == 6
    frames = to_tensor(line_blurred_video()[0][:, :30, :45])[None]  # odd size: padded and cut
    guides = wiener_guides(frames)
    with torch.no_grad():
        computed, _ = network(frames)
        given, _ = network(frames, guides=guides)
        other, _ = network(frames, guides=torch.zeros_like(guides))
    assert computed.shape == frames.shape
    torch.testing.assert_close(computed, given)
    assert (other - given).abs().max() > 1e-4  # the copy changes the output
    with pytest.raises(ValueError, match="guides must have"):
        network(frames, guides=guides[:, :1])


def test_networks_stored_without_the_switch_read_the_frames_alone() -> None:
    settings = TINY.as_dict()
    del settings["wiener_input"], settings["wiener_gradient"]
    assert not VideoDeblurConfig.from_stored(settings).wiener_input
    assert not VideoDeblurConfig.from_stored(settings).wiener_gradient
    assert not VideoDeblurConfig().wiener_input
    assert not load_video_deblur(DEFAULT_CHECKPOINT).config.wiener_input


def test_training_with_wiener_input_learns_and_stores_the_switch(
    quick_root: Path, tmp_path: Path
) -> None:
    splits = load_video_splits(quick_root, with_test=False)
    config = VideoTrainConfig(steps=8, batch=2, clip_frames=3, crop=32, validate_every=4,
                              threads=1, device="cpu", model=TINY)  # fmt: skip
    history = train_video_deblur(splits, tmp_path, config, progress=False)
    assert history["train_loss"][-1] < history["train_loss"][0]
    assert load_video_deblur(tmp_path / "best.pt").config.wiener_input


def test_motion_guides_undo_the_blur_of_a_panned_photograph() -> None:
    blurred, sharp = photo_video(skimage.data.astronaut(), 6, step_px=2.0, angle_deg=0.0,
                                 noise_sigma=0.0, seed=0)  # fmt: skip
    guides = frames_from_tensor(motion_guides(to_tensor(blurred)[None])[0])
    np.testing.assert_array_equal(guides, deblur_video_motion(blurred))
    inner = slice(1, -1)  # the end frames' paths are extrapolated
    assert (np.mean([psnr(s, g, 255.0) for s, g in zip(sharp[inner], guides[inner], strict=True)])
            > np.mean([psnr(s, b, 255.0) for s, b in zip(sharp[inner], blurred[inner],
                                                          strict=True)]) + 0.5)  # fmt: skip
    one = to_tensor(blurred[:1])[None]
    torch.testing.assert_close(motion_guides(one), one, atol=1e-6, rtol=0)  # no motion to measure


def test_the_network_with_wiener_motion_reads_the_motion_copies() -> None:
    config = VideoDeblurConfig(channels=8, hidden=4, blocks=1, wiener_input=True,
                               wiener_motion=True)  # fmt: skip
    torch.manual_seed(0)
    network = VideoDeblurNet(config).eval()
    blurred, _ = photo_video(skimage.data.astronaut(), 4, step_px=2.0, angle_deg=0.0,
                             noise_sigma=0.0, seed=0)  # fmt: skip
    frames = to_tensor(blurred[:, :48, :64])[None]
    with torch.no_grad():
        computed, _ = network(frames)
        given, _ = network(frames, guides=network_guides(frames, config))
        blind, _ = network(frames, guides=wiener_guides(frames))
    torch.testing.assert_close(computed, given)
    assert (blind - given).abs().max() > 1e-5
    with pytest.raises(ValueError, match="needs wiener_input"):
        VideoDeblurConfig(wiener_motion=True)
    with pytest.raises(ValueError, match="set one"):
        VideoDeblurConfig(wiener_input=True, wiener_motion=True, wiener_gradient=True)
    stored = config.as_dict()
    del stored["wiener_motion"]
    assert not VideoDeblurConfig.from_stored(stored).wiener_motion
