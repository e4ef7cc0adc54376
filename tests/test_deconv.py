"""Inverse and Wiener deconvolution, noise estimation, and the PSNR / SSIM metrics."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
import skimage.data
from skimage.metrics import peak_signal_noise_ratio, structural_similarity

from blurloc.blur import (
    BlurEstimate,
    BlurFeatures,
    blur_image,
    motion_kernel,
    shake_path,
    to_gray,
    trajectory_kernel,
)
from blurloc.data.real import entry_path, load_pairs, part_entries
from blurloc.deconv import (
    GATE_MAX_AGREEMENT,
    GATE_MAX_LENGTH,
    GATE_MIN_ANISOTROPY,
    GATE_MIN_FIT,
    GATE_MIN_LENGTH,
    GATE_NOISE_EXPONENT,
    GATE_REFERENCE_NOISE,
    _even_dft_size,
    blind_restoration_expected_to_gain,
    ccs_pack,
    deblur_blind,
    difference_power,
    estimate_noise_sigma,
    inverse_filter,
    kernel_to_otf,
    wiener_deconvolve,
)
from blurloc.experiments.deblurring import (
    boundary_comparison,
    filter_comparison,
    frame_changes,
    nsr_curve,
)
from blurloc.experiments.wiener_oracles import frame_gains, gain_by_extent
from blurloc.metrics import FREQUENCY_BAND_EDGES, band_squared_error, psnr, ssim


def well_posed_kernel() -> np.ndarray:
    """An asymmetric shake kernel (so conj(C) and centring matter) with no spectral zeros:
    half of the exposure still, half along an L-shaped path."""
    path = trajectory_kernel(np.array([[0, 0], [5, 2], [9, 7]]))
    still = np.zeros_like(path)
    still[path.shape[0] // 2, path.shape[1] // 2] = 1.0
    return 0.5 * still + 0.5 * path


def test_noise_free_blur_is_undone_in_the_interior() -> None:
    image = to_gray(skimage.data.camera())[100:356, 100:356]
    kernel = well_posed_kernel()
    blurred = blur_image(image, kernel, boundary="reflect")
    restored = wiener_deconvolve(blurred, kernel, nsr=1e-7)
    interior = (slice(20, -20), slice(20, -20))
    quality = psnr(image[interior], restored[interior], data_range=1.0)
    assert quality >= 40.0
    mirrored = wiener_deconvolve(blurred, kernel[::-1, ::-1], nsr=1e-7)  # conj(C) <-> C
    assert psnr(image[interior], mirrored[interior], data_range=1.0) < quality - 5.0


def test_inverse_filter_undoes_a_kernel_without_zeros() -> None:
    rng = np.random.default_rng(0)
    image = rng.random((64, 64))
    kernel = well_posed_kernel()
    restored = inverse_filter(blur_image(image, kernel, boundary="reflect"), kernel)
    assert psnr(image[20:-20, 20:-20], restored[20:-20, 20:-20], 1.0) > 40


def test_wiener_beats_the_inverse_filter_under_noise() -> None:
    image = to_gray(skimage.data.astronaut())[::2, ::2]
    kernel = motion_kernel(11, 30)
    blurred = blur_image(image, kernel, 0.01, rng=np.random.default_rng(3))
    wiener = np.clip(wiener_deconvolve(blurred, kernel), 0, 1)
    inverse = np.clip(inverse_filter(blurred, kernel), 0, 1)
    assert psnr(image, wiener, 1.0) > psnr(image, blurred.clip(0, 1), 1.0) + 1.0
    assert psnr(image, wiener, 1.0) > psnr(image, inverse, 1.0) + 5.0


def test_rgb_and_dtypes_are_kept() -> None:
    image = skimage.data.coffee()[:120, :160]
    kernel = motion_kernel(5, 60)
    out = wiener_deconvolve(image, kernel, nsr=0.01)
    assert out.dtype == np.uint8 and out.shape == image.shape
    as_float = wiener_deconvolve(image.astype(np.float32) / 255, kernel, nsr=0.01)
    assert as_float.dtype == np.float32
    # per channel: the red channel alone gives the red channel of the RGB result
    red = wiener_deconvolve(image[..., 0].astype(np.float64) / 255, kernel, nsr=0.01)
    np.testing.assert_allclose(as_float[..., 0], red, atol=1e-5)


def test_difference_power_is_zero_at_the_mean_and_eight_at_the_highest_frequency() -> None:
    power = difference_power((6, 8))
    assert power.shape == (6, 5) and power.dtype == np.float32
    assert power[0, 0] == 0.0
    np.testing.assert_allclose(power[3, 4], 8.0, rtol=1e-6)
    np.testing.assert_allclose(power[1], power[5])  # -u and u respond alike
    # the squared DFT of the differences [1, -1] down the rows and along the columns
    rows = np.zeros((6, 8))
    rows[0, 0], rows[1, 0] = 1.0, -1.0
    columns = np.zeros((6, 8))
    columns[0, 0], columns[0, 1] = 1.0, -1.0
    expected = np.abs(np.fft.rfft2(rows)) ** 2 + np.abs(np.fft.rfft2(columns)) ** 2
    np.testing.assert_allclose(power, expected, atol=1e-5)


def test_gradient_regulariser_keeps_the_mean_that_a_constant_nsr_scales() -> None:
    flat = np.full((40, 48), 0.6)
    kernel = motion_kernel(9, 20)
    np.testing.assert_allclose(wiener_deconvolve(flat, kernel, 0.1, "gradient"), 0.6, atol=1e-5)
    np.testing.assert_allclose(wiener_deconvolve(flat, kernel, 0.1), 0.6 / 1.1, atol=1e-5)


def test_gradient_regulariser_undoes_noise_free_blur_and_beats_a_constant_nsr_on_a_photo() -> None:
    image = to_gray(skimage.data.camera())[100:356, 100:356]
    kernel = well_posed_kernel()
    blurred = blur_image(image, kernel, boundary="reflect")
    restored = wiener_deconvolve(blurred, kernel, 1e-7, "gradient")
    interior = (slice(20, -20), slice(20, -20))
    assert psnr(image[interior], restored[interior], data_range=1.0) >= 40.0
    # with noise, each at its best weight (an oracle over a grid): the mean is kept
    line = motion_kernel(11, 30)
    noisy = blur_image(image, line, 0.01, boundary="reflect", rng=np.random.default_rng(4))
    weights = np.logspace(-4, 0, 17)

    def best(regulariser: str) -> float:
        return max(psnr(image, np.clip(wiener_deconvolve(noisy, line, w, regulariser), 0, 1), 1.0)
                   for w in weights)  # fmt: skip

    assert best("gradient") > best("constant")


def test_blind_deblurring_with_the_gradient_regulariser() -> None:
    sharp = _photo("coffee", (320, 240))
    blurred = _uint8(blur_image(sharp, motion_kernel(15, 30), 0.01, rng=np.random.default_rng(2)))
    restored = deblur_blind(blurred, gated=False, regulariser="gradient")
    assert psnr(sharp, restored, 255.0) - psnr(sharp, blurred, 255.0) > 1.0
    assert not np.array_equal(restored, deblur_blind(blurred, gated=False, regulariser="constant"))


def test_frame_changes_count_restored_frames_and_pair_by_frame() -> None:
    def row(method: str, frame: int, value: float) -> dict:
        return {"method": method, "scene": "chess", "sequence": 1, "frame": frame,
                "psnr_db": value}  # fmt: skip

    rows = [row("blurred", 0, 30.0), row("blurred", 1, 20.0), row("blurred", 2, 25.0),
            row("gated", 1, 20.0), row("gated", 0, 31.0), row("gated", 2, 25.0),
            row("ungated", 0, 29.0), row("ungated", 1, 22.0), row("ungated", 2, 24.0)]  # fmt: skip
    gated, ungated = frame_changes(rows)
    assert gated["method"] == "gated" and (gated["frames"], gated["restored"]) == (3, 1)
    assert gated["mean_change_db"] == pytest.approx(1 / 3, abs=1e-3)
    assert gated["median_restored_db"] == 1.0 and gated["restored_with_gain"] == 1
    assert ungated["restored"] == 3 and ungated["median_restored_db"] == -1.0
    assert ungated["restored_with_gain"] == 1
    assert ungated["ci_low_db"] <= ungated["mean_change_db"] <= ungated["ci_high_db"]
    with pytest.raises(ValueError, match="no blurred row"):
        frame_changes([row("blurred", 0, 30.0), row("gated", 5, 30.0)])


def test_noise_estimate() -> None:
    image = blur_image(
        to_gray(skimage.data.camera()), motion_kernel(9, 10), 0.02, rng=np.random.default_rng(4)
    )
    assert estimate_noise_sigma(image) == pytest.approx(0.02, rel=0.15)


@pytest.mark.parametrize("channels", [None, 3])
def test_metrics_equal_scikit_image(channels: int | None) -> None:
    rng = np.random.default_rng(7)
    shape = (48, 64) if channels is None else (48, 64, 3)
    a = rng.random(shape)
    b = np.clip(a + rng.normal(0, 0.1, shape), 0, 1)
    assert psnr(a, b, 1.0) == pytest.approx(peak_signal_noise_ratio(a, b, data_range=1.0))
    expected = structural_similarity(
        a,
        b,
        data_range=1.0,
        gaussian_weights=True,
        sigma=1.5,
        use_sample_covariance=False,
        channel_axis=2 if channels else None,
    )
    assert ssim(a, b, 1.0) == pytest.approx(expected)
    uint8_a, uint8_b = (a * 255).round().astype(np.uint8), (b * 255).round().astype(np.uint8)
    assert psnr(uint8_a, uint8_b, 255) == pytest.approx(
        peak_signal_noise_ratio(uint8_a, uint8_b, data_range=255)
    )
    assert psnr(a, a, 1.0) == float("inf")
    assert ssim(a, a, 1.0) == pytest.approx(1.0)


def test_band_squared_error_splits_the_error_by_frequency() -> None:
    rng = np.random.default_rng(3)
    sharp = rng.integers(0, 256, (4, 120, 160, 3), dtype=np.uint8)
    noisy = np.clip(sharp + rng.normal(0, 5, sharp.shape), 0, 255).astype(np.uint8)
    bands = band_squared_error(sharp, noisy)
    assert bands.shape == (len(FREQUENCY_BAND_EDGES) - 1,)
    squared = np.sum((noisy.astype(float) - sharp) ** 2)
    assert bands.sum() == pytest.approx(squared)  # Parseval: the bands add up to the error
    assert band_squared_error(sharp[0], noisy[0]).sum() == pytest.approx(
        np.sum((noisy[0].astype(float) - sharp[0]) ** 2))  # fmt: skip
    columns = np.arange(160)[None, :, None]
    zero = np.zeros((120, 160, 1))
    for error, band in (
        (zero + 7.0, 0),
        (np.cos(2 * np.pi * columns / 8) + zero, 3),
        ((-1.0) ** (np.arange(120)[:, None, None] + columns) + zero, 4),
    ):
        split = band_squared_error(zero, error)
        assert split[band] == pytest.approx(split.sum())  # fmt: skip


def test_longer_blur_moves_the_error_to_lower_frequencies() -> None:
    photo = to_gray(skimage.data.astronaut())[100:220, 200:360, None]
    low_share = []
    for length in (3, 15):
        blurred = blur_image(photo[..., 0], motion_kernel(length, 30), boundary="reflect")
        bands = band_squared_error(photo, blurred[..., None])
        low_share.append(bands[:3].sum() / bands.sum())  # below 1/8 cycles per pixel
    assert low_share[1] > low_share[0] + 0.2


def test_band_squared_error_refuses_bad_input() -> None:
    frames = np.zeros((2, 8, 8, 3))
    with pytest.raises(ValueError, match="one shape"):
        band_squared_error(frames, frames[:1])
    with pytest.raises(ValueError, match="one shape"):
        band_squared_error(frames[0, 0], frames[0, 0])
    with pytest.raises(ValueError, match="edges"):
        band_squared_error(frames, frames, edges=(0.0, 0.25, 0.5))


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda: wiener_deconvolve(np.ones((16, 16)), motion_kernel(3, 0), nsr=0),
            "nsr must be > 0",
        ),
        (
            lambda: wiener_deconvolve(np.ones((16, 16)), motion_kernel(3, 0), nsr=-1),
            "nsr must be > 0",
        ),
        (lambda: wiener_deconvolve(np.ones((16, 16)), np.zeros((3, 3)), nsr=0.1), "sums to 0"),
        (
            lambda: wiener_deconvolve(np.ones((16, 16)), motion_kernel(3, 0), 0.1, "tikhonov"),
            "regulariser must be one of .*'tikhonov'",
        ),
        (
            lambda: wiener_deconvolve(np.ones((16, 16)), motion_kernel(3, 0), None, "gradient"),
            "needs its weight",
        ),
        (
            lambda: deblur_blind(np.ones((16, 16)), regulariser="flat"),
            "regulariser must be one of .*'flat'",
        ),
        (lambda: wiener_deconvolve(np.ones((4, 4)), motion_kernel(9, 0), nsr=0.1), "larger"),
        (
            lambda: wiener_deconvolve(np.array([[np.inf, 0], [0, 0]]), np.ones((1, 1)), nsr=0.1),
            "NaN or inf",
        ),
        (lambda: wiener_deconvolve(np.ones((1, 5)), np.ones((1, 1)), nsr=0.1), "at least 2x2"),
        (lambda: wiener_deconvolve(np.ones((5, 5), bool), np.ones((1, 1)), nsr=0.1), "dtype"),
        (
            lambda: wiener_deconvolve(np.ones((8, 8)), np.ones((1, 1)), 0.1, boundary="wrap"),
            "boundary must be one of .*'wrap'",
        ),
        (
            lambda: wiener_deconvolve(np.ones((8, 8)), np.ones((1, 1)), 0.1, iterations=-1),
            "iterations must be >= 0, got -1",
        ),
        (lambda: psnr(np.ones((4, 4)), np.ones((4, 5)), 1.0), "differ in shape"),
        (lambda: psnr(np.ones((4, 4)), np.ones((4, 4)), 0), "data_range"),
    ],
    ids=[
        "nsr-zero",
        "nsr-negative",
        "kernel-zero-sum",
        "unknown-regulariser",
        "gradient-without-weight",
        "blind-unknown-regulariser",
        "kernel-too-large",
        "inf",
        "one-row",
        "bool",
        "unknown-boundary",
        "negative-iterations",
        "shape-mismatch",
        "data-range",
    ],
)
def test_bad_input_is_refused(call, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        call()


def test_accuracy_by_noise_summarises_each_level_in_order() -> None:
    from blurloc.experiments.estimation import accuracy_by_noise

    trials = [
        {"noise_sigma": s, "angle_error_deg": a, "length_error_px": e}
        for s, a, e in ((0.0, 1.0, 0.5), (0.01, 5.0, 3.0), (0.0, 3.0, 0.2))
    ]
    rows = accuracy_by_noise(trials)
    assert [r["noise_sigma"] for r in rows] == [0.0, 0.01]
    assert rows[0]["trials"] == 2 and rows[0]["angle_median_deg"] == 2.0
    assert rows[0]["within_2deg_1px"] == 0.5 and rows[1]["within_2deg_1px"] == 0.0


def test_per_scene_table_means_scenes_and_sets_paper_values_beside() -> None:
    from blurloc.experiments.deblurring import paper_fig6_7, per_scene_table

    rows = [
        {"method": m, "scene": s, "psnr_db": p, "ssim": 0.5}
        for m, s, p in (
            ("blurred", "chess", 30.0),
            ("blurred", "chess", 32.0),
            ("blurred", "fire", 20.0),
            ("wiener", "chess", 25.0),
            ("wiener", "fire", 21.0),
        )
    ]
    table = per_scene_table(rows)
    assert [r["scene"] for r in table] == ["chess", "fire", "mean"]
    assert table[0]["blurred_psnr_db"] == 31.0 and table[2]["blurred_psnr_db"] == 25.5
    assert table[0]["frames"] == 2 and table[2]["frames"] == 3
    assert table[0]["paper_psnr_db"] == paper_fig6_7("chess")["paper_psnr_db"] is not None
    assert paper_fig6_7("no such scene") == {"paper_psnr_db": None, "paper_ssim": None}


def test_kernel_to_otf_is_the_centred_kernel_padded_and_transformed() -> None:
    kernel, shape = motion_kernel(15, 30), (64, 80)
    padded = np.pad(kernel, ((0, shape[0] - kernel.shape[0]), (0, shape[1] - kernel.shape[1])))
    centred = np.roll(padded, (-(kernel.shape[0] // 2), -(kernel.shape[1] // 2)), axis=(0, 1))
    np.testing.assert_allclose(kernel_to_otf(kernel, shape), np.fft.rfft2(centred), atol=1e-5)


@pytest.mark.parametrize("shape", [(4, 4), (6, 10), (120, 160), (486, 660)])
def test_ccs_pack_is_the_layout_of_opencv_dft(shape: tuple[int, int]) -> None:
    import cv2

    plane = np.random.default_rng(0).random(shape).astype(np.float32)
    expected = cv2.dft(plane)
    np.testing.assert_allclose(ccs_pack(np.fft.rfft2(plane)), expected,
                               atol=1e-6 * np.abs(expected).max())  # fmt: skip
    with pytest.raises(ValueError, match="M even"):
        ccs_pack(np.fft.rfft2(plane[:-1]))


def test_wiener_on_a_camera_sized_frame_equals_the_textbook_formula() -> None:
    """Eq. 4 applied by OpenCV's packed transforms equals NumPy's float64 DFT of the same mirror-
    padded frame: a 640x480 RGB uint8 frame, every channel, to one 8-bit step."""
    import cv2

    image = cv2.resize(skimage.data.astronaut() / 255.0, (640, 480), interpolation=cv2.INTER_AREA)
    kernel = motion_kernel(15, 30)
    blurred = np.round(np.clip(blur_image(image, kernel, 0.01, rng=np.random.default_rng(1)),
                               0, 1) * 255).astype(np.uint8)  # fmt: skip
    nsr = 0.01
    restored = wiener_deconvolve(blurred, kernel, nsr)
    pad = max(kernel.shape) + 8
    rows, columns = (_even_dft_size(n + 2 * pad) for n in blurred.shape[:2])
    padded = cv2.copyMakeBorder(blurred, pad, rows - 480 - pad, pad, columns - 640 - pad,
                                cv2.BORDER_REFLECT_101) / 255.0  # fmt: skip
    otf = kernel_to_otf(kernel, padded.shape[:2]).astype(np.complex128)
    gain = np.conj(otf) / (np.abs(otf) ** 2 + nsr)
    expected = np.fft.irfft2(np.fft.rfft2(padded, axes=(0, 1)) * gain[..., None], padded.shape[:2],
                             axes=(0, 1))[pad : pad + 480, pad : pad + 640]  # fmt: skip
    expected = np.round(np.clip(expected, 0, 1) * 255)
    assert restored.shape == blurred.shape
    assert np.abs(restored - expected).max() <= 1
    assert (restored != expected).mean() < 1e-3


def test_filter_comparison_restores_without_noise_and_orders_its_rows() -> None:
    image = to_gray(skimage.data.camera())[100:356, 100:356].astype(np.float64)
    rows = filter_comparison(image, well_posed_kernel(), [0.0, 0.01], np.random.default_rng(0))
    assert [(r["noise_sigma"], r["method"]) for r in rows] == [
        (s, m) for s in (0.0, 0.01)
        for m in ("blurred", "inverse filter (eq. 3)", "Wiener (eq. 4)")]  # fmt: skip
    clean = {r["method"]: r["psnr_db"] for r in rows if r["noise_sigma"] == 0}
    assert clean["inverse filter (eq. 3)"] >= 40 and clean["Wiener (eq. 4)"] >= 40
    noisy = filter_comparison(image, motion_kernel(11, 30), [0.01], np.random.default_rng(1))
    noisy = {r["method"]: r["psnr_db"] for r in noisy}  # a kernel with spectral zeros
    assert noisy["Wiener (eq. 4)"] > max(noisy["inverse filter (eq. 3)"] + 5, noisy["blurred"])
    assert all(r["image"].shape == image.shape for r in rows)


def test_nsr_curve_peaks_inside_the_range_under_noise() -> None:
    image = to_gray(skimage.data.camera())[128:384, 128:384].astype(np.float64)
    kernel = motion_kernel(15, 30)
    blurred = blur_image(image, kernel, 0.01, rng=np.random.default_rng(1))
    curve = nsr_curve(image, blurred, kernel, np.logspace(-4, 0, 9))
    best = int(np.argmax(curve["psnr_db"]))
    assert 0 < best < len(curve["nsr"]) - 1
    assert curve["psnr_db"][best] > curve["blurred_psnr_db"] + 1
    assert 1e-4 < curve["estimated_nsr"] < 1


def test_mirror_padding_beats_the_periodic_dft() -> None:
    image = to_gray(skimage.data.camera())[128:384, 128:384].astype(np.float64)
    kernel = motion_kernel(15, 30)
    blurred = blur_image(image, kernel, 0.002, rng=np.random.default_rng(2))
    scores = {r["method"]: r["psnr_db"] for r in boundary_comparison(image, blurred, kernel)}
    assert scores["Wiener, mirror padding"] > scores["Wiener, periodic DFT"] + 1


def frame_cut_from_a_larger_blurred_photograph(
    kernel: np.ndarray, margin: int = 24
) -> tuple[np.ndarray, np.ndarray]:
    """(blurred frame, sharp frame): a photograph blurred as a whole, then cut, so that the
    frame's border holds light from beyond the frame, as a camera's frame does."""
    photo = (
        skimage.data.astronaut()[100 : 100 + 120 + 2 * margin, 150 : 150 + 160 + 2 * margin] / 255.0
    )
    blurred = np.stack([blur_image(photo[..., c], kernel, boundary="reflect") for c in range(3)],
                       axis=-1)  # fmt: skip
    frame = np.s_[margin:-margin, margin:-margin]
    return blurred[frame], photo[frame]


def test_unknown_boundary_restores_the_border_that_a_mirror_cannot() -> None:
    kernel = trajectory_kernel(np.array([[-6.0, -2.0], [0.0, 0.0], [5.0, 3.0]]), origin=np.zeros(2))
    blurred, sharp = frame_cut_from_a_larger_blurred_photograph(kernel)
    border = np.zeros(sharp.shape[:2], bool)
    border[:12] = border[-12:] = True
    border[:, :12] = border[:, -12:] = True
    scores = {}
    for boundary in ("mirror", "unknown"):
        restored = wiener_deconvolve(blurred, kernel, 0.002, "gradient", boundary)
        scores[boundary] = (psnr(sharp, np.clip(restored, 0, 1), 1.0),
                            psnr(sharp[border], np.clip(restored[border], 0, 1), 1.0))  # fmt: skip
    assert scores["unknown"][1] > scores["mirror"][1] + 3.0  # the border band
    assert scores["unknown"][0] > scores["mirror"][0] + 1.0  # the whole frame
    assert scores["unknown"][0] > psnr(sharp, blurred, 1.0) + 5.0


def test_unknown_boundary_solve_starts_at_the_mirror_result_and_improves_with_steps() -> None:
    kernel = trajectory_kernel(np.array([[-4.0, 1.0], [4.0, -1.0]]), origin=np.zeros(2))
    blurred, sharp = frame_cut_from_a_larger_blurred_photograph(kernel)
    quality = [
        psnr(sharp, wiener_deconvolve(blurred, kernel, 0.002, "gradient", "unknown", steps), 1.0)
        for steps in (0, 2, 10, 40)
    ]
    mirror = wiener_deconvolve(blurred, kernel, 0.002, "gradient", "mirror")
    assert quality[0] == pytest.approx(psnr(sharp, mirror, 1.0), abs=1e-3)  # 0 steps: the start
    assert quality[0] < quality[1] < quality[2] <= quality[3] + 0.01


@pytest.mark.parametrize("dtype", [np.uint8, np.float32, np.float64])
@pytest.mark.parametrize("channels", [None, 3])
def test_unknown_boundary_keeps_shape_and_dtype(dtype, channels) -> None:
    shape = (40, 56) if channels is None else (40, 56, channels)
    image = np.random.default_rng(1).random(shape)
    image = (image * 255).astype(np.uint8) if dtype == np.uint8 else image.astype(dtype)
    restored = wiener_deconvolve(image, motion_kernel(7, 20), 0.05, "constant", "unknown")
    assert restored.shape == image.shape
    assert restored.dtype == (np.uint8 if dtype == np.uint8 else dtype)


def test_oracle_gain_split_by_extent() -> None:
    def row(frame: int, variant: str, extent: float, value: float) -> dict:
        return {"scene": "chess", "sequence": 1 + frame % 2, "frame": frame // 2,
                "variant": variant, "extent_px": extent, "psnr_db": value}  # fmt: skip

    extents, blurred, restored = [1.0, 3.0, 4.0, 9.0], [20.0, 22.0, 25.0, 18.0], [19, 23, 27, 22]
    rows = [row(i, "blurred", e, b) for i, (e, b) in enumerate(zip(extents, blurred, strict=True))]
    rows += [row(i, "path_linear_best", e, r)
             for i, (e, r) in enumerate(zip(extents, restored, strict=True))]  # fmt: skip
    extent, gain = frame_gains(rows, "path_linear_best")
    np.testing.assert_allclose(gain, [-1, 1, 2, 4])
    np.testing.assert_allclose(extent, extents)
    assert gain_by_extent(rows, "path_linear_best", 4.0) == (3.0, 0.0)


def test_inversion_is_exact_under_the_periodic_model_even_with_spectral_zeros() -> None:
    """Notebook 02's first figure: the 15 px line kernel, no noise, yet about 6 dB. Blurred and
    divided by the same DFT (the periodic model) the image comes back to rounding, so what the
    near-zeros of the kernel's spectrum amplify is the mismatch at the border of a camera-like
    (mirror-boundary) blur, not a flaw of the division."""
    photo = to_gray(skimage.data.camera()).astype(np.float64)
    kernel = motion_kernel(15, 30)
    otf = kernel_to_otf(kernel, photo.shape)
    periodic = np.fft.irfft2(np.fft.rfft2(photo) * otf, s=photo.shape)
    restored = np.fft.irfft2(np.fft.rfft2(periodic) / otf, s=photo.shape)
    assert np.abs(otf).min() < 1e-4  # spectral zeros
    assert psnr(photo, restored, 1.0) > 100
    camera_like = inverse_filter(blur_image(photo, kernel, 0.0), kernel)
    assert psnr(photo[24:-24, 24:-24], np.clip(camera_like, 0, 1)[24:-24, 24:-24], 1.0) < 20


# ---- blind deblurring's gate -------------------------------------------------------------


def _photo(name: str, size: tuple[int, int]) -> np.ndarray:
    """A bundled RGB photograph resized (area-averaged) to ``size`` (width, height), uint8."""
    return cv2.resize(getattr(skimage.data, name)(), size, interpolation=cv2.INTER_AREA)


def _uint8(image: np.ndarray) -> np.ndarray:
    return np.round(np.clip(image, 0, 1) * 255).astype(np.uint8)


def test_gate_passes_a_sharp_frame_through_untouched() -> None:
    sharp = _photo("rocket", (160, 120))  # the detector calls it blurred: only the gate stops it
    assert (deblur_blind(sharp, gated=False) != sharp).any()
    passed = deblur_blind(sharp)
    np.testing.assert_array_equal(passed, sharp)
    assert passed is not sharp


def test_gate_restores_a_strongly_line_blurred_noise_free_frame() -> None:
    sharp = _photo("coffee", (320, 240))
    blurred = _uint8(blur_image(sharp, motion_kernel(15, 30)))
    restored = deblur_blind(blurred)
    assert psnr(sharp, restored, 255.0) - psnr(sharp, blurred, 255.0) > 2.0


def test_gate_passes_a_shaken_frame_that_restoration_would_harm() -> None:
    sharp = _photo("coffee", (320, 240))
    rng = np.random.default_rng(0)
    # without noise the weight (a multiple of the noise) is small, and the line deconvolution
    # of a curved shake path rings; with noise the same frame gains
    blurred = _uint8(blur_image(sharp, trajectory_kernel(shake_path(10, rng)), 0.0, rng=rng))
    ungated = deblur_blind(blurred, gated=False)
    assert psnr(sharp, ungated, 255.0) < psnr(sharp, blurred, 255.0)  # it would lose
    np.testing.assert_array_equal(deblur_blind(blurred), blurred)


def test_gate_thresholds() -> None:
    features = BlurFeatures(np.zeros(78), 0.0, anisotropy=GATE_MIN_ANISOTROPY, scale=1.0)
    # refined length within GATE_MAX_AGREEMENT of every coarse length tried below
    trusted = BlurEstimate(length_px=GATE_MIN_LENGTH, angle_deg=0.0, fit=GATE_MIN_FIT)
    sigma = GATE_REFERENCE_NOISE
    shortest = GATE_MIN_LENGTH * (2.0**GATE_NOISE_EXPONENT)  # at twice the reference noise
    assert blind_restoration_expected_to_gain(trusted, features, sigma, GATE_MIN_LENGTH)
    assert not blind_restoration_expected_to_gain(trusted, features, sigma, 0.99 * GATE_MIN_LENGTH)
    assert blind_restoration_expected_to_gain(trusted, features, 2 * sigma, shortest)
    assert not blind_restoration_expected_to_gain(trusted, features, 2 * sigma, 0.99 * shortest)
    assert blind_restoration_expected_to_gain(trusted, features, sigma, GATE_MAX_LENGTH)
    assert not blind_restoration_expected_to_gain(trusted, features, sigma, 1.01 * GATE_MAX_LENGTH)
    unrefined = BlurEstimate(length_px=GATE_MIN_LENGTH, angle_deg=0.0, fit=0.0)
    assert not blind_restoration_expected_to_gain(unrefined, features, sigma, GATE_MIN_LENGTH)
    isotropic = BlurFeatures(np.zeros(78), 0.0, anisotropy=0.9 * GATE_MIN_ANISOTROPY, scale=1.0)
    assert not blind_restoration_expected_to_gain(trusted, isotropic, sigma, GATE_MIN_LENGTH)


def test_gate_rejects_a_refined_length_far_above_the_coarse_one() -> None:
    """The sinc-refined length is compared with the coarse length in the image's pixels: at
    scale 2 a coarse length of 6 analysis px is 12 image px."""
    features = BlurFeatures(np.zeros(62), 0.0, anisotropy=GATE_MIN_ANISOTROPY, scale=2.0)
    length = 1.5 * GATE_MIN_LENGTH
    agreement = min(GATE_MAX_AGREEMENT, 1.5)  # finite even where the gate ships without the bound
    coarse_px = length * features.scale

    def gains(refined_px: float, max_agreement: float = GATE_MAX_AGREEMENT) -> bool:
        estimate = BlurEstimate(length_px=refined_px, angle_deg=0.0, fit=GATE_MIN_FIT)
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr("blurloc.deconv.GATE_MAX_AGREEMENT", max_agreement)
            return blind_restoration_expected_to_gain(
                estimate, features, GATE_REFERENCE_NOISE, length
            )

    assert gains(agreement * coarse_px, agreement)
    assert not gains(1.01 * agreement * coarse_px, agreement)
    assert gains(coarse_px)  # agreeing lengths pass at the shipped bound


def _changes(
    pairs: list[tuple[np.ndarray, np.ndarray]], gated: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """PSNR change (dB) of blind deblurring for each (blurred, sharp) pair, and whether the
    frame was restored."""
    changes, restored = [], []
    for blurred, sharp in pairs:
        result = deblur_blind(blurred, gated=gated)
        restored.append(bool((result != blurred).any()))
        changes.append(psnr(sharp, result, 255.0) - psnr(sharp, blurred, 255.0))
    return np.array(changes), np.array(restored)


def test_gate_does_not_harm_stand_in_frames(quick_root) -> None:
    """The target on the stand-in: the mean change over all frames >= 0 dB, the median over the
    frames restored > 0 (the ungated rule loses on these frames)."""
    paths = sorted(quick_root.glob("*/seq-*/frame-*.color.png"))
    pairs = [(cv2.imread(str(p)), cv2.imread(str(p).replace(".color.png", ".sharp.png")))
             for p in paths]  # fmt: skip
    changes, restored = _changes(pairs)
    assert len(pairs) >= 16
    assert changes.mean() >= 0.0
    assert not restored.any() or np.median(changes[restored]) > 0
    assert _changes(pairs, gated=False)[0].mean() < 0  # what the gate prevents


@pytest.mark.skipif(
    not all(entry_path(entry).is_file() for entry in part_entries("pairs")),
    reason="the real blurred/sharp pair is not present",
)
def test_gate_does_not_harm_the_real_pair() -> None:
    pairs = [(blurred, sharp) for _, blurred, sharp in load_pairs()]
    changes, _ = _changes(pairs)
    assert len(pairs) >= 1 and (changes >= 0).all()
