"""Reader of the real development set described by ``samples/real/MANIFEST.csv``. Torch-free.

The manifest lists every file with its part (``sharp``, ``blurred``, ``pairs``, ``posed``,
``tum``, ``recording``), source repository, commit, path in the source, licence and sha256.
Files named ``skimage:<name>`` are read from the installed scikit-image; the others from their
part's data root (:func:`data_root`). Every problem is reported as a
:class:`~blurloc.data.sevenscenes.DataError` naming the file.
"""

from __future__ import annotations

import csv
import functools
import hashlib
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import skimage
import skimage.io

from ..config import project_root
from .sevenscenes import DataError

ROOT_VARIABLE = "BLURLOC_REAL_DATA"


def manifest_path() -> Path:
    """``samples/real/MANIFEST.csv`` of the project (:func:`blurloc.config.project_root`: found
    from the working folder, or named by ``BLURLOC_ROOT``)."""
    return project_root() / "samples" / "real" / "MANIFEST.csv"


PARTS = ("sharp", "blurred", "pairs", "posed", "tum", "recording")
POSED_SCENE = "fr1_rpy"
#: Scene of the ``recording`` part: a whole real recording in the 7-Scenes layout.
RECORDING_SCENE = "fr1_rpy"
SKIMAGE_PREFIX = "skimage:"
_COLUMNS = ["file", "part", "source_repository", "commit", "source_path", "licence", "sha256",
            "description"]  # fmt: skip


@dataclass(frozen=True)
class ManifestEntry:
    """One row of the manifest: a file of the development set and where it came from."""

    file: str
    part: str
    source_repository: str
    commit: str
    source_path: str
    licence: str
    sha256: str
    description: str


def read_manifest(path: str | os.PathLike | None = None) -> list[ManifestEntry]:
    """Read the manifest and check that every row is complete.

    Parameters
    ----------
    path : str or os.PathLike, optional
        The manifest CSV (default :func:`manifest_path`).

    Returns
    -------
    list of ManifestEntry
        In file order.

    Raises
    ------
    DataError
        Naming the manifest (and line) when it is missing, its header differs, a row lacks a
        file, part, source, licence or a 64-digit sha256, a part is unknown, or a file repeats.
    """
    path = Path(path) if path is not None else manifest_path()
    if not path.is_file():
        raise DataError(f"{path}: manifest is missing")
    stat = path.stat()
    return list(_parsed_manifest(str(path), stat.st_mtime_ns, stat.st_size))


@functools.lru_cache(maxsize=8)
def _parsed_manifest(name: str, mtime_ns: int, size: int) -> tuple[ManifestEntry, ...]:
    """The checked rows of the manifest ``name``, parsed once per version of the file (its
    modification time and size key the cache: the set's lookups read it once per file)."""
    path = Path(name)
    with path.open(newline="") as handle:
        reader = csv.DictReader(handle)
        if reader.fieldnames != _COLUMNS:
            raise DataError(f"{path}: header must be {','.join(_COLUMNS)}")
        entries = [ManifestEntry(**row) for row in reader]
    seen: set[str] = set()
    for line, entry in enumerate(entries, start=2):
        if not (entry.file and entry.source_repository and entry.licence):
            raise DataError(f"{path}:{line}: file, source_repository and licence are required")
        if entry.part not in PARTS:
            raise DataError(f"{path}:{line}: part {entry.part!r} is not one of {PARTS}")
        if len(entry.sha256) != 64 or set(entry.sha256) - set("0123456789abcdef"):
            raise DataError(f"{path}:{line}: sha256 of {entry.file} is not 64 hex digits")
        if entry.file in seen:
            raise DataError(f"{path}:{line}: {entry.file} is listed twice")
        seen.add(entry.file)
    return tuple(entries)


