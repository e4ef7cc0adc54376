"""The recurrent deblurring network (eq. 8-11), its training loop, checkpoints and CLI."""

from __future__ import annotations

import json
import shutil
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest
import skimage.data
import torch
from torch import nn

from blurloc.cli import main
from blurloc.data import check_data, load_split, read_image
from blurloc.data.frames import list_frames
from blurloc.experiments.photo_video import (
    PHOTO_TRAINING_PHOTOS,
    PHOTO_VIDEO_PHOTOS,
    PHOTO_VIDEO_SPEEDS,
    add_photo_videos,
    photo_training_videos,
    photo_video,
    photo_video_gains,
)
from blurloc.experiments.registration import registered_psnr
from blurloc.experiments.video import write_deblurred_root
from blurloc.inference import (
    DEFAULT_CHECKPOINT,
    VideoRestorer,
    load_video_deblur,
    restore_sequence,
)
from blurloc.metrics import mean_frame_psnr
from blurloc.models.video_deblur import (
    VideoDeblurConfig,
    VideoDeblurNet,
    frame_translation,
    parameter_count,
    shift_features,
)
from blurloc.stored import VIDEO_SWITCHES_ADDED
from blurloc.train.config import VideoTrainConfig
from blurloc.train.loop import validation_cut
from blurloc.train.video import (
    load_video_splits,
    train_video_deblur,
    with_motion_deconvolution,
)
from blurloc.video_wiener import deblur_video_motion

SINGLE_FRAME = VideoDeblurConfig(aux_state=False, blending=False, recurrent=False)


def test_default_network_is_small_and_has_no_transposed_convolution() -> None:
    model = VideoDeblurNet()
    assert parameter_count(model) <= 1_000_000
    assert not any(isinstance(m, nn.ConvTranspose2d) for m in model.modules())
    # the ablations have the same core: dropping parts removes at most a few percent
    single = VideoDeblurNet(SINGLE_FRAME)
    assert parameter_count(single) >= 0.75 * parameter_count(model)


