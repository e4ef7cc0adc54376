"""Blur kernels from a video's own motion, and deblurring a video with them."""

from __future__ import annotations

import pickle

import cv2
import numpy as np
import pytest
import skimage.data

from blurloc.blur import blur_image, estimate_noise_sigma, kernel_to_otf, trajectory_kernel
from blurloc.blur.video_motion import (
    MAX_CORRECTED_SHARE,
    calibrate_exposure_share,
    exposure_paths,
    fit_exposure_share,
    frame_shifts,
    frame_warps,
    grid_points,
    local_motion_kernels,
    mid_exposure_shifts,
    path_length,
    video_motion_kernels,
)
from blurloc.cli import main
from blurloc.deconv import wiener_deconvolve
from blurloc.experiments.photo_video import photo_video, photo_video_motion
from blurloc.images import linear_to_srgb, srgb_to_linear
from blurloc.inference import (
    DEFAULT_CHECKPOINT,
    MOTION_CHECKPOINT,
    MotionNetworkRestorer,
    VideoRestorer,
)
from blurloc.metrics import mean_frame_psnr
from blurloc.video_wiener import (
    AGREEMENT_L1,
    deblur_by_kernels,
    deblur_by_local_kernels,
    deblur_video_motion,
    kernel_disagreement,
)

#: A vertical line kernel, 8 px long: unlike the pans' kernels.
VERTICAL_LINE = trajectory_kernel(np.array([[0.0, -4.0], [0.0, 4.0]]), origin=np.zeros(2))


def _panned(step: tuple[float, float], frames: int = 5) -> np.ndarray:
    """Sharp 160x120 crops of a photograph whose content moves by ``step`` px per frame."""
    photo = skimage.data.astronaut()
    crops = []
    for index in range(frames):
        matrix = np.float32([[1, 0, step[0] * index - 100], [0, 1, step[1] * index - 100]])
        crops.append(cv2.warpAffine(photo, matrix, (160, 120), borderMode=cv2.BORDER_REFLECT))
    return np.stack(crops)


def test_frame_shifts_measure_the_motion_of_the_content() -> None:
    shifts = frame_shifts(_panned((3.0, -2.0)))
    assert shifts.shape == (4, 2)
    np.testing.assert_allclose(shifts, np.tile([3.0, -2.0], (4, 1)), atol=0.15)
    with pytest.raises(ValueError, match="at least 2 frames"):
        frame_shifts(_panned((1.0, 0.0))[:1])


@pytest.mark.parametrize("noise", [0.0, 0.01])
def test_frame_shifts_follow_the_true_motion_of_blurred_frames(noise: float) -> None:
    """On GoPro-style blurred frames, where each frame's own blur moves the phase correlation's
    peak, the refined displacements stay within half a pixel of the pan's true motion."""
    step, angle = 1.5, 110.0  # 13.5 px of blur per frame, with a wobble
    blurred, _ = photo_video(skimage.data.rocket(), frames=6, step_px=step, angle_deg=angle,
                             noise_sigma=noise, seed=2)  # fmt: skip
    true = np.diff(photo_video_motion(6, 9, step, angle)[:, 4], axis=0)
    errors = np.linalg.norm(frame_shifts(blurred) - true, axis=1)
    assert errors.max() < 0.5


def test_a_frame_without_structure_keeps_the_phase_correlation() -> None:
    flat = np.full((3, 120, 160, 3), 128, np.uint8)
    shifts = frame_shifts(flat)  # ECC cannot converge on a flat frame: no error, finite shifts
    assert shifts.shape == (2, 2) and np.all(np.isfinite(shifts))


@pytest.mark.parametrize("share", [0.5, 1.0])
def test_mid_exposure_shifts_undo_the_centroid_of_an_accelerating_camera(share: float) -> None:
    times = np.arange(8.0)

    def position(t):  # a camera speeding up along x while it sways along y
        return np.stack([0.4 * t**2 + 2 * t, 3 * np.sin(t)], axis=-1)

    offsets = np.linspace(-share / 2, share / 2, 2001)  # the exposure, densely sampled
    centroids = position(times[:, None] + offsets[None, :]).mean(axis=1)
    middles = position(times)
    measured = np.diff(centroids, axis=0)  # what aligning the blurred frames gives
    truth = np.diff(middles, axis=0)
    corrected = mid_exposure_shifts(measured, share)
    inner = np.s_[1:-1]  # the end frames continue their neighbour's motion: no curvature there
    raw_error = np.abs(measured - truth)[inner].max()
    assert raw_error > 0.01 * share**2  # the centroids are off the middles...
    # ... by the curvature's s^2 / 24, which the correction removes up to the sway's
    # departure from a parabola over the exposure
    assert np.abs(corrected - truth)[inner].max() < 0.25 * raw_error
    steady = np.tile([3.0, -1.0], (5, 1))  # no acceleration: centroids are the middles
    np.testing.assert_allclose(mid_exposure_shifts(steady, share), steady, atol=1e-12)