def data_root(part: str | None = None) -> Path:
    """Folder holding the development set's files, or those of one part.

    The first of the folder named by the environment variable ``BLURLOC_REAL_DATA`` (when it
    is set), ``samples/real`` and ``../shared/real`` (beside the repository) that holds the
    first file outside scikit-image of ``part`` (of the whole manifest when None): the parts
    committed with the repository are read from ``samples/real`` unless the variable's folder
    holds them too, the others from wherever they were placed; when no folder holds it, the
    variable's folder if set, else ``samples/real``.

    Parameters
    ----------
    part : str, optional
        A part of the manifest (``PARTS``).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ValueError
        If ``part`` is not one of PARTS.
    DataError
        If the manifest cannot be read (:func:`read_manifest`).
    """
    local = manifest_path().parent
    named = [Path(os.environ[ROOT_VARIABLE])] if os.environ.get(ROOT_VARIABLE) else []
    entries = read_manifest() if part is None else part_entries(part)
    files = [e.file for e in entries if not e.file.startswith(SKIMAGE_PREFIX)]
    for candidate in [*named, local, local.parents[2] / "shared" / "real"]:
        if files and (candidate / files[0]).is_file():
            return candidate
    return named[0] if named else local


def entry_path(entry: ManifestEntry, root: str | os.PathLike | None = None) -> Path:
    """Where a manifest file lies: in scikit-image's data folder, or under ``root`` (default
    its part's :func:`data_root`)."""
    if entry.file.startswith(SKIMAGE_PREFIX):
        return Path(skimage.__file__).parent / "data" / entry.file.removeprefix(SKIMAGE_PREFIX)
    return Path(root if root is not None else data_root(entry.part)) / entry.file


