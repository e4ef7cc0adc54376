"""Kernels, the blur model, the spectrum and blind estimation of linear motion blur."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
import skimage.data
from scipy.stats import spearmanr

from blurloc.blur import (
    LengthModel,
    blur_features,
    blur_image,
    default_length_model,
    estimate_motion_blur,
    fit_length_model,
    log_power_spectrum,
    motion_kernel,
    shake_path,
    to_gray,
    trajectory_kernel,
)
from blurloc.blur.features import edge_widths
from blurloc.experiments.estimation import angle_error_deg


@pytest.mark.parametrize(
    ("length", "angle"), [(9.0, 0.0), (12.5, 30.0), (20.0, 90.0), (7.3, 135.0)]
)
def test_motion_kernel_geometry(length: float, angle: float) -> None:
    kernel = motion_kernel(length, angle)
    assert kernel.sum() == pytest.approx(1.0)
    assert kernel.shape[0] % 2 == 1 and kernel.shape[0] == kernel.shape[1]
    rows, cols = np.indices(kernel.shape)
    centre = kernel.shape[0] // 2
    x, y = cols - centre, -(rows - centre)  # y up
    assert (kernel * x).sum() == pytest.approx(0, abs=1e-9)  # centred
    assert (kernel * y).sum() == pytest.approx(0, abs=1e-9)
    # second moment along the direction: a uniform segment of length L has variance L^2 / 12
    # (plus 1/6 from the bilinear splat)
    theta = np.radians(angle)
    along = x * np.cos(theta) + y * np.sin(theta)
    across = -x * np.sin(theta) + y * np.cos(theta)
    assert (kernel * along**2).sum() == pytest.approx(length**2 / 12, rel=0.05, abs=0.2)
    assert (kernel * across**2).sum() < 0.35


def test_trajectory_kernel_of_a_straight_path_is_the_linear_kernel() -> None:
    path = np.column_stack([np.linspace(-6, 6, 50), np.zeros(50)])
    np.testing.assert_allclose(
        trajectory_kernel(path, size=15), motion_kernel(12, 0, size=15), atol=2e-3
    )
    # trajectories are in image coordinates (y down): right-and-down is -45°, i.e. 135° (y up)
    diagonal = np.column_stack([np.linspace(-4, 4, 30), np.linspace(-4, 4, 30)])
    np.testing.assert_allclose(
        trajectory_kernel(diagonal, size=15), motion_kernel(8 * np.sqrt(2), 135, size=15), atol=3e-3
    )


def test_shake_paths_span_their_extent_and_differ_in_shape() -> None:
    rng = np.random.default_rng(3)
    paths = [shake_path(extent, rng) for extent in (11.0, 17.0, 25.0)]
    for path, extent in zip(paths, (11.0, 17.0, 25.0), strict=True):
        assert path.shape == (500, 2)
        np.testing.assert_allclose(np.ptp(path, axis=0).max(), extent)
        kernel = trajectory_kernel(path)
        assert kernel.shape[0] <= 2 * extent + 5 and np.isclose(kernel.sum(), 1.0)
    # equal speed along the path, but not a straight segment: the travelled length exceeds the
    # bounding box's diagonal for most draws (camera shake turns)
    bends = [np.linalg.norm(np.diff(p, axis=0), axis=1).sum() / np.linalg.norm(np.ptp(p, axis=0))
             for p in (shake_path(15.0, rng) for _ in range(20))]  # fmt: skip
    assert np.median(bends) > 1.2
    assert not np.allclose(shake_path(15.0, np.random.default_rng(0)),
                           shake_path(15.0, np.random.default_rng(1)))  # fmt: skip


def test_blur_model_wrap_equals_fft_convolution() -> None:
    rng = np.random.default_rng(0)
    image = rng.random((32, 40))
    kernel = motion_kernel(7, 20)
    blurred = blur_image(image, kernel, boundary="wrap")
    padded = np.zeros_like(image)
    k = kernel.shape[0]
    padded[:k, :k] = kernel
    padded = np.roll(padded, (-(k // 2), -(k // 2)), axis=(0, 1))
    expected = np.real(np.fft.ifft2(np.fft.fft2(image) * np.fft.fft2(padded)))
    np.testing.assert_allclose(blurred, expected, atol=1e-10)


def test_blur_model_adds_noise_of_the_given_sigma() -> None:
    image = np.full((200, 200), 0.5)
    noisy = blur_image(image, motion_kernel(5, 0), 0.02, rng=np.random.default_rng(1))
    assert noisy.std() == pytest.approx(0.02, rel=0.05)


def test_spectrum_shows_sinc_zeros() -> None:
    image = to_gray(skimage.data.camera())
    blurred = blur_image(image, motion_kernel(16, 0))
    spectrum = log_power_spectrum(blurred)
    centre = spectrum.shape[0] // 2
    row = spectrum[centre - 3 : centre + 4].mean(axis=0)  # along the horizontal motion
    zero = centre + spectrum.shape[0] // 16  # first zero at N / L bins
    assert row[zero] < row[zero - 8] - 2 and row[zero] < row[zero + 8] - 1


@pytest.mark.parametrize("noise", [0.0, 0.005])
def test_blind_estimate_of_linear_blur(noise: float) -> None:
    rng = np.random.default_rng(42)
    images = [to_gray(getattr(skimage.data, n)()) for n in ("camera", "astronaut", "coffee")]
    angle_errors, length_errors = [], []
    for index in range(9):
        length, angle = rng.uniform(7, 27), rng.uniform(0, 180)
        blurred = blur_image(images[index % 3], motion_kernel(length, angle), noise, rng=rng)
        estimate = estimate_motion_blur(blurred)
        angle_errors.append(angle_error_deg(estimate.angle_deg, angle))
        length_errors.append(abs(estimate.length_px - length))
        assert 0 <= estimate.angle_deg < 180
    assert np.median(angle_errors) <= 1.5
    assert np.median(length_errors) <= 1.0


def test_sinc_refinement_is_kept_only_within_the_agreement_band() -> None:
    image = blur_image(to_gray(skimage.data.camera()), motion_kernel(20, 40), 0.002,
                       rng=np.random.default_rng(5))  # fmt: skip
    features = blur_features(image)
    refined = estimate_motion_blur(image, features=features)
    assert refined.fit > 0 and abs(refined.length_px - 20) < 1  # the sinc zeros are read
    coarse = estimate_motion_blur(image, features=features, agreement=(10.0, 20.0))
    assert coarse.fit == 0 and coarse.angle_deg == features.angle_deg  # outside the band: coarse
    assert coarse.length_px == pytest.approx(default_length_model().predict(features.values)[0]
                                             * features.scale)  # fmt: skip


@pytest.mark.parametrize("name", ["camera", "coffee"])
def test_sinc_refinement_does_not_depend_on_the_frame_size(name: str) -> None:
    """An 8 px line on a photograph and the same blur area-averaged to half size (4 px): both
    are read from the sinc zeros, and the half-size length is half the full-size one."""
    blurred = blur_image(to_gray(getattr(skimage.data, name)()), motion_kernel(8, 0), 0.0)
    half = cv2.resize(blurred, None, fx=0.5, fy=0.5, interpolation=cv2.INTER_AREA)
    full_estimate, half_estimate = estimate_motion_blur(blurred), estimate_motion_blur(half)
    assert full_estimate.fit > 0 and half_estimate.fit > 0
    assert half_estimate.length_px == pytest.approx(full_estimate.length_px / 2, rel=0.05)
    assert half_estimate.length_px == pytest.approx(4.0, abs=0.25)


def test_small_trajectory_blur_in_small_frames() -> None:
    """Slightly bent camera paths of 2-10 px on 160x120 photographs, noise σ = 0.01, 8 bits."""
    rng = np.random.default_rng(1)
    names = ("astronaut", "coffee", "chelsea", "rocket", "brick", "gravel")
    extents, lengths, angle_errors = [], [], []
    for index in range(18):
        photo = getattr(skimage.data, names[index % len(names)])()
        photo = photo if photo.ndim == 3 else np.dstack([photo] * 3)
        frame = cv2.resize(photo, (160, 120), interpolation=cv2.INTER_AREA) / 255.0
        length, angle = rng.uniform(2, 10), rng.uniform(0, 180)
        t = np.linspace(-0.5, 0.5, 20)
        path = length * np.column_stack([t * np.cos(np.radians(angle)),
                                         -t * np.sin(np.radians(angle)) + 0.1 * t**2])  # fmt: skip
        blurred = blur_image(frame, trajectory_kernel(path), 0.01, rng=rng)
        estimate = estimate_motion_blur(np.round(np.clip(blurred, 0, 1) * 255).astype(np.uint8))
        extents.append(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
        lengths.append(estimate.length_px)
        angle_errors.append(angle_error_deg(estimate.angle_deg, angle))
    assert np.median(np.abs(np.subtract(lengths, extents))) <= 1.0
    assert np.median(angle_errors) <= 10.0
    assert spearmanr(lengths, extents).statistic >= 0.6


def test_length_model_fits_a_smooth_rule_and_round_trips(tmp_path) -> None:
    rng = np.random.default_rng(0)
    features = rng.normal(size=(400, 6))
    extents = 3.0 + 2.0 * np.tanh(features[:, 0]) + features[:, 1] ** 2 / 2
    model = fit_length_model(features[:300], extents[:300], steps=500)
    held_out = np.abs(model.predict(features[300:]) - extents[300:])
    assert np.median(held_out) < 0.25 * np.median(np.abs(extents[300:] - extents[:300].mean()))
    model.save(tmp_path / "model")  # numpy's rule: .npz is added
    assert [p.name for p in tmp_path.iterdir()] == ["model.npz"]  # written whole, no leftovers
    np.testing.assert_array_equal(
        LengthModel.load(tmp_path / "model.npz").predict(features), model.predict(features)
    )


def test_shipped_length_model_reads_the_features() -> None:
    model = default_length_model()
    assert model.mean.size == blur_features(np.zeros((120, 160))).values.size
    assert all(layers[-1][0].shape[0] == 1 for layers in model.members)


def test_edge_widths_grow_with_blur_across_the_edges_only() -> None:
    steps = np.zeros((96, 128), np.float32)
    steps[:, 40:] = 0.8  # vertical edges at columns 40 and (wrapped) 0
    steps[:, 88:] = 0.2
    across = blur_image(steps, motion_kernel(8, 0)).astype(np.float32)  # horizontal blur
    along = blur_image(steps, motion_kernel(8, 90)).astype(np.float32)  # vertical blur
    median_17 = 11  # log median width, 17 px windows
    sharp, wide, same = (edge_widths(image, 0.0)[median_17] for image in (steps, across, along))
    assert np.exp(sharp) < 2.5 and 6.0 < np.exp(wide) < 11.0  # a step spans 2 px of Sobel
    assert abs(same - sharp) < 0.1
    assert not edge_widths(np.full((32, 32), 0.5, np.float32), 0.0)[:15].any()  # no edges: 1 px


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: motion_kernel(0, 10), "length must be > 0"),
        (lambda: motion_kernel(-3, 10), "length must be > 0"),
        (lambda: blur_image(np.ones((8, 8)), motion_kernel(20, 0)), "larger than the image"),
        (lambda: blur_image(np.ones((8, 8)), np.array([[1.0, -1.0]])), "sums to 0"),
        (lambda: blur_image(np.full((8, 8), np.nan), motion_kernel(3, 0)), "NaN or inf"),
        (lambda: blur_image(np.ones((1, 1)), np.ones((1, 1))), "at least 2x2"),
        (lambda: blur_image(np.ones((0, 5)), np.ones((1, 1))), "at least 2x2"),
        (lambda: blur_image(np.ones((8, 8), np.int64), motion_kernel(3, 0)), "unsupported dtype"),
        (lambda: blur_image(np.ones((8, 8)), motion_kernel(3, 0), boundary="zero"), "boundary"),
        (lambda: estimate_motion_blur(np.ones((10, 500))), "too small"),
        (lambda: shake_path(0.0, np.random.default_rng(0)), "extent_px must be > 0"),
    ],
    ids=[
        "zero-length",
        "negative-length",
        "kernel-too-large",
        "zero-sum",
        "nan",
        "one-pixel",
        "empty",
        "int64",
        "bad-boundary",
        "too-small-to-estimate",
        "zero-shake",
    ],
)
def test_bad_input_is_refused(call, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        call()


def test_detection_rates_count_each_class() -> None:
    from blurloc.blur import detection_rates

    scores = np.array([0.5, 2.0, 3.0, 1.0, 0.2, 2.5])
    blurred = np.array([False, True, True, True, False, False])
    flagged, passed, balanced = detection_rates(scores, blurred, 1.5)
    assert flagged == pytest.approx(2 / 3) and passed == pytest.approx(2 / 3)
    assert balanced == pytest.approx(2 / 3)
