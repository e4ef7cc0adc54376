"""How much of a frame's blur is restorable: the blur model b = c * x checked on a frame against
its sharp frame, and the gain of Wiener deconvolution with the true point spread functions.

A stand-in frame's PSF varies across the image (points at other depths and positions move
differently), so the true PSF is rebuilt per tile from the camera's poses over the exposure and
the mid-exposure depth (:func:`~blurloc.data.exposure.exposure_tracks`), one kernel at each
tile's centre.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import cv2
import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from ..blur.kernels import trajectory_kernel
from ..data.camera_motion import sequence_trajectory
from ..data.exposure import exposure_tracks
from ..data.synth_config import SynthConfig
from ..deconv import wiener_deconvolve
from ..geometry import intrinsics
from ..images import linear_to_srgb, srgb_to_linear
from ..metrics import psnr


@dataclass(frozen=True)
class TileKernel:
    """The PSF of one tile: rows ``top:bottom`` and columns ``left:right`` of the frame."""

    top: int
    bottom: int
    left: int
    right: int
    kernel: np.ndarray


def blur_linear(sharp: np.ndarray, kernel: np.ndarray) -> np.ndarray:
    r"""Blur a gamma-encoded image with ``kernel`` in linear light (as exposures average).

    .. math:: b = \left(c * x^{\gamma}\right)^{1/\gamma}, \quad \gamma = 2.2

    Parameters
    ----------
    sharp : numpy.ndarray
        (H, W, 3) gamma-encoded image in [0, 1].
    kernel : numpy.ndarray
        (k, k) PSF summing to 1 (a convolution, not a correlation); borders mirrored.

    Returns
    -------
    numpy.ndarray
        (H, W, 3) gamma-encoded blurred image in [0, 1].
    """
    linear = srgb_to_linear(np.asarray(sharp, np.float64)).astype(np.float32)
    flipped = np.ascontiguousarray(kernel[::-1, ::-1], dtype=np.float32)
    return linear_to_srgb(cv2.filter2D(linear, -1, flipped, borderType=cv2.BORDER_REFLECT_101))


def lens_blur(image: np.ndarray, sigma_px: float) -> np.ndarray:
    """A Gaussian lens blur (standard deviation ``sigma_px``) of an (H, W, 3) image in [0, 1],
    applied in linear light; ``sigma_px`` 0 returns the image."""
    if sigma_px <= 0:
        return np.asarray(image, np.float64)
    linear = srgb_to_linear(np.asarray(image, np.float64))
    return linear_to_srgb(cv2.GaussianBlur(linear, (0, 0), sigma_px))


def standin_tile_kernels(
    root: str | Path, scene: str, sequence: int, frame: int, tile_px: int = 40,
    renders: int | None = None,
) -> list[TileKernel]:  # fmt: skip
    """The true PSF of each ``tile_px`` square tile of one stand-in frame.

    Each tile's kernel is the image path over the exposure
    (:func:`~blurloc.blur.kernels.trajectory_kernel`) of the surface point seen at the tile's
    centre at mid-exposure, centred on its mid-exposure position, rebuilt from the settings in
    ``root/standin.json``, the sequence's trajectory and the frame's depth. Tiles whose centre
    sees no surface are left out. With ``renders`` N, the kernel is instead the point's
    positions at the N instants the renderer averages (the midpoint rule,
    :func:`~blurloc.data.exposure.render_exposure`), each splatted bilinearly with weight 1/N:
    the PSF of the rendered exposure rather than of the continuous one.

    Parameters
    ----------
    root : str or pathlib.Path
        A stand-in root.
    scene, sequence, frame : str, int, int
        Which frame.
    tile_px : int
        Tile side, pixels.
    renders : int, optional
        The number of renders the frame averages (``samples`` in ``blur.csv``); default: the
        continuous path.

    Returns
    -------
    list of TileKernel
    """
    manifest = json.loads((Path(root) / "standin.json").read_text())
    settings = dict(manifest["config"])
    settings["sequence_counts"] = {k: tuple(v) for k, v in settings["sequence_counts"].items()}
    config = SynthConfig(**settings)
    scene_model, trajectory = sequence_trajectory(scene, sequence, config, manifest["seed"])
    stem = Path(root) / scene / f"seq-{sequence:02d}" / f"frame-{frame:06d}"
    depth = cv2.imread(f"{stem}.depth.png", cv2.IMREAD_UNCHANGED).astype(np.float64) / 1000.0
    camera = intrinsics(config.width, config.height)
    step = tile_px
    v, u = np.mgrid[step // 2 : config.height : step, step // 2 : config.width : step]
    valid = depth[v, u].ravel() > 0
    dense = 201  # instants of the continuous path, the middle one at mid-exposure
    tracks = exposure_tracks(scene_model, trajectory, frame / config.fps, config, camera, depth,
                             grid_step=step, samples=dense)  # fmt: skip
    tiles = []
    for index, (row, column) in enumerate(zip(v.ravel()[valid], u.ravel()[valid], strict=True)):
        path, middle = tracks[:, index], tracks[dense // 2, index]
        if renders is None:
            kernel = trajectory_kernel(path, origin=middle)
        else:
            kernel = _sampled_kernel(path, renders, middle)
        top, left = row - step // 2, column - step // 2
        tiles.append(TileKernel(top, min(top + step, config.height), left,
                                min(left + step, config.width), kernel))  # fmt: skip
    return tiles


def _sampled_kernel(path: np.ndarray, renders: int, middle: np.ndarray) -> np.ndarray:
    """The kernel of ``renders`` equal-weight positions on ``path`` (equal time steps over the
    exposure) at the midpoint rule's instants, each splatted bilinearly, centred on ``middle``."""
    times = np.linspace(-0.5, 0.5, len(path))
    instants = (np.arange(renders) + 0.5) / renders - 0.5
    points = np.column_stack([np.interp(instants, times, path[:, axis]) for axis in range(2)])
    offsets = points - middle
    size = 2 * int(np.ceil(np.abs(offsets).max() + 1)) + 1
    return np.mean([trajectory_kernel(point[None], size=size, origin=middle)
                    for point in points], axis=0)  # fmt: skip


