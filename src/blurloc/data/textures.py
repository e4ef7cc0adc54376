"""The textures of the stand-in's surfaces, in linear light: photographs bundled with
scikit-image, painted versions of some of them (flat paint with a weak texture) and drawn
patterns (a checkerboard, bookshelves, a window, a door, flat colour), each as a mip pyramid
that the renderer (:mod:`blurloc.data.render`) samples."""

from __future__ import annotations

from functools import cache

import cv2
import numpy as np
import skimage.data

from ..images import srgb_to_linear

#: Levels of every texture's mip pyramid.
MIP_LEVELS = 5
_MAX_TEXTURE_SIDE = 256


def _checkerboard(squares: int = 8, square_px: int = 32) -> np.ndarray:
    board = (np.indices((squares, squares)).sum(axis=0) % 2).astype(np.float32)
    board = np.kron(board, np.ones((square_px, square_px), np.float32))
    return 0.12 + 0.76 * board


_PHOTOS = {
    "astronaut": skimage.data.astronaut,
    "brick": skimage.data.brick,
    "camera": skimage.data.camera,
    "chelsea": skimage.data.chelsea,
    "clock": skimage.data.clock,
    "coffee": skimage.data.coffee,
    "coins": skimage.data.coins,
    "colorwheel": skimage.data.colorwheel,
    "grass": skimage.data.grass,
    "gravel": skimage.data.gravel,
    "hubble": skimage.data.hubble_deep_field,
    "ihc": skimage.data.immunohistochemistry,
    "moon": skimage.data.moon,
    "page": skimage.data.page,
    "rocket": skimage.data.rocket,
    "text": skimage.data.text,
}
#: Photographs whose painted version (``"painted-<name>"``) is flat paint with the photograph as
#: a weak texture.
PAINTED = ("brick", "grass", "gravel")
#: Standard deviation of a painted texture's encoded intensity (its mean is 0.9).
PAINT_DETAIL = 0.03


def _painted(photo: str) -> np.ndarray:
    """Flat paint (encoded intensity 0.9) with the gray photograph as a weak texture."""
    gray = _PHOTOS[photo]().astype(np.float32)
    gray = gray.mean(axis=2) if gray.ndim == 3 else gray
    return np.clip(0.9 + PAINT_DETAIL * (gray - gray.mean()) / gray.std(), 0, 1)


def _books(size: int = 256, shelf_px: int = 64) -> np.ndarray:
    """Shelves of book spines: flat colours with strong edges (a fixed arrangement)."""
    rng = np.random.default_rng(11)
    palette = np.float32([[0.7, 0.15, 0.1], [0.15, 0.3, 0.6], [0.9, 0.85, 0.7], [0.2, 0.45, 0.25],
                          [0.95, 0.6, 0.1], [0.1, 0.1, 0.12], [0.85, 0.85, 0.85]])  # fmt: skip
    image = np.full((size, size, 3), 0.12, np.float32)
    for top in range(0, size, shelf_px):
        image[top + shelf_px - 6 : top + shelf_px] = (0.75, 0.6, 0.45)  # the shelf's board
        column = int(rng.integers(0, 8))
        while column < size:
            width, height = int(rng.integers(5, 15)), int(rng.integers(38, shelf_px - 8))
            image[top + shelf_px - 6 - height : top + shelf_px - 6, column : column + width] = (
                palette[rng.integers(len(palette))] * rng.uniform(0.7, 1.0)
            )
            column += width + int(rng.integers(0, 3))
    return image


def _window(size: int = 256) -> np.ndarray:
    """A window: bright panes (lighter towards the top) in a frame with mullions."""
    sky = np.linspace(0.98, 0.8, size, dtype=np.float32)[:, None, None] * np.float32([0.9, 0.95, 1])
    image = np.broadcast_to(sky, (size, size, 3)).copy()
    frame = np.float32([0.92, 0.92, 0.9])
    image[:14], image[-14:], image[:, :14], image[:, -14:] = frame, frame, frame, frame
    image[size // 2 - 5 : size // 2 + 5], image[:, size // 2 - 5 : size // 2 + 5] = frame, frame
    return image


def _door(size: int = 256) -> np.ndarray:
    """A panelled door: two recessed panels outlined in shadow, and a dark handle."""
    image = np.full((size, size, 3), (0.88, 0.86, 0.8), np.float32)
    for top, bottom in ((24, 112), (136, 232)):
        image[top:bottom, 40:216] = (0.55, 0.54, 0.5)
        image[top + 4 : bottom - 4, 44:212] = (0.82, 0.8, 0.75)
    image[120:132, 222:246] = (0.12, 0.12, 0.12)
    return image


_PATTERNS = {"books": _books, "door": _door, "flat": lambda: np.ones((16, 16), np.float32),
             "window": _window}  # fmt: skip
TEXTURE_NAMES = (*sorted(_PHOTOS), "checker", *(f"painted-{name}" for name in PAINTED),
                 *sorted(_PATTERNS))  # fmt: skip


@cache
def texture_pyramid(name: str) -> tuple[np.ndarray, ...]:
    """Mip pyramid (linear-light float32 RGB, halving sizes) of a named texture.

    Level 0 has at most 256 texels a side and sides that are multiples of ``2**(MIP_LEVELS-1)``,
    so every level is exactly half the one below and all levels tile with the same period.
    """
    if name == "checker":
        image = _checkerboard()
    elif name in _PATTERNS:
        image = _PATTERNS[name]()
    elif name.removeprefix("painted-") in PAINTED and name.startswith("painted-"):
        image = _painted(name.removeprefix("painted-"))
    elif name in _PHOTOS:
        image = _PHOTOS[name]().astype(np.float32) / 255.0
    else:
        raise ValueError(f"unknown texture {name!r}; choose from {TEXTURE_NAMES}")
    if image.ndim == 2:
        image = np.repeat(image[..., None], 3, axis=2)
    image = srgb_to_linear(image[..., :3]).astype(np.float32)
    scale = min(1.0, _MAX_TEXTURE_SIDE / max(image.shape[:2]))
    step = 2 ** (MIP_LEVELS - 1)
    size = tuple(max(step, round(side * scale / step) * step) for side in image.shape[1::-1])
    if size != image.shape[1::-1]:
        image = cv2.resize(image, size, interpolation=cv2.INTER_AREA)
    levels = [np.ascontiguousarray(image)]
    for _ in range(MIP_LEVELS - 1):
        levels.append(cv2.pyrDown(levels[-1], borderType=cv2.BORDER_WRAP))
    return tuple(levels)
