"""Files the commands read and write: an output never over an input, into a dataset or over a
training run, every file written whole (atomic rename), images checked from their header before
they are decoded and kept at their own bit depth and with their alpha channel, files carried
into a copy by hard link."""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from .image_headers import MAX_PIXELS_VARIABLE, ImageHeader, max_pixels, parse_header
from .images import IMAGE_SUFFIXES

#: Image suffixes whose files store 16-bit samples and an alpha channel (others: 8-bit colour).
DEEP_SUFFIXES = (".png", ".tif", ".tiff")
#: Files whose presence makes a folder a scene of a 7-Scenes-layout dataset.
SPLIT_FILES = ("TrainSplit.txt", "TestSplit.txt")
#: Files of a training run folder (the two checkpoints first); only the trainer writes them.
RUN_FILES = ("last.pt", "best.pt", "history.json")


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


def dataset_folder(path: str | os.PathLike) -> Path | None:
    """The folder of a 7-Scenes-layout dataset that ``path`` is or lies in, if any.

    A folder belongs to a dataset when it holds split files (:data:`SPLIT_FILES`: a scene),
    ground-truth poses (``frame-*.pose.txt``: a sequence), or a subfolder with split files (a
    root). A folder of deblurred frames alone (what ``deblur-video`` writes) is not a dataset.

    Parameters
    ----------
    path : str or os.PathLike
        A file or folder, existing or not.

    Returns
    -------
    pathlib.Path or None
        The innermost such folder among ``path`` and its parents; None when there is none.
    """
    resolved = Path(path).resolve()
    for folder in (resolved, *resolved.parents):
        if folder.is_dir() and _holds_dataset(folder):
            return folder
    return None


def _holds_dataset(folder: Path) -> bool:
    def scene(candidate: Path) -> bool:
        return any((candidate / name).is_file() for name in SPLIT_FILES)

    try:
        return (
            scene(folder)
            or next(folder.glob("frame-*.pose.txt"), None) is not None
            or any(child.is_dir() and scene(child) for child in folder.iterdir())
        )
    except OSError:  # a folder this user may not list holds nothing this command reads
        return False


def check_output(
    output: str | os.PathLike,
    *inputs: str | os.PathLike | None,
    names: Iterable[str] | None = None,
    overwrite: bool = False,
) -> None:
    """Refuse an output that would write over or into an input, a dataset or a training run.

    The shared check of every command that writes: ``output`` is none of the inputs and lies
    in none of the input folders (:func:`check_output_not_input`), lies in no 7-Scenes-layout
    dataset (:func:`dataset_folder`), is not a file of a training run (:data:`RUN_FILES` beside
    a ``best.pt`` or ``last.pt``), and replaces no existing file unless ``overwrite``.

    Parameters
    ----------
    output : str or os.PathLike
        The file, or the folder, the command is about to write.
    *inputs : str or os.PathLike or None
        Files or folders the command reads; ``None`` entries (options not given) are skipped.
    names : iterable of str, optional
        When ``output`` is a folder: the names of the files the command writes into it (an
        empty tuple for a folder whose files the command manages itself, such as a run
        folder). None when ``output`` is a file.
    overwrite : bool
        Allow replacing existing files of the same names (the option ``--overwrite``).

    Raises
    ------
    ValueError
        Naming the output and the reason, before anything is written.
    """
    check_output_not_input(output, *inputs)
    target = Path(output)
    dataset = dataset_folder(target)
    if dataset is not None:
        raise ValueError(f"{output}: lies in the dataset {dataset} (it holds split files or "
                         "ground-truth poses); write outside it")  # fmt: skip
    if target.name in RUN_FILES and any((target.parent / n).is_file() for n in RUN_FILES[:2]):
        raise ValueError(f"{output}: is a file of the training run in {target.parent}; "
                         "write elsewhere")  # fmt: skip
    if names is None:
        if target.is_dir():
            raise ValueError(f"{output}: is a folder; give a file to write")
        clash = [target.name] if target.exists() else []
    else:
        if target.exists() and not target.is_dir():
            raise ValueError(f"{output}: exists and is not a folder; give a folder to write")
        clash = sorted(n for n in names if (target / n).exists())
    if clash and not overwrite:
        where = (
            "exists"
            if names is None
            else f"already holds {len(clash)} file(s) of the names to write (e.g. {clash[0]})"
        )
        raise ValueError(f"{output}: {where}; give --overwrite to replace")  # fmt: skip


