"""Folder deblurring in a process pool: the same pixels as one process and as a float64
reference of eq. 4, errors named, frames refused by the caller's check."""

from __future__ import annotations

from functools import partial
from pathlib import Path

import cv2
import numpy as np
import pytest
import skimage.data

from blurloc.batch_deblur import available_cores, deblur_files
from blurloc.blur import blur_image, motion_kernel
from blurloc.deconv import _even_dft_size, deblur_blind, estimate_nsr
from blurloc.files import read_image_file


def reference_wiener(image: np.ndarray, kernel: np.ndarray, nsr: float) -> np.ndarray:
    """Eq. 4 in float64 with NumPy's FFT, with the package's mirror padding, rounded to uint8."""
    pad = max(kernel.shape) + 8
    height, width = image.shape[:2]
    shape = (_even_dft_size(height + 2 * pad), _even_dft_size(width + 2 * pad))
    widths = ((pad, shape[0] - height - pad), (pad, shape[1] - width - pad), (0, 0))
    padded = np.pad(image / 255.0, widths, mode="reflect")
    placed = np.zeros(shape)
    placed[: kernel.shape[0], : kernel.shape[1]] = kernel / kernel.sum()
    otf = np.fft.rfft2(np.roll(placed, (-(kernel.shape[0] // 2), -(kernel.shape[1] // 2)), (0, 1)))
    response = np.conj(otf) / (np.abs(otf) ** 2 + nsr)
    restored = np.fft.irfft2(np.fft.rfft2(padded, axes=(0, 1)) * response[..., None], shape,
                             axes=(0, 1))[pad : pad + height, pad : pad + width]  # fmt: skip
    return np.round(np.clip(restored, 0, 1) * 255).astype(np.uint8)


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Four line-blurred, noisy 160x120 RGB PNG frames."""
    folder = tmp_path_factory.mktemp("frames")
    rng = np.random.default_rng(0)
    for index, name in enumerate(("astronaut", "coffee", "chelsea", "rocket")):
        photo = cv2.resize(getattr(skimage.data, name)(), (160, 120), interpolation=cv2.INTER_AREA)
        blurred = blur_image(photo, motion_kernel(7, 40 * index), 0.005, rng=rng)
        image = np.round(np.clip(blurred, 0, 1) * 255).astype(np.uint8)
        cv2.imwrite(str(folder / f"frame-{index:06d}.color.png"), image[..., ::-1])
    return folder


def read_rgb(path: Path) -> np.ndarray:
    return cv2.imread(str(path))[..., ::-1]


def test_pool_gives_the_pixels_of_one_process_and_of_eq_4(folder: Path, tmp_path: Path) -> None:
    frames = sorted(folder.glob("*.png"))
    kernel = motion_kernel(7, 40)
    outputs = {}
    for workers in (1, 2):
        pairs = [(path, tmp_path / str(workers) / path.name) for path in frames]
        (tmp_path / str(workers)).mkdir()
        done = list(deblur_files(pairs, kernel=kernel, workers=workers))
        assert [(a, b) for a, b, _ in done] == pairs  # in input order
        outputs[workers] = [read_rgb(out) for _, out in pairs]
    for serial, pooled, path in zip(outputs[1], outputs[2], frames, strict=True):
        np.testing.assert_array_equal(pooled, serial)
        image = read_rgb(path)
        expected = reference_wiener(image, kernel, estimate_nsr(image))
        assert np.abs(pooled.astype(int) - expected).max() <= 1  # float32 vs float64: one step
        assert (pooled != expected).mean() < 1e-3


def test_blind_files_are_restored_as_blind_deblurring_restores_them(tmp_path: Path) -> None:
    sharp = cv2.resize(skimage.data.coffee(), (320, 240), interpolation=cv2.INTER_AREA)
    blurred = np.round(np.clip(blur_image(sharp / 255.0, motion_kernel(15, 30)), 0, 1) * 255)
    path = tmp_path / "blurred.png"
    cv2.imwrite(str(path), cv2.cvtColor(blurred.astype(np.uint8), cv2.COLOR_RGB2BGR))
    list(deblur_files([(path, tmp_path / "out.png")], workers=1))
    image = read_image_file(path)[0]
    expected = deblur_blind(image)
    assert not np.array_equal(expected, image)  # the gate restores this frame
    np.testing.assert_array_equal(read_image_file(tmp_path / "out.png")[0], expected)


def test_blind_pool_equals_one_process(folder: Path, tmp_path: Path) -> None:
    frames = sorted(folder.glob("*.png"))
    for workers in (1, 2):
        (tmp_path / str(workers)).mkdir()
        pairs = [(path, tmp_path / str(workers) / path.name) for path in frames]
        assert len(list(deblur_files(pairs, workers=workers))) == len(frames)
    for path in frames:
        np.testing.assert_array_equal(read_rgb(tmp_path / "2" / path.name),
                                      read_rgb(tmp_path / "1" / path.name))  # fmt: skip


def refuse_wide(shape: tuple[int, ...], path: Path, limit: int) -> None:
    if shape[1] > limit:
        raise ValueError(f"{path}: wider than {limit} px")


def test_errors_name_the_frame_and_checks_refuse(folder: Path, tmp_path: Path) -> None:
    frames = sorted(folder.glob("*.png"))
    broken = tmp_path / "broken.png"
    broken.write_bytes(b"not a png")
    pairs = [(path, tmp_path / path.name) for path in [*frames, broken]]
    with pytest.raises(ValueError, match=r"broken\.png"):
        list(deblur_files(pairs, workers=2))
    check = partial(refuse_wide, limit=100)
    with pytest.raises(ValueError, match="wider than 100 px"):
        list(deblur_files([(frames[0], tmp_path / "x.png")], check=check, workers=1))
    with pytest.raises(ValueError, match="workers"):
        list(deblur_files(pairs, workers=0))
    assert available_cores() >= 1


def test_a_passed_through_frame_is_a_copy_of_its_file(tmp_path: Path) -> None:
    sharp = cv2.resize(skimage.data.rocket(), (160, 120), interpolation=cv2.INTER_AREA)
    source = tmp_path / "sharp.png"
    cv2.imwrite(str(source), sharp[..., ::-1])
    pairs = [(source, tmp_path / "out.png"), (source, tmp_path / "out.tif")]
    assert [lost for _, _, lost in deblur_files(pairs, workers=1)] == [[], []]
    assert (tmp_path / "out.png").read_bytes() == source.read_bytes()
    np.testing.assert_array_equal(read_rgb(tmp_path / "out.tif"), sharp)  # decoded, re-encoded