@pytest.mark.parametrize("stride", [4, 2])
@pytest.mark.parametrize(("height", "width"), [(120, 160), (37, 53), (4, 4)])
def test_any_frame_size_is_restored_to_the_same_size(height: int, width: int, stride: int) -> None:
    model = VideoDeblurNet(VideoDeblurConfig(feature_stride=stride)).eval()
    frames = torch.rand(2, 3, 3, height, width) * 2 - 1
    with torch.no_grad():
        restored, (hidden, *_) = model(frames)
    assert restored.shape == frames.shape
    assert hidden.shape[-2:] == (-(-height // stride), -(-width // stride))


def test_feature_stride_must_be_two_or_four() -> None:
    with pytest.raises(ValueError, match="feature_stride must be 2 or 4, got 3"):
        VideoDeblurConfig(feature_stride=3)


def test_output_is_a_residual_on_the_blurred_frame() -> None:
    model = VideoDeblurNet().eval()
    last = model.output[-1]
    nn.init.zeros_(last.weight)
    nn.init.zeros_(last.bias)
    frames = torch.rand(1, 3, 3, 16, 24) * 2 - 1
    with torch.no_grad():
        restored, _ = model(frames)
    torch.testing.assert_close(restored, frames)


def test_single_frame_network_ignores_the_past_and_recurrent_one_does_not() -> None:
    torch.manual_seed(0)
    frames = torch.rand(1, 3, 3, 16, 16) * 2 - 1
    changed = frames.clone()
    changed[:, 0] = -changed[:, 0]  # only the first frame differs
    for config, depends in ((SINGLE_FRAME, False), (VideoDeblurConfig(), True)):
        model = VideoDeblurNet(config).eval()
        with torch.no_grad():
            a, _ = model(frames)
            b, _ = model(changed)
        assert torch.allclose(a[:, 2], b[:, 2], atol=1e-6) is not depends


def test_state_carries_across_chunks() -> None:
    torch.manual_seed(1)
    model = VideoDeblurNet().eval()
    video = (np.random.default_rng(0).random((7, 20, 28, 3)) * 255).astype(np.uint8)
    whole = restore_sequence(model, video, chunk=7)
    pieces = restore_sequence(model, video, chunk=3)
    assert np.abs(whole.astype(int) - pieces.astype(int)).max() <= 1  # float rounding only


def test_bounded_state_stays_bounded_where_an_expansive_recurrence_blows_up() -> None:
    torch.manual_seed(2)
    frames = torch.rand(1, 60, 3, 16, 16) * 2 - 1
    unbounded = VideoDeblurNet(
        VideoDeblurConfig(channels=8, hidden=4, blocks=1, bounded_state=False)
    )
    with torch.no_grad():
        for parameter in unbounded.parameters():
            parameter.mul_(4.0)  # an expansive recurrence, as a training-loss spike can leave
    bounded = VideoDeblurNet(replace(unbounded.config, bounded_state=True))
    bounded.load_state_dict(unbounded.state_dict())  # the same weights, states through tanh
    with torch.no_grad():
        restored, (hidden, aux, _, _) = bounded(frames)
        _, (exploded, _, _, _) = unbounded(frames)
    assert hidden.abs().max() <= 1 and aux.abs().max() <= 1 and torch.isfinite(restored).all()
    assert not torch.isfinite(exploded).all() or exploded.abs().max() > 1e6
    assert VideoDeblurConfig().bounded_state  # the default, and the shipped network's
    assert load_video_deblur(DEFAULT_CHECKPOINT).config.bounded_state


def test_a_checkpoint_made_before_a_switch_existed_loads_with_it_off(tmp_path: Path) -> None:
    settings = VideoDeblurConfig(channels=8, hidden=4, blocks=1, bounded_state=False).as_dict()
    network = VideoDeblurNet(VideoDeblurConfig(**settings))
    legacy = {key: value for key, value in settings.items() if key not in VIDEO_SWITCHES_ADDED}
    torch.save({"format": "blurloc-video-deblur-1", "model_config": legacy,
                "model": network.state_dict()}, tmp_path / "old.pt")  # fmt: skip
    loaded = load_video_deblur(tmp_path / "old.pt")
    assert not loaded.config.bounded_state and not loaded.config.align
    assert VideoDeblurConfig.from_stored(settings | {"bounded_state": True}).bounded_state
    torch.save({"format": "blurloc-video-deblur-1", "model_config": {"width": 3},
                "model": network.state_dict()}, tmp_path / "odd.pt")  # fmt: skip
    with pytest.raises(ValueError, match="damaged network configuration"):
        load_video_deblur(tmp_path / "odd.pt")


def test_a_run_stored_before_the_added_switches_is_reused(quick_root: Path, tmp_path: Path) -> None:
    splits = load_video_splits(quick_root, with_test=False)
    # every switch as the runs stored before it were made
    model = VideoDeblurConfig(channels=8, hidden=4, blocks=1, **VIDEO_SWITCHES_ADDED)
    config = VideoTrainConfig(steps=4, batch=2, clip_frames=3, crop=32, validate_every=2,
                              threads=1, model=model)  # fmt: skip
    first = train_video_deblur(splits, tmp_path, config, progress=False, stop_after=1)
    for name in ("last.pt", "best.pt"):  # as a version without the switches stored them
        payload = torch.load(tmp_path / name, map_location="cpu", weights_only=False)
        for key in VIDEO_SWITCHES_ADDED:
            del payload["train_config"]["model"][key], payload["model_config"][key]
        torch.save(payload, tmp_path / name)
    resumed = train_video_deblur(splits, tmp_path, config, progress=False)  # not refused
    assert first["step"] == [2] and resumed["step"] == [2, 4]


@pytest.mark.parametrize("shift", [(3, 0), (0, -5), (7, 4), (-2, -9)])
def test_frame_translation_finds_the_image_shift_between_noisy_blurred_frames(
    shift: tuple[int, int],
) -> None:
    # a photograph blurred a little, cut twice with its content moved by `shift`, sensor noise
    photo = cv2.GaussianBlur(skimage.data.astronaut(), (0, 0), 1.0).astype(np.float32) / 255
    dx, dy = shift
    rng = np.random.default_rng(0)
    frames = [photo[100 - y : 220 - y, 100 - x : 260 - x] for x, y in ((0, 0), (dx, dy))]
    previous, current = (torch.from_numpy(f + rng.normal(0, 0.01, f.shape).astype(np.float32))
                         .permute(2, 0, 1)[None] for f in frames)  # fmt: skip
    found = frame_translation(previous, current)[0]
    torch.testing.assert_close(found, torch.tensor([dx, dy], dtype=torch.float32), atol=0.25,
                               rtol=0)  # fmt: skip


def test_shift_features_moves_a_map_by_whole_and_half_pixels() -> None:
    features = torch.arange(2 * 8 * 10, dtype=torch.float32).reshape(1, 2, 8, 10)
    moved = shift_features(features, torch.tensor([[2.0, -1.0]]))
    torch.testing.assert_close(moved[..., 1:6, 3:8], features[..., 2:7, 1:6])  # out(x) = in(x - d)
    half = shift_features(features, torch.tensor([[0.5, 0.0]]))
    torch.testing.assert_close(half[..., 2:8], (features[..., 1:7] + features[..., 2:8]) / 2)


def test_aligned_network_leaves_a_still_video_as_the_unaligned_one_does() -> None:
    torch.manual_seed(3)
    still = (torch.rand(1, 1, 3, 24, 32) * 2 - 1).repeat(1, 4, 1, 1, 1)  # no motion: shift 0
    plain = VideoDeblurNet().eval()
    aligned = VideoDeblurNet(VideoDeblurConfig(align=True)).eval()
    aligned.load_state_dict(plain.state_dict())
    with torch.no_grad():
        torch.testing.assert_close(aligned(still)[0], plain(still)[0], atol=1e-5, rtol=0)


def test_aligned_network_carries_its_last_frame_across_chunks() -> None:
    torch.manual_seed(2)
    model = VideoDeblurNet(VideoDeblurConfig(align=True)).eval()
    assert parameter_count(model) == parameter_count(VideoDeblurNet())
    video = (np.random.default_rng(1).random((7, 20, 28, 3)) * 255).astype(np.uint8)
    whole = restore_sequence(model, video, chunk=7)
    pieces = restore_sequence(model, video, chunk=3)
    assert np.abs(whole.astype(int) - pieces.astype(int)).max() <= 1


def test_blending_weights_are_non_negative_and_sum_to_one() -> None:
    model = VideoDeblurNet().eval()
    with torch.no_grad():
        model(torch.rand(1, 4, 3, 16, 16) * 2 - 1, keep_attention=True)
    assert len(model.last_attention) == 3  # from the second frame on
    for weights in model.last_attention:
        assert (weights >= 0).all() and (weights <= 1).all()


def test_training_learns_resumes_identically_and_checkpoints_load(
    quick_root: Path, tmp_path: Path
) -> None:
    splits = load_video_splits(quick_root)
    config = VideoTrainConfig(steps=12, batch=2, clip_frames=3, crop=32, validate_every=6,
                              model=VideoDeblurConfig(channels=16, hidden=8, blocks=1))  # fmt: skip
    straight = train_video_deblur(splits, tmp_path / "a", config, progress=False)
    assert straight["train_loss"][-1] < straight["train_loss"][0]  # it learns
    # interrupted after the first validation, then resumed: the same run, step for step
    first = train_video_deblur(splits, tmp_path / "b", config, progress=False, stop_after=1)
    assert first["step"] == [6]
    resumed = train_video_deblur(splits, tmp_path / "b", config, progress=False)
    assert resumed["step"] == straight["step"]
    np.testing.assert_allclose(resumed["train_loss"], straight["train_loss"], rtol=1e-5)
    np.testing.assert_allclose(resumed["val_psnr"], straight["val_psnr"], rtol=1e-5)
    model = load_video_deblur(tmp_path / "a" / "best.pt")
    assert model.config.channels == 16
    # a best network chosen on other validation frames is not continued
    fewer = {**splits, "validation": splits["validation"][:-1]}
    with pytest.raises(ValueError, match=r"validation\.sequences"):
        train_video_deblur(fewer, tmp_path / "b", config, progress=False)
    # nor one trained on other videos (e.g. other scenes or more photo videos)
    more = {**splits, "train": [*splits["train"], splits["train"][0]]}
    with pytest.raises(ValueError, match=r"train\.sequences"):
        train_video_deblur(more, tmp_path / "b", config, progress=False)


def test_validation_parts_are_the_ends_of_whole_training_sequences(
    quick_root: Path, tmp_path: Path
) -> None:
    root = tmp_path / "root"
    shutil.copytree(quick_root, root)
    first_train = load_split(root, "chess", "train")[0]
    shutil.copytree(first_train.folder, root / "chess" / "seq-09")  # a second training sequence
    split_file = root / "chess" / "TrainSplit.txt"
    split_file.write_text(split_file.read_text().rstrip("\n") + "\nsequence9\n")
    whole = len(first_train)
    splits = load_video_splits(root, ["chess"], frames_per_sequence=3)
    assert [len(blurred) for blurred, _ in splits["train"]] == [3, 3]
    assert [len(blurred) for blurred, _ in splits["test"]] == [3]
    # validation: the end of the whole sequence, not of the 3 frames trained on
    end = first_train.frame_ids[whole - validation_cut(whole) :]
    blurred, sharp = splits["validation"][0]
    np.testing.assert_array_equal(blurred, first_train.images("color", end))
    np.testing.assert_array_equal(sharp, first_train.images("sharp", end))
    assert len(splits["validation"]) == 2
    one = load_video_splits(root, ["chess"], frames_per_sequence=3, validation_per_scene=1)
    assert len(one["validation"]) == 1 and len(one["train"]) == 2
    np.testing.assert_array_equal(one["validation"][0][0], blurred)
    with pytest.raises(ValueError, match="validation_per_scene"):
        load_video_splits(root, validation_per_scene=0)
    training = load_video_splits(root, ["chess"], frames_per_sequence=3, with_test=False)
    assert training["test"] == [] and len(training["train"]) == 2
    # the memory bound counts only what is read: a training fits where training + test do not
    needed = sum(b.nbytes + s.nbytes for kind in ("train", "validation") for b, s in training[kind])
    load_video_splits(root, ["chess"], frames_per_sequence=3, with_test=False, max_bytes=needed)
    with pytest.raises(ValueError, match="GB in memory"):
        load_video_splits(root, ["chess"], frames_per_sequence=3, max_bytes=needed)


def test_bad_checkpoints_and_videos_are_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="missing"):
        load_video_deblur(tmp_path / "none.pt")
    torch.save({"format": "something else"}, tmp_path / "other.pt")
    with pytest.raises(ValueError, match="not a blurloc checkpoint"):
        load_video_deblur(tmp_path / "other.pt")
    (tmp_path / "junk.pt").write_bytes(b"junk")
    with pytest.raises(ValueError, match="not a readable checkpoint"):
        load_video_deblur(tmp_path / "junk.pt")
    wrong = {"format": "blurloc-video-deblur-1", "model_config": VideoDeblurConfig().as_dict(),
             "model": VideoDeblurNet(SINGLE_FRAME).state_dict()}  # fmt: skip
    torch.save(wrong, tmp_path / "wrong.pt")
    with pytest.raises(ValueError, match="do not fit"):
        load_video_deblur(tmp_path / "wrong.pt")
    with pytest.raises(ValueError, match="at least 2 frames"):
        restore_sequence(VideoDeblurNet(), np.zeros((1, 8, 8, 3), np.uint8))


def test_shipped_checkpoint_loads() -> None:
    model = load_video_deblur(DEFAULT_CHECKPOINT)
    assert parameter_count(model) <= 1_000_000


def _write_frames(folder: Path, sizes: list[tuple[int, int]]) -> None:
    folder.mkdir(parents=True)
    rng = np.random.default_rng(0)
    for index, (height, width) in enumerate(sizes):
        frame = (rng.random((height, width, 3)) * 255).astype(np.uint8)
        cv2.imwrite(str(folder / f"frame-{index:06d}.color.png"), frame)


def test_cli_deblur_video(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    _write_frames(tmp_path / "seq", [(24, 32)] * 3)
    assert main(["deblur-video", str(tmp_path / "seq"), str(tmp_path / "out")]) == 0
    assert json.loads(capsys.readouterr().out)["frames"] == 3
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert names == [f"frame-{i:06d}.color.png" for i in range(3)]
    assert cv2.imread(str(tmp_path / "out" / names[0])).shape == (24, 32, 3)


def test_cli_deblur_video_bad_input(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    _write_frames(tmp_path / "mixed", [(24, 32), (24, 32), (20, 32)])
    _write_frames(tmp_path / "one", [(24, 32)])
    (tmp_path / "empty").mkdir()
    (tmp_path / "bad.pt").write_bytes(b"junk")
    cases = [
        (["deblur-video", str(tmp_path / "mixed"), str(tmp_path / "o")], "frame-000002"),
        (["deblur-video", str(tmp_path / "one"), str(tmp_path / "o")], "one frame only"),
        (["deblur-video", str(tmp_path / "empty"), str(tmp_path / "o")], "no frames"),
        (["deblur-video", str(tmp_path / "nowhere"), str(tmp_path / "o")], "no such folder"),
        (
            [
                "deblur-video",
                str(tmp_path / "one"),
                str(tmp_path / "o"),
                "--checkpoint",
                str(tmp_path / "bad.pt"),
            ],
            "bad.pt",
        ),
    ]
    for argv, message in cases:
        assert main(argv) == 1, argv
        assert message in capsys.readouterr().err, argv


def test_deblurred_root_keeps_the_layout(quick_root: Path, tmp_path: Path) -> None:
    out = write_deblurred_root(quick_root, tmp_path / "copy", lambda frames: 255 - frames)
    assert check_data(out) == check_data(quick_root)
    original = load_split(quick_root, "chess", "test")[0]
    copy = load_split(out, "chess", "test")[0]
    frame = original.frame_ids[0]
    inverted = 255 - read_image(original.path(frame))
    np.testing.assert_array_equal(read_image(copy.path(frame)), inverted)
    np.testing.assert_array_equal(copy.poses(), original.poses())
    assert len(list_frames(copy.folder)) == len(copy)


def test_deblurred_root_in_worker_processes_matches_one_process(
    quick_root: Path, tmp_path: Path
) -> None:
    """The shipped network deblurring a root in two worker processes writes the frames that
    one process writes (up to one grey level: the thread count changes float rounding), and
    what :func:`restore_sequence` gives for the sequence."""
    restorer = VideoRestorer(DEFAULT_CHECKPOINT)
    copies = {workers: write_deblurred_root(quick_root, tmp_path / f"w{workers}", restorer,
                                            workers=workers) for workers in (1, 2)}  # fmt: skip
    sequence = load_split(quick_root, "chess", "test")[0]
    blurred = sequence.images()
    expected = restore_sequence(load_video_deblur(DEFAULT_CHECKPOINT), blurred)
    for copy in copies.values():
        written = load_split(copy, "chess", "test")[0]
        frames = written.images()
        assert np.abs(frames.astype(int) - expected).max() <= 1
    with pytest.raises(ValueError, match="workers"):
        write_deblurred_root(quick_root, tmp_path / "w0", restorer, workers=0)


def test_registered_psnr_finds_a_known_shift() -> None:
    import skimage.data

    image = skimage.data.astronaut()[100:228, 150:310].astype(np.float64) / 255.0
    moved = cv2.warpAffine(image, np.float64([[1, 0, 1.5], [0, 1, -0.7]]), (160, 128),
                           flags=cv2.INTER_CUBIC, borderMode=cv2.BORDER_REFLECT)  # fmt: skip
    shift, plain, registered = registered_psnr(image, moved)
    assert shift == pytest.approx(np.hypot(1.5, 0.7), abs=0.15)
    assert registered > plain + 8.0
    same = registered_psnr(image, image)
    assert same[0] < 0.05 and same[2] > 100.0  # identical images stay (nearly) identical
    with pytest.raises(ValueError, match="share a shape"):
        registered_psnr(image, image[:64])


def test_photo_video_blurs_with_speed_and_the_shipped_network_does_not_make_it_worse() -> None:
    import skimage.data

    photo = skimage.data.coffee()
    still, still_sharp = photo_video(photo, frames=3, subframes=1, seed=1)
    slow, slow_sharp = photo_video(photo, frames=6, step_px=0.5, seed=1)
    fast, fast_sharp = photo_video(photo, frames=6, step_px=1.5, seed=1)
    assert still.shape == (3, 120, 160, 3) and still.dtype == np.uint8
    pairs = ((still, still_sharp), (slow, slow_sharp), (fast, fast_sharp))
    scores = [mean_frame_psnr([(b, s)]) for b, s in pairs]
    assert scores[0] > 38.0 > scores[1] > scores[2]  # one sub-frame: only the noise (σ = 0.01)
    model = load_video_deblur(DEFAULT_CHECKPOINT)
    for blurred, sharp in ((slow, slow_sharp), (fast, fast_sharp)):
        before = mean_frame_psnr([(blurred, sharp)])
        after = mean_frame_psnr([(restore_sequence(model, blurred), sharp)])
        assert after > before - 0.1, (before, after)
    with pytest.raises(ValueError, match="RGB"):
        photo_video(photo[..., 0])


def test_photo_training_videos_blur_photographs_the_scored_set_does_not_show() -> None:
    assert PHOTO_TRAINING_PHOTOS and not set(PHOTO_TRAINING_PHOTOS) & set(PHOTO_VIDEO_PHOTOS)

    def gradient_energy(video: np.ndarray) -> float:
        video = video.astype(float)
        return float(np.mean(np.diff(video, axis=1) ** 2) + np.mean(np.diff(video, axis=2) ** 2))

    videos = photo_training_videos(6, frames=4, seed=0)  # camera, brick, ... coins: textured
    assert len(videos) == 6
    for blurred, sharp in videos:
        assert blurred.shape == sharp.shape == (4, 120, 160, 3) and blurred.dtype == np.uint8
        assert gradient_energy(blurred) < 0.8 * gradient_energy(sharp)  # blurred, not just noisy
    again = photo_training_videos(2, frames=4, seed=0)
    assert all(np.array_equal(a[0], b[0]) for a, b in zip(again, videos[:2], strict=True))
    assert not np.array_equal(photo_training_videos(1, frames=4, seed=1)[0][0], videos[0][0])
    with pytest.raises(ValueError, match="count"):
        photo_training_videos(0)


def test_add_photo_videos_appends_to_training_and_validation() -> None:
    video = (np.zeros((5, 120, 160, 3), np.uint8),) * 2
    splits = {"train": [video] * 3, "validation": [video], "test": [video]}
    assert add_photo_videos(splits, 0) is splits
    mixed = add_photo_videos(splits, 3, frames=2)
    assert [len(mixed[name]) for name in ("train", "validation", "test")] == [6, 2, 1]
    assert len(splits["train"]) == 3  # the given lists are not changed
    assert mixed["train"][3][0].shape == (2, 120, 160, 3)
    assert [len(add_photo_videos(splits, 1, frames=2)[name]) for name in splits] == [4, 2, 1]
    assert not np.array_equal(mixed["validation"][1][0], mixed["train"][3][0])  # other videos
    with pytest.raises(ValueError, match="count"):
        add_photo_videos(splits, -1)
    both = add_photo_videos(splits, 2, frames=2, noise_sigmas=(0.01, 0.0))
    assert [len(both[name]) for name in ("train", "validation")] == [7, 3]
    assert np.array_equal(both["train"][3][0], mixed["train"][3][0])  # the first set as before
    clean = photo_training_videos(2, frames=2, seed=2, noise_sigma=0.0)
    assert all(np.array_equal(a[0], b[0]) for a, b in zip(both["train"][5:], clean, strict=True))
    for wrong in ((), (-0.01,)):
        with pytest.raises(ValueError, match="noise_sigmas"):
            add_photo_videos(splits, 1, noise_sigmas=wrong)


def test_training_videos_deconvolved_by_their_motion_as_the_restorer_sees_them() -> None:
    """with_motion_deconvolution gives each video's deconvolution (share read from it), what
    MotionNetworkRestorer feeds the network, and keeps the other parts; two processes give
    the same frames as one."""
    videos = [(*photo_video(skimage.data.coffee(), frames=4, step_px=step, angle_deg=angle),
               np.zeros((4, 3), np.float32))
              for step, angle in ((2.0, 20.0), (1.5, 100.0))]  # fmt: skip
    deconvolved = with_motion_deconvolution(videos)
    assert [len(video) for video in deconvolved] == [3, 3]
    for (blurred, sharp, extra), (restored, kept_sharp, kept_extra) in zip(
        videos, deconvolved, strict=True
    ):
        np.testing.assert_array_equal(restored, deblur_video_motion(blurred, None))
        assert kept_sharp is sharp and kept_extra is extra
        assert mean_frame_psnr([(restored, sharp)]) > mean_frame_psnr([(blurred, sharp)])
    for one, two in zip(deconvolved, with_motion_deconvolution(videos, workers=2), strict=True):
        np.testing.assert_array_equal(one[0], two[0])


def test_photo_video_gains_score_every_photo_and_speed_against_the_input() -> None:
    rows = photo_video_gains(np.asarray, frames=2)  # the input itself: no gain
    assert [(r["photo"], r["step_px"]) for r in rows] == [
        (photo, step) for photo in PHOTO_VIDEO_PHOTOS for step in PHOTO_VIDEO_SPEEDS
    ]
    assert all(r["gain_db"] == 0.0 == r["restored_psnr_db"] - r["blurred_psnr_db"] for r in rows)
    for photo in PHOTO_VIDEO_PHOTOS:  # faster pans blur more
        scores = [r["blurred_psnr_db"] for r in rows if r["photo"] == photo]
        assert scores == sorted(scores, reverse=True), (photo, scores)
    clean = photo_video_gains(np.asarray, frames=2, noise_sigma=0.0)
    assert all(
        c["blurred_psnr_db"] > r["blurred_psnr_db"] for c, r in zip(clean, rows, strict=True)
    )


def test_the_shipped_network_does_not_drift_over_a_long_video(quick_root: Path) -> None:
    """1008 frames: a stand-in sequence played forward and back 72 times (continuous motion,
    period 14). Any 98 consecutive frames hold each phase of the period exactly 7 times, so
    without a drifting recurrent state the first and last 98 frames score the same."""
    sequence = load_split(quick_root, "chess", "test")[0]
    order = [*range(len(sequence)), *range(len(sequence) - 2, 0, -1)]  # 0..7, 6..1: period 14
    blurred = sequence.images()[order]
    sharp = sequence.images("sharp")[order]
    repeats = 1008 // len(order)
    network = load_video_deblur(DEFAULT_CHECKPOINT)
    restored = restore_sequence(network, np.tile(blurred, (repeats, 1, 1, 1)))
    sharp = np.tile(sharp, (repeats, 1, 1, 1))
    window = 7 * len(order)
    first = mean_frame_psnr([(restored[:window], sharp[:window])])
    last = mean_frame_psnr([(restored[-window:], sharp[-window:])])
    assert abs(last - first) < 0.3, (first, last)