def _pieced(image: np.ndarray, tiles: list[TileKernel], operation) -> tuple[np.ndarray, np.ndarray]:
    """``operation(image, kernel)`` on the whole image, kept on each tile; and the tiles' mask."""
    result, mask = np.zeros_like(image, np.float64), np.zeros(image.shape[:2], bool)
    for tile in tiles:
        window = (slice(tile.top, tile.bottom), slice(tile.left, tile.right))
        result[window] = operation(image, tile.kernel)[window]
        mask[window] = True
    return result, mask


def best_forward(sharp: np.ndarray, blurred: np.ndarray, tiles: list[TileKernel],
                 size: int = 13) -> np.ndarray:  # fmt: skip
    """Each tile of ``blurred`` as well as any ``size`` x ``size`` convolution of ``sharp`` can
    make it: the least-squares kernel (shared by the channels, plus an offset) in linear light,
    fitted on the tile itself (a ceiling on every per-tile PSF); other pixels are 0."""
    margin = size // 2
    linear = np.pad(srgb_to_linear(sharp), ((margin, margin), (margin, margin), (0, 0)), "reflect")
    target = srgb_to_linear(blurred)
    result = np.zeros_like(blurred, np.float64)
    for tile in tiles:
        window = linear[tile.top : tile.bottom + 2 * margin, tile.left : tile.right + 2 * margin]
        rows = np.concatenate([sliding_window_view(window[..., c], (size, size))
                               .reshape(-1, size * size) for c in range(3)])  # fmt: skip
        rows = np.hstack([rows, np.ones((len(rows), 1))])
        truth = np.concatenate([target[tile.top : tile.bottom, tile.left : tile.right, c]
                                .reshape(-1) for c in range(3)])  # fmt: skip
        weights, *_ = np.linalg.lstsq(rows, truth, rcond=None)
        fitted = (rows @ weights).reshape(3, tile.bottom - tile.top, tile.right - tile.left)
        result[tile.top : tile.bottom, tile.left : tile.right] = np.moveaxis(fitted, 0, -1)
    return linear_to_srgb(result)


#: The noise-to-signal ratios the Wiener oracle chooses from.
ORACLE_NSRS = (1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4)


def wiener_linear(image: np.ndarray, kernel: np.ndarray, nsr: float) -> np.ndarray:
    """Wiener deconvolution (:func:`~blurloc.deconv.wiener_deconvolve`) in linear light, where
    the exposure's blur is a convolution: gamma-decode, deconvolve, gamma-encode (clipped)."""
    return linear_to_srgb(wiener_deconvolve(srgb_to_linear(image), kernel, nsr))


def restoration_bounds(
    blurred: np.ndarray, sharp: np.ndarray, tiles: list[TileKernel],
    nsrs: tuple[float, ...] = ORACLE_NSRS, margin: int = 8,
) -> dict[str, float]:  # fmt: skip
    r"""The blurred frame's PSNR, the forward model's consistency and the true-PSF Wiener gain.

    On the pixels of ``tiles`` (less ``margin`` px at the frame's border):

    - ``blurred_psnr``: PSNR(blurred, sharp), dB;
    - ``forward_psnr``: PSNR(blurred, c * sharp), each tile blurred with its own kernel in linear
      light (:func:`blur_linear`): how well b = c * x describes the frame (infinite if exactly);
    - ``best_forward_psnr``: the same with each tile's best-fitting kernel (:func:`best_forward`):
      how well any per-tile convolution describes it;
    - ``wiener_gain``: PSNR(Wiener(blurred, c), sharp) - ``blurred_psnr``, each tile deconvolved
      with its own kernel in linear light (:func:`wiener_linear`), at the one of ``nsrs`` that
      scores best against the sharp frame (an oracle: the true PSF and the best NSR);
      ``wiener_nsr``: that NSR.

    Parameters
    ----------
    blurred, sharp : numpy.ndarray
        (H, W, 3) gamma-encoded frames in [0, 1].
    tiles : list of TileKernel
        The true PSF of each tile.
    nsrs : tuple of float
        Noise-to-signal ratios the Wiener oracle chooses from.
    margin : int
        Border left out of every score, pixels.

    Returns
    -------
    dict
        ``blurred_psnr``, ``forward_psnr``, ``best_forward_psnr``, ``wiener_gain`` (dB) and
        ``wiener_nsr``.
    """
    blurred, sharp = np.asarray(blurred, np.float64), np.asarray(sharp, np.float64)
    forward, mask = _pieced(sharp, tiles, blur_linear)
    mask[:margin], mask[-margin:], mask[:, :margin], mask[:, -margin:] = False, False, False, False
    before = psnr(sharp[mask], blurred[mask], 1.0)
    scores = {}
    for nsr in nsrs:
        restored, _ = _pieced(blurred, tiles, partial(wiener_linear, nsr=nsr))
        scores[nsr] = psnr(sharp[mask], restored[mask], 1.0)
    best = max(scores, key=scores.get)
    return {
        "blurred_psnr": before,
        "forward_psnr": psnr(blurred[mask], forward[mask], 1.0),
        "best_forward_psnr": psnr(blurred[mask], best_forward(sharp, blurred, tiles)[mask], 1.0),
        "wiener_gain": scores[best] - before,
        "wiener_nsr": best,
    }