def test_mid_exposure_shifts_bring_measured_shifts_closer_to_the_middle_frames() -> None:
    blurred, _ = photo_video(skimage.data.astronaut(), frames=8, step_px=1.0, angle_deg=30.0,
                             noise_sigma=0.0)  # fmt: skip
    truth = np.diff(photo_video_motion(8, 9, 1.0, 30.0)[:, 4], axis=0)  # middle sub-frames
    measured = frame_shifts(blurred)
    raw_error = np.abs(measured - truth).mean()
    assert np.abs(mid_exposure_shifts(measured, 1.0) - truth).mean() < 0.8 * raw_error


def test_mid_exposure_shifts_check_their_input() -> None:
    shifts = np.array([[1.0, 0.0], [3.0, 0.0], [4.0, 1.0]])
    beyond = mid_exposure_shifts(shifts, MAX_CORRECTED_SHARE + 0.5)  # near-singular: kept
    np.testing.assert_array_equal(beyond, shifts)
    assert not np.allclose(mid_exposure_shifts(shifts, 1.0), shifts)
    with pytest.raises(ValueError, match="exposure_share"):
        mid_exposure_shifts(shifts, 0.0)
    with pytest.raises(ValueError, match="shifts"):
        mid_exposure_shifts(np.ones((2, 3)), 1.0)


def test_exposure_paths_follow_the_motion_over_the_exposure_share() -> None:
    steady = exposure_paths(np.tile([4.0, 0.0], (3, 1)), exposure_share=0.5, points=5)
    assert len(steady) == 4
    for path in steady:  # a straight segment of half a frame's motion, centred on the frame
        np.testing.assert_allclose(path[:, 1], 0.0)
        np.testing.assert_allclose(path[[0, -1], 0], [-1.0, 1.0])
        assert path_length(path) == pytest.approx(2.0)
    speeding_up = exposure_paths(np.array([[1.0, 0.0], [3.0, 0.0]]), exposure_share=1.0)
    middle = speeding_up[1]  # positions 0, 1, 4: the parabola bends towards the faster side
    assert middle[-1, 0] > -middle[0, 0] > 0
    with pytest.raises(ValueError, match="exposure_share"):
        exposure_paths(np.ones((2, 2)), exposure_share=0.0)
    with pytest.raises(ValueError, match="shifts"):
        exposure_paths(np.ones((2, 3)), exposure_share=1.0)


def _blurred_by_share(steps: np.ndarray, share: float) -> np.ndarray:
    """160x120 crops of a photograph whose mid-exposure positions move by ``steps``, each
    blurred in linear light by the kernel of its exposure path under ``share``."""
    photo = srgb_to_linear(skimage.data.astronaut() / 255.0).astype(np.float32)
    middles = np.vstack([np.zeros((1, 2)), np.cumsum(steps, axis=0)])
    frames = []
    for middle, path in zip(middles, exposure_paths(steps, share), strict=True):
        kernel = np.float32(trajectory_kernel(path, origin=np.zeros(2))[::-1, ::-1])
        matrix = np.float32([[1, 0, middle[0] - 100], [0, 1, middle[1] - 100]])
        moved = cv2.warpAffine(photo, matrix, (160, 120), flags=cv2.INTER_CUBIC,
                               borderMode=cv2.BORDER_REFLECT)  # fmt: skip
        linear = np.clip(cv2.filter2D(moved, -1, kernel), 0, 1)
        frames.append(np.uint8(np.rint(255 * linear_to_srgb(linear))))
    return np.stack(frames)


@pytest.mark.parametrize("share", [1.0, 1.5, 2.0])
def test_the_exposure_share_is_read_from_frames_whose_blur_changes(share: float) -> None:
    """A camera that speeds up, slows down and turns its direction: each frame's kernel differs
    from its neighbours', and the share under which the frames, with their measured motion,
    explain one another is within 15 % of the one they were blurred with (not the default's
    1.0 where that is 1.5 or 2). A steady pan blurs every frame alike: no share is told
    apart."""
    steps = np.array([[2.0, 0.5], [4.0, 1.0], [5.0, 3.0], [4.0, 5.0], [2.0, 6.0], [1.0, 4.0]])
    blurred = _blurred_by_share(steps, share)
    read = calibrate_exposure_share(blurred, frame_shifts(blurred))
    assert read == pytest.approx(share, rel=0.15)
    steady = _blurred_by_share(np.tile([3.3, 1.7], (6, 1)), share)
    assert calibrate_exposure_share(steady, frame_shifts(steady)) is None
    with pytest.raises(ValueError, match="shifts must be"):
        calibrate_exposure_share(blurred, np.zeros((3, 2)))
    with pytest.raises(ValueError, match="alike_weight"):
        fit_exposure_share(blurred, frame_shifts(blurred), alike_weight=-1.0)


