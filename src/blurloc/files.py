"""Files a command writes: never over one of its inputs, and always whole (atomic rename)."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


def check_output_not_input(
    output: str | os.PathLike, *inputs: str | os.PathLike | None
) -> None:
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