def image_files(folder: str | os.PathLike) -> list[Path]:
    """The images a folder command reads, in name order.

    In a 7-Scenes sequence folder only the colour frames (``frame-*.color.png``): never its
    depth maps or the stand-in's sharp frames. In any other folder every file with an image
    suffix (:data:`~blurloc.images.IMAGE_SUFFIXES`).

    Parameters
    ----------
    folder : str or os.PathLike
        An existing folder.

    Returns
    -------
    list of pathlib.Path
        Possibly empty.
    """
    folder = Path(folder)
    frames = sorted(p for p in folder.glob("frame-*.color.png") if p.is_file())
    if frames:
        return frames
    return sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() in IMAGE_SUFFIXES)


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


def image_header(path: str | os.PathLike) -> ImageHeader:
    """The header of an image file, checked against the pixel cap and for completeness.

    Parameters
    ----------
    path : str or os.PathLike
        A PNG, JPEG, BMP or TIFF file.

    Returns
    -------
    ImageHeader
        Its size, bit depth and channels.

    Raises
    ------
    ValueError
        Naming the file, when it is a folder, missing, of another format, truncated, or larger
        than the pixel cap (:func:`~blurloc.image_headers.max_pixels`, naming the cap and
        :data:`~blurloc.image_headers.MAX_PIXELS_VARIABLE`).
    """
    return _checked_header(Path(path), _file_bytes(Path(path)))


def _file_bytes(path: Path) -> bytes:
    if path.is_dir():
        raise ValueError(f"{path}: is a folder, not an image file")
    if not path.is_file():
        raise ValueError(f"{path}: image file is missing")
    return path.read_bytes()


def _checked_header(path: Path, data: bytes) -> ImageHeader:
    header = parse_header(data)
    if header is None:
        raise ValueError(f"{path}: image cannot be read (damaged, or not a PNG, JPEG, BMP or "
                         "TIFF image)")  # fmt: skip
    cap = max_pixels()
    if header.pixels > cap:
        raise ValueError(f"{path}: {header.width}x{header.height} pixels is more than the cap "
                         f"of {cap:,} pixels; set {MAX_PIXELS_VARIABLE} to raise it")  # fmt: skip
    if not header.complete:
        raise ValueError(f"{path}: image file is truncated (its {header.format} data stops "
                         "early); refusing a partly decoded image")  # fmt: skip
    return header


def decode_image(path: str | os.PathLike, flags: int) -> np.ndarray:
    """Decode an image file with OpenCV after checking its header, or raise a ValueError
    naming it.

    The file is read once; its header (:func:`image_header`) is checked against the pixel cap
    and for truncation before a pixel is decoded.

    Parameters
    ----------
    path : str or os.PathLike
        Image file (PNG, JPEG, BMP or TIFF).
    flags : int
        ``cv2.IMREAD_*`` flags.

    Returns
    -------
    numpy.ndarray
        The pixels as OpenCV returns them (BGR order).

    Raises
    ------
    ValueError
        Naming the file, when it is missing, a folder, damaged, truncated, not an image, or
        larger than the pixel cap.
    """
    import cv2  # here, so that commands which read no image start fast

    path = Path(path)
    data = _file_bytes(path)
    _checked_header(path, data)
    image = cv2.imdecode(np.frombuffer(data, np.uint8), flags)
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
        (H, W) gray or (H, W, 3) RGB: uint8 (written 8-bit), uint16 (written as it is where the
        suffix allows, else reduced to 8-bit) or float on [0, 1] (written 16-bit where the
        suffix allows, else 8-bit; clipped).
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
    if image.dtype != np.uint8 and not (deep and image.dtype == np.uint16):
        lost += [] if deep else ["16-bit depth"]
        dtype = np.uint16 if deep else np.uint8
        if image.dtype == np.uint16:
            image = image / np.float64(np.iinfo(np.uint16).max)
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