def test_the_calibrations_spectral_blur_is_the_blur_of_eq_1_away_from_the_border() -> None:
    """The exposure share's comparison blurs frames by products of spectra (circular
    convolution, :func:`~blurloc.blur.kernel_to_otf` in double precision): away from the border,
    by more than the kernel, it equals :func:`~blurloc.blur.blur_image` for a kernel that is
    neither normalised nor symmetric, so the share it reads is the one direct convolution would
    give. A kernel larger than the frame is refused."""
    image = np.random.default_rng(3).random((48, 64))
    kernel = np.zeros((5, 9))
    kernel[1, :7], kernel[3, 8] = 1.0, 4.0
    spectrum = kernel_to_otf(kernel, image.shape, np.float64)
    circular = np.fft.irfft2(np.fft.rfft2(image) * spectrum / kernel.sum(), s=image.shape)
    inside = np.s_[9:-9, 9:-9]
    np.testing.assert_allclose(circular[inside], blur_image(image, kernel)[inside], atol=1e-12)
    assert np.abs(circular - blur_image(image, kernel)).max() > 1e-3  # the border does differ
    with pytest.raises(ValueError, match="larger than the transform"):
        kernel_to_otf(np.ones((49, 5)), image.shape)


def test_a_long_steady_pan_does_not_hide_where_the_blur_changes() -> None:
    """150 frames of a steady pan, then a camera that speeds up and turns: the share is read
    from the pairs where the motion changes (at most CALIBRATION_MAX_PAIRS), so the steady
    frames, whose blurs are alike and tell nothing, do not dilute it below the depth at which
    it is told apart."""
    varying = np.array([[2.0, 0.5], [4.0, 1.0], [5.0, 3.0], [4.0, 5.0], [2.0, 6.0], [1.0, 4.0]])
    blurred = _blurred_by_share(np.vstack([np.tile([3.3, 1.7], (150, 1)), varying]), 1.0)
    assert calibrate_exposure_share(blurred, frame_shifts(blurred)) == pytest.approx(1.0, rel=0.2)


def test_a_still_video_has_no_blur_and_is_returned_unchanged() -> None:
    still = _panned((0.0, 0.0), frames=3)
    motion = video_motion_kernels(still)
    assert np.all(motion.lengths_px < 0.2)
    assert calibrate_exposure_share(still, frame_shifts(still)) is None
    np.testing.assert_array_equal(deblur_video_motion(still), still)


@pytest.mark.parametrize("noise", [0.0, 0.01])
def test_a_panned_video_is_deblurred_with_and_without_noise(noise: float) -> None:
    """A GoPro-style video (9 sub-frames averaged in linear light, 9 px of motion per frame at
    160x120) of a photograph: its own motion gives the kernels, and the restored frames are
    sharper."""
    blurred, sharp = photo_video(skimage.data.coffee(), frames=6, step_px=1.0, angle_deg=20.0,
                                 noise_sigma=noise, seed=1)  # fmt: skip
    motion = video_motion_kernels(blurred)
    np.testing.assert_allclose(np.median(motion.lengths_px), 9.0, atol=1.5)  # 9 px per frame
    restored = deblur_video_motion(blurred)
    assert restored.shape == blurred.shape and restored.dtype == np.uint8
    gain = mean_frame_psnr([(restored, sharp)]) - mean_frame_psnr([(blurred, sharp)])
    assert gain > 0.5


def test_deblur_video_motion_refuses_what_is_not_a_video() -> None:
    video = _panned((1.0, 0.0), frames=2)
    with pytest.raises(ValueError, match="uint8 video"):
        deblur_video_motion(video[0])
    with pytest.raises(ValueError, match="uint8 video"):
        deblur_video_motion(video.astype(np.float32))
    with pytest.raises(ValueError, match="min_weight"):
        deblur_video_motion(video, min_weight=0.0)
    with pytest.raises(ValueError, match="weight_per_noise must be > 0, got -1"):
        deblur_video_motion(video, weight_per_noise=-1.0)
    with pytest.raises(ValueError, match=r"boundary must be one of .*'periodic'"):
        deblur_video_motion(video, boundary="periodic")


def test_a_pans_border_is_restored_from_the_unknown_boundary_not_a_mirror() -> None:
    """The pan carries light into the frame from outside: solving for the image beyond the frame
    restores the frame's 12 px border where a mirror of the frame rings (no noise)."""
    blurred, sharp = photo_video(skimage.data.coffee(), frames=6, step_px=1.5, angle_deg=20.0,
                                 noise_sigma=0.0, seed=1)  # fmt: skip
    border = np.ones(sharp.shape[1:3], bool)
    border[12:-12, 12:-12] = False
    gains = {}
    for boundary in ("mirror", "unknown"):
        restored = deblur_video_motion(blurred, grid=1, boundary=boundary)
        gains[boundary] = (mean_frame_psnr([(restored[:, border], sharp[:, border])])
                           - mean_frame_psnr([(blurred[:, border], sharp[:, border])]))  # fmt: skip
    assert gains["unknown"] > gains["mirror"] + 1.0
    assert gains["unknown"] > 0.5


def test_a_640x480_video_is_deblurred() -> None:
    """7-Scenes' frame size: 18 px of motion per frame, no noise."""
    blurred, sharp = photo_video(skimage.data.coffee(), frames=4, step_px=2.0, angle_deg=20.0,
                                 size=(640, 480), noise_sigma=0.0, seed=1)  # fmt: skip
    restored = deblur_video_motion(blurred)
    assert mean_frame_psnr([(restored, sharp)]) - mean_frame_psnr([(blurred, sharp)]) > 0.5


