"""Files the commands read and write: an output never over an input, every file written whole
(atomic rename), images kept at their own bit depth and with their alpha channel, files carried
into a copy by hard link."""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np

#: Image suffixes whose files store 16-bit samples and an alpha channel (others: 8-bit colour).
DEEP_SUFFIXES = (".png", ".tif", ".tiff")


def check_output_not_input(output: str | os.PathLike, *inputs: str | os.PathLike | None) -> None:
    """Refuse an output path that is one of the inputs or lies inside an input folder.

    Paths are compared after resolving symbolic links and ``..``; an existing output is also
    compared by file identity (hard links). Call it before anything is written.

    Parameters
    ----------
    output : str or os.PathLike
        File or folder the command is about to write.
    *inputs : str or os.PathLike or None
        Files or folders the command reads; ``None`` entries (options not given) are skipped.

    Raises
    ------
    ValueError
        Naming both paths, when ``output`` is an input or lies inside an input folder.
    """
    target = Path(output).resolve()
    for source in inputs:
        if source is None:
            continue
        resolved = Path(source).resolve()
        same = target == resolved or (
            target.exists() and resolved.exists() and os.path.samefile(target, resolved)
        )
        if same:
            raise ValueError(f"{output}: output is the input {source}; refusing to overwrite it")
        if resolved.is_dir() and resolved in target.parents:
            raise ValueError(
                f"{output}: output lies inside the input folder {source}; choose another place"
            )


@contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """A temporary file beside ``path`` that replaces ``path`` only when the block succeeds.

    The temporary name keeps ``path``'s suffix (so writers that choose the format from the
    suffix, such as ``cv2.imwrite``, still work) and starts with a dot. On success it is renamed
    over ``path`` (atomic on one file system), so a reader never sees half a file; on failure it
    is removed and ``path`` is left as it was. The file gets the permissions a new file would
    get under the current umask.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; its folder is created if missing.

    Yields
    ------
    pathlib.Path
        The temporary file to write (it exists, empty).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=path.suffix)
    os.close(handle)
    temporary = Path(name)
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(temporary, 0o666 & ~umask)
        yield temporary
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


def decode_image(path: str | os.PathLike, flags: int) -> np.ndarray:
    """Decode an image file with OpenCV, or raise a ValueError naming it.

    Parameters
    ----------
    path : str or os.PathLike
        Image file.
    flags : int
        ``cv2.IMREAD_*`` flags.

    Returns
    -------
    numpy.ndarray
        The pixels as OpenCV returns them (BGR order).

    Raises
    ------
    ValueError
        Naming the file, when it is missing, damaged or not an image.
    """
    import cv2  # here, so that commands which read no image start fast

    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: image file is missing")
    image = cv2.imread(str(path), flags)
    if image is None:
        raise ValueError(f"{path}: image cannot be read (damaged or not an image)")
    return image


def read_image_file(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray | None]:
    """Read an image at its own bit depth, gray or colour, with its alpha channel.

    Parameters
    ----------
    path : str or os.PathLike
        An 8- or 16-bit gray, RGB or RGBA image file.

    Returns
    -------
    pixels : numpy.ndarray
        (H, W) gray or (H, W, 3) RGB; uint8 for an 8-bit file, float64 on [0, 1] for a 16-bit
        one (the filters keep float, so no precision is lost on the way).
    alpha : numpy.ndarray or None
        (H, W) alpha in the file's own dtype, or None.

    Raises
    ------
    ValueError
        Naming the file, when it is missing, unreadable or of another pixel type.
    """
    import cv2  # here, so that commands which read no image start fast

    image = decode_image(path, cv2.IMREAD_UNCHANGED)
    channels = image.shape[2] if image.ndim == 3 else 1
    if image.dtype not in (np.uint8, np.uint16) or channels not in (1, 3, 4):
        raise ValueError(f"{path}: {image.dtype} image with shape {image.shape} not supported; "
                         "use 8- or 16-bit gray, RGB or RGBA images")  # fmt: skip
    alpha = image[..., 3].copy() if channels == 4 else None
    pixels = image if channels == 1 else image[..., 2::-1]  # BGR(A) -> RGB
    if image.dtype == np.uint8:
        return pixels.copy(), alpha
    return pixels / 65535.0, alpha


def write_image_file(
    path: str | os.PathLike, image: np.ndarray, alpha: np.ndarray | None = None
) -> list[str]:
    """Write an image atomically, as deep as ``path``'s suffix allows.

    Parameters
    ----------
    path : str or os.PathLike
        Image file; ``.png`` and ``.tif`` keep 16-bit samples and alpha, other suffixes store
        8-bit colour.
    image : numpy.ndarray
        (H, W) gray or (H, W, 3) RGB: uint8 (written 8-bit) or float on [0, 1] (written 16-bit
        where the suffix allows, else 8-bit; clipped).
    alpha : numpy.ndarray, optional
        (H, W) alpha, uint8 or uint16, written beside the colour where the suffix allows.

    Returns
    -------
    list of str
        What the suffix could not keep: "16-bit depth" and/or "alpha" (empty when nothing).

    Raises
    ------
    ValueError
        Naming the file, when it cannot be written.
    """
    import cv2  # here, so that commands which write no image start fast

    path = Path(path)
    deep = path.suffix.lower() in DEEP_SUFFIXES
    lost = []
    if image.dtype != np.uint8:
        lost += [] if deep else ["16-bit depth"]
        dtype = np.uint16 if deep else np.uint8
        image = np.round(np.clip(image, 0.0, 1.0) * np.iinfo(dtype).max).astype(dtype)
    pixels = image if image.ndim == 2 else image[..., ::-1]  # RGB -> BGR
    if alpha is not None and not deep:
        lost.append("alpha")
    elif alpha is not None:
        if alpha.dtype != pixels.dtype:  # one depth for all channels
            alpha = (alpha // 257 if pixels.dtype == np.uint8 else alpha * 257).astype(pixels.dtype)
        colour = cv2.cvtColor(pixels, cv2.COLOR_GRAY2BGR) if pixels.ndim == 2 else pixels
        pixels = np.dstack([colour, alpha])
    with atomic_path(path) as temporary:
        try:
            written = cv2.imwrite(str(temporary), pixels)
        except cv2.error:
            written = False
        if not written:
            raise ValueError(f"{path}: cannot write this image")
    return lost


def link_or_copy(source: str | os.PathLike, target: str | os.PathLike) -> None:
    """Carry ``source`` over to ``target``: a hard link (no copy of the bytes) where the file
    system allows it, else a copy; an existing ``target`` is replaced.

    Parameters
    ----------
    source : str or os.PathLike
        An existing file.
    target : str or os.PathLike
        Where it must also appear.
    """
    target = Path(target)
    target.unlink(missing_ok=True)
    try:
        os.link(source, target)
    except OSError:
        shutil.copyfile(source, target)