def sha256_of(path: str | os.PathLike) -> str:
    """Hex sha256 of a file's bytes."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def verify(
    root: str | os.PathLike | None = None,
    manifest: str | os.PathLike | None = None,
    parts: Sequence[str] | None = None,
) -> list[ManifestEntry]:
    """Check every file of the manifest (or of some of its parts) against its sha256.

    Parameters
    ----------
    root : str or os.PathLike, optional
        Data root (each part's :func:`data_root` when None).
    manifest : str or os.PathLike, optional
        The manifest CSV (default :func:`manifest_path`).
    parts : sequence of str, optional
        Parts to check (``PARTS``; default every part).

    Returns
    -------
    list of ManifestEntry
        The entries checked.

    Raises
    ------
    ValueError
        If a part is not one of PARTS.
    DataError
        Naming the first file that is missing or whose sha256 differs from the manifest's.

    Examples
    --------
    >>> from blurloc.data.real import verify
    >>> len(verify(parts=["tum"]))  # the two TUM ground-truth files of a fresh clone
    2
    """
    unknown = sorted(set(parts or ()) - set(PARTS))
    if unknown:
        raise ValueError(f"parts must be among {PARTS}, got {unknown}")
    entries = [entry for entry in read_manifest(manifest) if parts is None or entry.part in parts]
    for entry in entries:
        path = entry_path(entry, root)
        if not path.is_file():
            raise DataError(f"{path}: missing (listed in {manifest} as {entry.file})")
        digest = sha256_of(path)
        if digest != entry.sha256:
            raise DataError(f"{path}: sha256 {digest} differs from the manifest's {entry.sha256}")
    return entries


def part_entries(part: str, manifest: str | os.PathLike | None = None) -> list[ManifestEntry]:
    """The manifest's entries of one part (``sharp``, ``blurred``, ``pairs``, ``posed``,
    ``tum``, ``recording``), in manifest order."""
    if part not in PARTS:
        raise ValueError(f"part must be one of {PARTS}, got {part!r}")
    return [entry for entry in read_manifest(manifest) if entry.part == part]


def files_present(*parts: str, root: str | os.PathLike | None = None) -> bool:
    """Whether every file of the given parts (all parts when none is given) lies where
    :func:`entry_path` looks: a fresh clone holds every part but the posed frames.

    Parameters
    ----------
    *parts : str
        Parts of the manifest (``PARTS``).
    root : str or os.PathLike, optional
        Data root (each part's :func:`data_root` when None).

    Returns
    -------
    bool
        True when each file exists (its checksum is not read: see :func:`verify`).
    """
    entries = [e for part in parts for e in part_entries(part)] if parts else read_manifest()
    return all(entry_path(entry, root).is_file() for entry in entries)


def _stem(entry: ManifestEntry) -> str:
    return Path(entry.file.removeprefix(SKIMAGE_PREFIX)).stem


def _read_photograph(path: Path) -> np.ndarray:
    """A photograph as RGB uint8 (H, W, 3): gray repeated over three channels, alpha dropped.
    Read by scikit-image (Pillow), which decodes the same pixels as OpenCV but prints no libpng
    warnings (scikit-image's ``page.png`` carries a colour profile that libpng objects to)."""
    image = skimage.io.imread(path)
    image = image[..., None] if image.ndim == 2 else image
    image = image[..., :-1] if image.shape[2] in (2, 4) else image
    if image.dtype != np.uint8:
        raise DataError(f"{path}: expected an 8-bit photograph, got {image.dtype}")
    return np.ascontiguousarray(np.repeat(image, 3, axis=2) if image.shape[2] == 1 else image)


def load_photographs(part: str, root: str | os.PathLike | None = None) -> dict[str, np.ndarray]:
    """The photographs of part ``sharp`` or ``blurred``, by file stem, as RGB uint8 (H, W, 3)
    (gray photographs repeated over three channels)."""
    if part not in ("sharp", "blurred"):
        raise ValueError(f"part must be 'sharp' or 'blurred', got {part!r}")
    return {_stem(e): _read_photograph(entry_path(e, root)) for e in part_entries(part)}


def load_pairs(root: str | os.PathLike | None = None) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The blurred/sharp pairs, cut to their common top-left area.

    Returns
    -------
    list of (str, numpy.ndarray, numpy.ndarray)
        Name (the blurred file's stem without ``_blur``), blurred and sharp RGB uint8 images of
        equal shape.

    Raises
    ------
    DataError
        When a ``_blur`` file has no ``_sharp`` partner in the manifest.
    """
    files = {e.file: e for e in part_entries("pairs")}
    pairs = []
    for name, entry in files.items():
        if not name.endswith("_blur" + Path(name).suffix):
            continue
        partner = name.replace("_blur", "_sharp")
        if partner not in files:
            raise DataError(f"{entry_path(entry, root)}: no sharp partner {partner} listed")
        blurred = _read_photograph(entry_path(entry, root))
        sharp = _read_photograph(entry_path(files[partner], root))
        height, width = (min(a, b) for a, b in zip(blurred.shape[:2], sharp.shape[:2], strict=True))
        pairs.append((_stem(entry).removesuffix("_blur"), blurred[:height, :width],
                      sharp[:height, :width]))  # fmt: skip
    return pairs


def posed_root(root: str | os.PathLike | None = None) -> Path:
    """The 7-Scenes-layout root of the posed frames (scene ``fr1_rpy``), for
    :func:`~blurloc.data.sevenscenes.load_split`."""
    return Path(root if root is not None else data_root("posed")) / "posed"


def recording_root(root: str | os.PathLike | None = None) -> Path:
    """The 7-Scenes-layout root of the whole real recording (scene ``fr1_rpy``: every frame of
    TUM RGB-D ``freiburg1_rpy`` at 160x120, cut into 10 sequences, every 4th held out as the
    test split; written by :func:`blurloc.data.tum.convert_tum`), for
    :func:`~blurloc.data.sevenscenes.load_split`."""
    return Path(root if root is not None else data_root("recording")) / "recording"


def posed_camera(root: str | os.PathLike | None = None) -> np.ndarray:
    """The posed frames' 3x3 camera matrix, from ``intrinsics.txt`` (first line fx fy cx cy).

    .. math:: K = \\begin{pmatrix} f_x & 0 & c_x \\\\ 0 & f_y & c_y \\\\ 0 & 0 & 1 \\end{pmatrix}
    """
    path = posed_root(root) / POSED_SCENE / "intrinsics.txt"
    lines = [line for line in path.read_text().splitlines() if not line.startswith("#")]
    fx, fy, cx, cy = (float(v) for v in lines[0].split())
    return np.array([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]])


def posed_frame_table(root: str | os.PathLike | None = None) -> list[dict[str, str]]:
    """Rows of the posed frames' ``frames.csv``: frame file, sequence, TUM stamp, source file,
    depth stamp and median depth in metres, in recording order."""
    with (posed_root(root) / POSED_SCENE / "frames.csv").open(newline="") as handle:
        return list(csv.DictReader(handle))


def tum_files(root: str | os.PathLike | None = None) -> list[Path]:
    """The real TUM RGB-D ground-truth files (``stamp tx ty tz qx qy qz qw`` lines)."""
    return [entry_path(entry, root) for entry in part_entries("tum")]
