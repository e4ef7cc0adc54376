"""The video network told each frame's blur (``VideoDeblurConfig.blur_condition``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import skimage.data
import torch

from blurloc.blur import estimate_motion_blur
from blurloc.experiments.photo_video import photo_training_lines, photo_video
from blurloc.inference import DEFAULT_CHECKPOINT, load_video_deblur, to_tensor
from blurloc.models.video_deblur import (
    VideoDeblurConfig,
    VideoDeblurNet,
    blur_descriptor,
    blur_descriptors,
)
from blurloc.train.config import VideoTrainConfig
from blurloc.train.video import (
    _sample_clips,
    load_video_splits,
    train_video_deblur,
    with_blur_descriptors,
)

TINY = VideoDeblurConfig(channels=8, hidden=4, blocks=1, blur_condition=True)


def test_a_descriptor_is_the_same_for_a_line_and_its_reverse_and_mirrors_negate_its_third() -> None:
    line = blur_descriptor(6.0, 30.0)
    np.testing.assert_allclose(line, blur_descriptor(6.0, 210.0), atol=1e-6)
    np.testing.assert_allclose(blur_descriptor(6.0, 150.0), line * [1, 1, -1], atol=1e-6)
    assert line[0] == pytest.approx(0.75)
    assert np.hypot(*line[1:]) == pytest.approx(6.0 / 8.0)  # direction weighted by L / (L + 2)
    assert np.allclose(blur_descriptor(0.0, 45.0), 0.0)  # no blur: no direction
    for length, angle in ((-1.0, 0.0), (np.nan, 0.0), (3.0, np.inf)):
        with pytest.raises(ValueError, match="finite length"):
            blur_descriptor(length, angle)


def test_the_photo_training_lines_follow_the_estimators_angle_convention() -> None:
    blurred, _ = photo_video(skimage.data.coffee(), 6, step_px=1.5, angle_deg=100.0,
                             noise_sigma=0.0)  # fmt: skip
    true_angle = (-100.0) % 180.0  # rows downwards in the pan, upwards in the estimate
    errors = [abs((estimate_motion_blur(frame).angle_deg - true_angle + 90.0) % 180.0 - 90.0)
              for frame in blurred]  # fmt: skip
    assert np.median(errors) < 10.0  # the wobble of the pan turns single frames further
    lines = photo_training_lines(5, seed=3)
    assert len(lines) == 5
    assert all(2.25 <= length <= 15.75 and 0.0 <= angle < 180.0 for length, angle in lines)


def test_a_conditioned_network_starts_as_the_plain_one_and_then_reads_the_blur() -> None:
    torch.manual_seed(0)
    plain = VideoDeblurNet(VideoDeblurConfig(channels=8, hidden=4, blocks=1)).eval()
    conditioned = VideoDeblurNet(TINY).eval()
    missing = conditioned.load_state_dict(plain.state_dict(), strict=False).missing_keys
    assert missing and all(key.startswith("modulate.") for key in missing)
    blurred = photo_video(skimage.data.coffee(), 3, step_px=1.0, noise_sigma=0.0)[0]
    frames = to_tensor(blurred[:, :30, :45])[None]  # odd size: padded and cut
    blur = blur_descriptors(frames)
    assert blur.shape == (1, 3, 3) and blur[..., 0].min() > 0
    with torch.no_grad():
        expected, _ = plain(frames)
        computed, _ = conditioned(frames)
        torch.testing.assert_close(computed, expected)  # zero modulation at the start
        conditioned.modulate[-1].bias.fill_(0.5)
        conditioned.modulate[-1].weight.normal_()
        given, _ = conditioned(frames, blur=blur)
        other, _ = conditioned(frames, blur=torch.zeros_like(blur))
    assert (given - other).abs().max() > 1e-3  # the blur changes the output
    with pytest.raises(ValueError, match="blur must be"):
        conditioned(frames, blur=blur[:, :1])


def test_training_clips_negate_the_descriptor_with_every_mirror() -> None:
    ramp = np.add.outer(np.arange(24) * 4, np.arange(32) * 2).astype(np.uint8)  # rises down, right
    video = np.repeat(np.stack([ramp] * 6)[..., None], 3, axis=3)
    descriptors = np.tile(blur_descriptor(5.0, 30.0), (6, 1))
    config = VideoTrainConfig(batch=32, clip_frames=3, crop=16)
    blurred, _, blur = _sample_clips([(video, video, descriptors)], config,
                                     np.random.default_rng(0))  # fmt: skip
    assert blur.shape == (32, 3, 3)
    first = blurred[:, 0, 0]
    mirrored_x = first[:, :, -1].mean(1) < first[:, :, 0].mean(1)
    mirrored_y = first[:, -1, :].mean(1) < first[:, 0, :].mean(1)
    odd = mirrored_x ^ mirrored_y
    assert 0 < int(odd.sum()) < 32
    expected = torch.where(odd, -descriptors[0, 2], descriptors[0, 2]).float()
    torch.testing.assert_close(blur[:, :, 2], expected[:, None].expand(-1, 3))
    torch.testing.assert_close(
        blur[:, :, :2], torch.from_numpy(descriptors[:3, :2]).expand(32, 3, 2)
    )


def test_videos_keep_the_descriptors_they_carry_and_get_estimates_otherwise() -> None:
    blurred, sharp = photo_video(skimage.data.coffee(), 2, step_px=1.0, noise_sigma=0.0)
    told = np.zeros((2, 3), np.float32)
    kept, estimated = with_blur_descriptors([(blurred, sharp, told), (blurred, sharp)])
    assert kept[2] is told
    assert estimated[2].shape == (2, 3) and estimated[2][:, 0].min() > 0


def test_networks_stored_without_the_switch_are_told_no_blur() -> None:
    settings = TINY.as_dict()
    del settings["blur_condition"]
    assert not VideoDeblurConfig.from_stored(settings).blur_condition
    assert not load_video_deblur(DEFAULT_CHECKPOINT).config.blur_condition


def test_training_a_conditioned_network_learns_and_stores_the_switch(
    quick_root: Path, tmp_path: Path
) -> None:
    splits = load_video_splits(quick_root, with_test=False)
    config = VideoTrainConfig(steps=8, batch=2, clip_frames=3, crop=32, validate_every=4,
                              threads=1, device="cpu", model=TINY)  # fmt: skip
    history = train_video_deblur(splits, tmp_path, config, progress=False)
    assert history["train_loss"][-1] < history["train_loss"][0]
    assert load_video_deblur(tmp_path / "best.pt").config.blur_condition


def test_training_mixes_videos_with_and_without_their_own_descriptors(tmp_path: Path) -> None:
    blurred, sharp = photo_video(skimage.data.coffee(), 4, step_px=1.0, noise_sigma=0.0)
    told = np.tile(blur_descriptor(9.0, 0.0), (4, 1))
    splits = {"train": [(blurred, sharp, told), (blurred, sharp)],
              "validation": [(blurred, sharp)]}  # fmt: skip
    model = VideoDeblurConfig(channels=8, hidden=4, blocks=1, blur_condition=True,
                              wiener_input=True)  # fmt: skip
    config = VideoTrainConfig(steps=2, batch=2, clip_frames=2, crop=32, validate_every=2,
                              threads=1, device="cpu", model=model)  # fmt: skip
    history = train_video_deblur(splits, tmp_path, config, progress=False)
    assert history["step"] == [2]