def test_deblur_video_cli_restores_a_folder_by_the_videos_motion(
    tmp_path, capsys: pytest.CaptureFixture
) -> None:
    blurred, sharp = photo_video(skimage.data.coffee(), frames=4, step_px=1.0, angle_deg=20.0,
                                 noise_sigma=0.0, seed=1)  # fmt: skip
    folder = tmp_path / "video"
    folder.mkdir()
    for index, frame in enumerate(blurred):
        cv2.imwrite(str(folder / f"frame-{index:03d}.png"), frame[..., ::-1])

    def restored(name: str) -> np.ndarray:
        return np.stack([cv2.imread(str(tmp_path / name / f"frame-{i:03d}.png"))[..., ::-1]
                         for i in range(4)])  # fmt: skip

    assert main(["deblur-video", str(folder), str(tmp_path / "read"), "--method", "motion"]) == 0
    np.testing.assert_array_equal(restored("read"), deblur_video_motion(blurred, None))
    assert mean_frame_psnr([(restored("read"), sharp)]) > mean_frame_psnr([(blurred, sharp)])
    assert main(["deblur-video", str(folder), str(tmp_path / "fixed"), "--method", "motion",
                 "--exposure-share", "1"]) == 0  # fmt: skip
    np.testing.assert_array_equal(restored("fixed"), deblur_video_motion(blurred, 1.0))
    assert main(["deblur-video", str(folder), str(tmp_path / "one"), "--method", "motion",
                 "--grid", "1"]) == 0  # fmt: skip
    np.testing.assert_array_equal(restored("one"), deblur_video_motion(blurred, None, grid=1))
    assert main(["deblur-video", str(folder), str(tmp_path / "mirror"), "--method", "motion",
                 "--grid", "1", "--boundary", "mirror"]) == 0  # fmt: skip
    np.testing.assert_array_equal(
        restored("mirror"), deblur_video_motion(blurred, None, grid=1, boundary="mirror")
    )
    assert not np.array_equal(restored("mirror"), restored("one"))
    assert main(["deblur-video", str(folder), str(tmp_path / "default")]) == 0  # motion-network
    np.testing.assert_array_equal(restored("default"), MotionNetworkRestorer()(blurred))
    assert mean_frame_psnr([(restored("default"), sharp)]) > mean_frame_psnr([(blurred, sharp)])
    assert main(["deblur-video", str(folder), str(tmp_path / "chain"), "--grid", "1",
                 "--exposure-share", "1"]) == 0  # fmt: skip
    np.testing.assert_array_equal(restored("chain"), VideoRestorer(MOTION_CHECKPOINT)(
        deblur_video_motion(blurred, 1.0, grid=1)))  # fmt: skip
    capsys.readouterr()
    for wrong, message in (
        (["--method", "motion", "--exposure-share", "0"], "must be > 0"),
        (["--method", "network", "--exposure-share", "0.5"], "is for --method motion-network"),
        (["--method", "motion", "--checkpoint", "x.pt"], "--method motion has none"),
        (["--grid", "0"], "--grid must be >= 1"),
        (["--method", "network", "--grid", "2"], "--grid is for --method motion-network"),
        (["--method", "network", "--boundary", "mirror"], "--boundary is for"),
    ):
        assert main(["deblur-video", str(folder), str(tmp_path / "o2"), *wrong]) == 1
        assert message in capsys.readouterr().err
    assert not (tmp_path / "o2").exists()


def test_the_kernel_of_a_curved_path_points_the_way_the_image_moved() -> None:
    """Blur along a bending path, noise-free: the kernels from the video's motion restore the
    frames better than the same kernels turned by 180° (a straight line could not tell)."""
    photo = skimage.data.astronaut().astype(np.float32) / 255

    def view(x: float, y: float) -> np.ndarray:
        matrix = np.float32([[1, 0, x - 150], [0, 1, y - 150]])
        return cv2.warpAffine(photo, matrix, (160, 120), flags=cv2.INTER_LINEAR,
                              borderMode=cv2.BORDER_REFLECT)  # fmt: skip

    def position(time: float) -> tuple[float, float]:
        return 3.0 * time + 0.5 * time**2, 1.2 * time**2

    blurred, sharp = [], []
    for frame in range(6):
        times = frame - 2.5 + np.linspace(-0.5, 0.5, 17)
        blurred.append(np.mean([view(*position(t)) for t in times], axis=0))
        sharp.append(view(*position(frame - 2.5)))
    blurred, sharp = (np.uint8(np.clip(np.array(v) * 255 + 0.5, 0, 255)) for v in (blurred, sharp))
    motion = video_motion_kernels(blurred)
    scores = {}
    for name, turn in (("as measured", False), ("turned", True)):
        restored = [wiener_deconvolve(frame / 255, kernel[::-1, ::-1] if turn else kernel,
                                      nsr=0.1, regulariser="gradient")
                    for frame, kernel in zip(blurred, motion.kernels, strict=True)]  # fmt: skip
        restored = np.uint8(np.clip(np.array(restored) * 255 + 0.5, 0, 255))
        scores[name] = mean_frame_psnr([(restored[1:-1], sharp[1:-1])])  # inner frames
    assert scores["as measured"] > scores["turned"] + 0.5


