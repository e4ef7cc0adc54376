"""The restoration bounds: the forward model and the true-PSF Wiener oracle on frames where the
blur model holds (real photographs blurred with a known PSF) and where it does not."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from blurloc.blur.kernels import motion_kernel
from blurloc.data.real import load_photographs
from blurloc.experiments.restoration_bounds import (
    TileKernel,
    blur_linear,
    lens_blur,
    restoration_bounds,
    standin_tile_kernels,
)


@pytest.fixture(scope="module")
def photo() -> np.ndarray:
    """A real sharp photograph at 160x120, in [0, 1]."""
    image = next(iter(load_photographs("sharp").values()))
    return np.round(cv2.resize(image, (160, 120), interpolation=cv2.INTER_AREA)) / 255.0


def whole(kernel: np.ndarray) -> list[TileKernel]:
    return [TileKernel(0, 120, 0, 160, kernel)]


def test_true_psf_restores_a_photograph_blurred_with_it(photo):
    kernel = motion_kernel(9.0, 30.0)
    blurred = np.round(blur_linear(photo, kernel) * 255) / 255
    scores = restoration_bounds(blurred, photo, whole(kernel))
    assert scores["forward_psnr"] > 50.0  # b = c * x up to 8-bit rounding
    assert scores["best_forward_psnr"] > 45.0
    assert scores["wiener_gain"] > 1.0


def test_no_gain_when_the_psf_says_sharp_but_the_frame_is_blurred(photo):
    blurred = np.round(blur_linear(photo, motion_kernel(9.0, 30.0)) * 255) / 255
    scores = restoration_bounds(blurred, photo, whole(np.ones((1, 1))))
    assert scores["wiener_gain"] < 0.25  # only the NSR's rescaling; the true PSF gains > 1 dB
    assert scores["forward_psnr"] == pytest.approx(scores["blurred_psnr"])


def test_lens_blur_is_identity_at_zero_and_smooths_otherwise(photo):
    assert np.array_equal(lens_blur(photo, 0.0), photo)
    assert (
        np.abs(np.diff(lens_blur(photo, 1.0), axis=1)).mean()
        < np.abs(np.diff(photo, axis=1)).mean()
    )


def test_standin_tile_kernels_cover_the_frame_and_sum_to_one(quick_root):
    tiles = standin_tile_kernels(quick_root, "chess", 1, 4, tile_px=16)
    assert tiles
    for tile in tiles:
        assert tile.kernel.sum() == pytest.approx(1.0)
        assert 0 <= tile.top < tile.bottom and 0 <= tile.left < tile.right
    sampled = standin_tile_kernels(quick_root, "chess", 1, 4, tile_px=16, renders=5)
    assert len(sampled) == len(tiles)
    assert all(t.kernel.sum() == pytest.approx(1.0) for t in sampled)