def test_a_kernel_larger_than_the_frame_passes_through() -> None:
    # An 8-row strip panned 12 px per frame: its kernels (15 x 15) are taller than the strip.
    strip = cv2.resize(skimage.data.astronaut(), (64, 8), interpolation=cv2.INTER_AREA)
    frames = np.stack([np.roll(strip, 12 * index, axis=1) for index in range(3)])
    motion = video_motion_kernels(frames)
    assert all(kernel.shape[0] > 8 for kernel in motion.kernels)
    assert min(motion.lengths_px) > 10
    np.testing.assert_array_equal(deblur_video_motion(frames), frames)


@pytest.mark.parametrize("exposure", [None, 5, 17])
def test_the_photo_videos_true_paths_are_the_blur_that_made_them(exposure: int | None) -> None:
    """Convolving a sharp frame in linear light with the kernel of its true exposure path gives
    the blurred frame (up to the interpolation of the sub-frames); a path turned by 90 degrees
    does not; so also with 5 or 17 of every 9 sub-frames' time exposed. The middle sub-frames'
    positions move as frame_shifts measures; an even exposure has no middle and is refused."""
    step, angle = 1.0, 20.0
    blurred, sharp = photo_video(skimage.data.coffee(), frames=4, step_px=step,
                                 angle_deg=angle, noise_sigma=0.0, seed=1,
                                 exposure_subframes=exposure)  # fmt: skip
    positions = photo_video_motion(4, 9, step, angle, exposure)
    assert positions.shape == (4, exposure or 9, 2)
    middle = positions[:, (exposure or 9) // 2]
    np.testing.assert_array_equal(middle, photo_video_motion(4, 9, step, angle)[:, 4])
    with pytest.raises(ValueError, match="odd"):
        photo_video(skimage.data.coffee(), frames=2, exposure_subframes=4)
    np.testing.assert_allclose(frame_shifts(sharp), np.diff(middle, axis=0), atol=0.3)
    inner = np.s_[16:-16, 16:-16]  # away from the content the pan brings in
    for frame in range(4):
        path = positions[frame] - middle[frame]
        linear = srgb_to_linear(sharp[frame] / 255.0)

        def error(path: np.ndarray, frame: int = frame, linear: np.ndarray = linear) -> float:
            kernel = trajectory_kernel(path, origin=np.zeros(2))[::-1, ::-1]  # convolution
            reblurred = linear_to_srgb(cv2.filter2D(linear, -1, kernel)) * 255
            return float(np.sqrt(np.mean((reblurred[inner] - blurred[frame][inner]) ** 2)))

        assert error(path) < 3.0 and 2 * error(path) < error(path[:, ::-1] * [1, -1])


def test_deblur_by_kernels_is_the_restoration_step_of_deblur_video_motion() -> None:
    blurred, sharp = photo_video(skimage.data.coffee(), frames=4, step_px=1.0, angle_deg=20.0,
                                 noise_sigma=0.0, seed=1)  # fmt: skip
    motion = video_motion_kernels(blurred)
    np.testing.assert_array_equal(
        deblur_by_kernels(blurred, motion.kernels, motion.lengths_px),
        deblur_video_motion(blurred, grid=1),
    )
    positions = photo_video_motion(4, 9, 1.0, 20.0)
    true_paths = positions - positions[:, 4:5]
    told = deblur_by_kernels(blurred, [trajectory_kernel(path, origin=np.zeros(2))
                                       for path in true_paths],
                             np.array([path_length(path) for path in true_paths]))  # fmt: skip
    assert mean_frame_psnr([(told, sharp)]) > mean_frame_psnr([(blurred, sharp)]) + 0.5
    short = np.full(4, 0.5)  # paths under MIN_PATH_PX: passed through
    np.testing.assert_array_equal(deblur_by_kernels(blurred, motion.kernels, short), blurred)
    with pytest.raises(ValueError, match="one kernel and one length per frame"):
        deblur_by_kernels(blurred, motion.kernels[:3], motion.lengths_px)
    with pytest.raises(ValueError, match="min_weight"):
        deblur_by_kernels(blurred, motion.kernels, motion.lengths_px, min_weight=0.0)


def test_the_regularisers_weight_is_the_frames_noise_times_a_factor_with_a_floor() -> None:
    """Each frame is deconvolved at max(weight_per_noise * its estimated noise, min_weight):
    above the floor the factor sets the weight, below it the floor does."""
    blurred, _ = photo_video(skimage.data.coffee(), frames=3, step_px=1.0, angle_deg=20.0,
                             noise_sigma=0.02, seed=1)  # fmt: skip
    motion = video_motion_kernels(blurred)
    sigma = estimate_noise_sigma(blurred[1])
    assert 0.015 < sigma < 0.025
    restored = deblur_by_kernels(blurred, motion.kernels, motion.lengths_px, min_weight=1e-4,
                                 weight_per_noise=7.0)  # fmt: skip
    direct = wiener_deconvolve(blurred[1], motion.kernels[1], 7.0 * sigma, "gradient", "unknown")
    assert np.abs(restored[1].astype(int) - direct).max() <= 1
    floored = deblur_by_kernels(blurred, motion.kernels, motion.lengths_px, min_weight=0.5,
                                weight_per_noise=7.0)  # fmt: skip
    direct = wiener_deconvolve(blurred[1], motion.kernels[1], 0.5, "gradient", "unknown")
    assert np.abs(floored[1].astype(int) - direct).max() <= 1
    assert np.abs(floored[1].astype(int) - restored[1]).mean() > 1


def _turned_centre_motion(frames: int, step: float, angle: float, roll: float) -> np.ndarray:
    """How the content at the frame's centre moves from frame to frame in a photo video whose
    camera also turns by ``roll`` degrees per sub-frame: the pan's step turned by the roll of
    the sub-frame it arrives at."""
    middle = photo_video_motion(frames, 9, step, angle)[:, 4]
    arrivals = 9 * np.arange(1, frames) + 4
    moves = zip(arrivals, np.diff(middle, axis=0), strict=True)
    return np.array([cv2.getRotationMatrix2D((0.0, 0.0), roll * n, 1.0)[:, :2] @ move
                     for n, move in moves])  # fmt: skip


def test_a_pair_that_phase_correlation_mislocks_is_measured_again_from_its_neighbour() -> None:
    """A camera that also turns about its optical axis: phase correlation locks onto a wrong
    peak between the first two frames (about 20 px off) and ECC climbs from there to a wrong
    optimum; started again from the next pair's displacement it finds the content's motion."""
    blurred, _ = photo_video(skimage.data.chelsea(), frames=8, step_px=1.0, angle_deg=74.0,
                             noise_sigma=0.0, seed=2, roll_deg=0.1)  # fmt: skip
    true = _turned_centre_motion(8, 1.0, 74.0, 0.1)
    errors = np.linalg.norm(frame_shifts(blurred) - true, axis=1)
    assert errors.max() < 1.0


def test_a_pair_without_structure_takes_its_neighbours_displacement() -> None:
    """A flat frame in a panning video: ECC aligns neither pair it belongs to from any start,
    so both take the displacement of a neighbouring pair that was aligned, not phase
    correlation's guess on a flat frame."""
    frames = _panned((-2.0, -1.0), frames=5)
    frames[1] = 128
    shifts = frame_shifts(frames)
    np.testing.assert_allclose(shifts[2:], np.tile([-2.0, -1.0], (2, 1)), atol=0.15)
    assert np.abs(shifts[:2]).max() < 5  # a neighbour's, not tens of px


def test_frame_warps_see_a_turn_about_the_optical_axis() -> None:
    """Sharp frames turned by 1 degree each about their centre: the affine warps hold that turn,
    and the translations they start from are refused as a shape mismatch when miscounted."""
    photo = cv2.resize(skimage.data.astronaut(), (320, 320), interpolation=cv2.INTER_AREA)
    frames = np.stack([cv2.warpAffine(photo, cv2.getRotationMatrix2D((160, 160), turn, 1.0),
                                      (320, 320))[100:220, 80:240]
                       for turn in (0.0, 1.0, 2.0)])  # fmt: skip
    warps = frame_warps(frames, frame_shifts(frames))
    assert warps.shape == (2, 2, 3)
    # a counter-clockwise turn on screen (y down) is a negative angle of the warp's rotation
    angles = np.degrees(np.arctan2(warps[:, 1, 0], warps[:, 0, 0]))
    np.testing.assert_allclose(angles, -1.0, atol=0.15)
    # the content at the crop's top-left corner moves as the turn about the photo's centre does
    corner = np.array([0.0, 0.0])
    turn = cv2.getRotationMatrix2D((160, 160), 1.0, 1.0)
    offset = np.array([80.0, 100.0])  # the crop's corner in the photo
    arrived = turn[:, :2] @ (corner + offset) + turn[:, 2] - offset
    np.testing.assert_allclose(warps[0, :, :2] @ corner + warps[0, :, 2], arrived, atol=0.3)
    with pytest.raises(ValueError, match="shifts must be"):
        frame_warps(frames, np.zeros((3, 2)))


@pytest.mark.parametrize(("size", "step"), [((160, 120), 1.0), ((640, 480), 4.0)])
def test_frame_warps_keep_a_turn_at_any_frame_size(size: tuple[int, int], step: float) -> None:
    """A GoPro-style video panning and turning 0.3 degrees per sub-frame (2.7 degrees per frame
    of 9 sub-frames), the pan scaled with the frame: at 640x480 as at 160x120 every pair keeps
    its affine warp and the turn, though there the translation departs from the centre's
    displacement by several px."""
    blurred, _ = photo_video(skimage.data.coffee(), frames=4, step_px=step, angle_deg=20.0,
                             size=size, noise_sigma=0.0, seed=1, roll_deg=0.3)  # fmt: skip
    warps = frame_warps(blurred, frame_shifts(blurred))
    angles = np.degrees(np.arctan2(warps[:, 1, 0], warps[:, 0, 0]))
    np.testing.assert_allclose(angles, -2.7, atol=0.15)


def test_local_kernels_where_the_image_moves_differently_across_the_frame() -> None:
    """With a grid of one point, the frame's centre, the kernels are video_motion_kernels'. With
    a turn about the optical axis every point of a 3 x 3 grid gets its own, and deblurring with
    them gains more than with one kernel per frame."""
    pan, _ = photo_video(skimage.data.coffee(), frames=4, step_px=1.0, angle_deg=20.0,
                         noise_sigma=0.0, seed=1)  # fmt: skip
    motion = local_motion_kernels(pan, grid=1)
    assert motion.grid == 1 and motion.lengths_px.shape == (4, 1)
    np.testing.assert_array_equal(motion.lengths_px[:, 0], video_motion_kernels(pan).lengths_px)
    np.testing.assert_array_equal(motion.points, [[80.0, 60.0]])
    blurred, sharp = photo_video(skimage.data.astronaut(), frames=8, step_px=1.0,
                                 noise_sigma=0.0, seed=0, roll_deg=0.3)  # fmt: skip
    motion = local_motion_kernels(blurred)
    assert motion.grid == 3 and motion.lengths_px.shape == (8, 9)
    np.testing.assert_allclose(motion.points, grid_points(120, 160, 3))
    # the turn adds to the pan on one side of the frame and takes from it on the other
    assert motion.lengths_px.std(axis=1).min() > 0.5
    before = mean_frame_psnr([(blurred, sharp)])
    restored = deblur_video_motion(blurred)
    local = mean_frame_psnr([(restored, sharp)]) - before
    single = mean_frame_psnr([(deblur_video_motion(blurred, grid=1), sharp)]) - before
    assert local > single + 0.3 and local > 0.5
    # frames restored one at a time or three at once, on threads: the same video
    for threads in (1, 3):
        np.testing.assert_array_equal(deblur_video_motion(blurred, threads=threads), restored)
    with pytest.raises(ValueError, match="threads must be >= 1"):
        deblur_video_motion(blurred, threads=0)
    with pytest.raises(ValueError, match="grid"):
        local_motion_kernels(blurred, grid=0)


def test_local_kernels_that_agree_restore_as_one_kernel_does() -> None:
    """Blending the same kernel at every grid point (the grid kept, ``agreement_l1=None``) gives
    one kernel's restoration (the blend's weights sum to 1): up to the last rounding with mirror
    boundaries, which restore the whole frame per point; with unknown boundaries, where each
    point restores its own tile, up to the unfinished conjugate-gradient solve (to within 3 grey
    levels after 40 steps, where tiles and frame solve the same problem); counts that do not
    match are refused."""
    blurred, _ = photo_video(skimage.data.coffee(), frames=3, step_px=1.0, angle_deg=20.0,
                             noise_sigma=0.0, seed=1)  # fmt: skip
    motion = video_motion_kernels(blurred)
    nine = np.repeat(motion.lengths_px[:, None], 9, axis=1)
    same = [[kernel] * 9 for kernel in motion.kernels]
    single = deblur_by_kernels(blurred, motion.kernels, motion.lengths_px, boundary="mirror")
    blended = deblur_by_local_kernels(blurred, same, nine, 3, boundary="mirror",
                                      agreement_l1=None)  # fmt: skip
    assert np.abs(blended.astype(int) - single).max() <= 1
    for steps, largest, mean in ((10, 10, 0.3), (40, 3, 0.1)):
        single = deblur_by_kernels(blurred, motion.kernels, motion.lengths_px, iterations=steps)
        blended = deblur_by_local_kernels(blurred, same, nine, 3, iterations=steps,
                                          agreement_l1=None)  # fmt: skip
        difference = np.abs(blended.astype(int) - single)
        assert difference.max() <= largest and difference.mean() < mean
    # only the top-left point's kernel deblurs: the frame changes where that point's weight
    # reaches (up to the next points, at x = 80 and y = 60) and nowhere else
    lengths = np.zeros((3, 9))
    lengths[:, 0] = motion.lengths_px
    top_left = deblur_by_local_kernels(blurred, [[kernel] * 9 for kernel in motion.kernels],
                                       lengths, 3, agreement_l1=None)  # fmt: skip
    changed = np.any(top_left != blurred, axis=(0, 3))
    assert changed[:10, :10].all() and not changed[60:, :].any() and not changed[:, 80:].any()
    with pytest.raises(ValueError, match="grid point"):
        deblur_by_local_kernels(blurred, [[kernel] * 4 for kernel in motion.kernels],
                                np.repeat(motion.lengths_px[:, None], 4, axis=1), 3)  # fmt: skip


def test_the_kernel_disagreement_of_a_grid() -> None:
    """0 for equal kernels (also of different sizes, centred alike), 2 for kernels that share no
    pixel, in between for a line against a longer one; what is not a kernel is refused."""
    delta = np.ones((1, 1))
    line = trajectory_kernel(np.array([[-2.0, 0.0], [2.0, 0.0]]), origin=np.zeros(2))
    longer = trajectory_kernel(np.array([[-3.0, 0.0], [3.0, 0.0]]), origin=np.zeros(2))
    assert kernel_disagreement([delta, np.pad(delta, 2)]) == 0.0
    assert kernel_disagreement([line]) == 0.0
    assert kernel_disagreement([delta, np.roll(np.pad(delta, 1), 1, axis=1)]) == pytest.approx(2)
    assert 0.1 < kernel_disagreement([line, longer, line]) < 1.0
    across, down = np.full((1, 5), 0.2), np.full((5, 1), 0.2)  # share the centre pixel only
    assert kernel_disagreement([across, down]) == pytest.approx(1.6)
    assert kernel_disagreement([line, 3 * line]) == pytest.approx(0.0)  # each divided by its sum
    with pytest.raises(ValueError, match="odd sides"):
        kernel_disagreement([np.ones((2, 2)) / 4])
    with pytest.raises(ValueError, match="odd sides"):
        kernel_disagreement([])
    with pytest.raises(ValueError, match="sum to more than 0"):
        kernel_disagreement([line, np.zeros((3, 3))])


def test_a_frame_whose_kernels_agree_is_restored_once_with_the_middle_kernel() -> None:
    """Within ``agreement_l1`` a frame takes the middle point's kernel over the whole frame, as
    one kernel per frame does (exactly); beyond it the frame keeps its grid; a turning camera's
    kernels disagree beyond the default; a negative tolerance is refused."""
    blurred, _ = photo_video(skimage.data.coffee(), frames=3, step_px=1.0, angle_deg=20.0,
                             noise_sigma=0.0, seed=1)  # fmt: skip
    motion = video_motion_kernels(blurred)
    nine = np.repeat(motion.lengths_px[:, None], 9, axis=1)
    others = [VERTICAL_LINE] * 4
    mixed = [[*others, kernel, *others] for kernel in motion.kernels]  # the middle one differs
    single = deblur_by_kernels(blurred, motion.kernels, motion.lengths_px)
    np.testing.assert_array_equal(deblur_by_local_kernels(blurred, mixed, nine, 3,
                                                          agreement_l1=2.0), single)  # fmt: skip
    kept = deblur_by_local_kernels(blurred, mixed, nine, 3, agreement_l1=0.3)
    np.testing.assert_array_equal(
        kept, deblur_by_local_kernels(blurred, mixed, nine, 3, agreement_l1=None)
    )
    assert np.abs(kept.astype(int) - single).max() > 10
    turning, _ = photo_video(skimage.data.astronaut(), frames=4, step_px=1.0, noise_sigma=0.0,
                             seed=0, roll_deg=0.3)  # fmt: skip
    assert min(kernel_disagreement(kernels) for kernels in
               local_motion_kernels(turning).kernels) > AGREEMENT_L1  # fmt: skip
    with pytest.raises(ValueError, match="agreement_l1"):
        deblur_video_motion(blurred, agreement_l1=-0.1)


def test_a_pan_takes_one_kernel_per_frame_by_default_and_an_even_grid_its_middle_point() -> None:
    """With the default tolerance most of a pan's frames take one kernel (the restoration of
    ``agreement_l1=2``, every frame one kernel) and the others keep their grid (that of
    ``agreement_l1=None``); on a 2 x 2 grid the middle point is row 1, column 1."""
    blurred, _ = photo_video(skimage.data.coffee(), frames=6, step_px=1.0, angle_deg=20.0,
                             noise_sigma=0.0, seed=1)  # fmt: skip
    agree = np.array([kernel_disagreement(kernels) <= AGREEMENT_L1
                      for kernels in local_motion_kernels(blurred).kernels])  # fmt: skip
    assert agree.mean() >= 0.8
    default = deblur_video_motion(blurred)
    np.testing.assert_array_equal(
        default[agree], deblur_video_motion(blurred, agreement_l1=2.0)[agree]
    )
    np.testing.assert_array_equal(
        default[~agree], deblur_video_motion(blurred, agreement_l1=None)[~agree]
    )
    motion = video_motion_kernels(blurred)
    others = VERTICAL_LINE
    four = [[others, others, others, kernel] for kernel in motion.kernels]
    np.testing.assert_array_equal(
        deblur_by_local_kernels(blurred, four, np.repeat(motion.lengths_px[:, None], 4, axis=1),
                                2, agreement_l1=2.0),
        deblur_by_kernels(blurred, motion.kernels, motion.lengths_px),
    )  # fmt: skip


def test_motion_network_restorer_removes_blur_the_network_alone_leaves() -> None:
    """On a noisy pan the deconvolution by the video's motion, then the network, restores more
    than the network alone and than the deconvolution alone; the restorer survives pickling
    (worker processes receive it so) unchanged."""
    blurred, sharp = photo_video(skimage.data.coffee(), frames=6, step_px=2.0, angle_deg=20.0,
                                 noise_sigma=0.01, seed=3)  # fmt: skip
    restorer = MotionNetworkRestorer()
    chained = restorer(blurred)
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(restorer))(blurred), chained)
    scores = {name: mean_frame_psnr([(video, sharp)]) for name, video in (
        ("blurred", blurred), ("chained", chained),
        ("network", VideoRestorer(DEFAULT_CHECKPOINT)(blurred)),
        ("motion", deblur_video_motion(blurred, None)))}  # fmt: skip
    assert scores["chained"] > max(scores["network"], scores["motion"]) > scores["blurred"]
