"""Fetch the real development set from its source repositories and check it against the manifest.

Every file that ``MANIFEST.csv`` lists is taken from the source repository at the commit it
names: the byte copies (blurred photographs, the GoPro pair, the TUM ground-truth files) with
``git show COMMIT:PATH``; the posed frames and the whole recording are written from the
``data/`` folder of jmstark/gpu_odometry at its commit by ``make_posed.py`` and
``blurloc.data.tum.convert_tum``, as the README says. scikit-image's photographs are read from
the installed package and not fetched. ``--parts`` writes only the parts named (a fresh clone
holds every part but ``posed``). At the end every file of those parts is checked against its
sha256 (``blurloc.data.real.verify``); a file that differs is named and the script exits
with 1.

Needs git and, with the default ``--repositories``, access to github.com: of each of the five
repositories only the commit the manifest names is fetched (depth 1; of four of them only the
files listed, of gpu_odometry its whole tree, about 400 MB, for the recording's frames)::

    python samples/real/fetch.py [--out samples/real] [--parts posed ...]
        [--repositories https://github.com/{owner}/{name}.git] [--work /tmp/blurloc-fetch]

``--repositories`` is a template for where each repository is cloned from (``{owner}`` and
``{name}`` filled in), e.g. a folder of local mirrors: ``/mirrors/{owner}+{name}/repo``.
"""

from __future__ import annotations

import argparse
import io
import subprocess
import sys
import tarfile
from pathlib import Path

from blurloc.data import DataError
from blurloc.data.real import (
    PARTS,
    POSED_SCENE,
    RECORDING_SCENE,
    SKIMAGE_PREFIX,
    posed_root,
    read_manifest,
    recording_root,
    verify,
)
from blurloc.data.tum import convert_tum

HERE = Path(__file__).resolve().parent
#: How the posed frames and the recording were written from the recording's ``data/`` folder
#: (the README's commands): the first posed frame's stamp, frames per posed sequence, and the
#: recording's width.
POSED_START_STAMP = "1305031230.865523"
POSED_FRAMES = 40
RECORDING_WIDTH = 160


def repository(name: str, commit: str, template: str, work: Path, blobs: bool = False) -> Path:
    """A git directory of ``name`` (owner/name) that holds ``commit``: a local one the template
    names, else a bare repository under ``work`` into which that one commit is fetched (depth 1,
    once). Without ``blobs`` the files' contents are left on the server and fetched as they are
    read (one file of a large repository); with it they come at once (a folder of it)."""
    owner, short = name.split("/")
    source = template.format(owner=owner, name=short)
    if Path(source).is_dir():
        return Path(source)
    clone = work / f"{owner}+{short}{'' if blobs else '-blobless'}.git"
    check = ["git", "-C", str(clone), "cat-file", "-e", f"{commit}^{{commit}}"]
    if not clone.is_dir() or subprocess.run(check, capture_output=True).returncode != 0:
        subprocess.run(["git", "init", "--quiet", "--bare", str(clone)], check=True)
        subprocess.run(["git", "-C", str(clone), "remote", "add", "origin", source], check=True)
        fetch = ["git", "-C", str(clone), "fetch", "--quiet", "--depth", "1", "origin", commit]
        subprocess.run(fetch if blobs else [*fetch, "--filter=blob:none"], check=True)
    return clone


def git_bytes(git_dir: Path, commit: str, path: str) -> bytes:
    """The bytes of ``path`` at ``commit``."""
    return subprocess.run(["git", "-C", str(git_dir), "show", f"{commit}:{path}"],
                          check=True, capture_output=True).stdout  # fmt: skip


def recording_source(git_dir: Path, commit: str, work: Path) -> Path:
    """The recording's ``data/`` folder at ``commit``, unpacked under ``work``."""
    target = work / f"recording-{commit[:12]}"
    if not (target / "data" / "rgb.txt").is_file():
        archive = subprocess.run(["git", "-C", str(git_dir), "archive", commit, "data"],
                                 check=True, capture_output=True).stdout  # fmt: skip
        with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
            tar.extractall(target, filter="data")
    return target / "data"


def main() -> None:
    """Write every manifest file under ``--out``, then verify them all."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE, help="where the set is written "
                        "(default: this folder, where the package looks first)")  # fmt: skip
    parser.add_argument("--repositories", default="https://github.com/{owner}/{name}.git",
                        help="where each source repository is cloned from")  # fmt: skip
    parser.add_argument("--work", type=Path, default=Path("/tmp/blurloc-fetch"))
    parser.add_argument("--parts", nargs="+", choices=PARTS, default=list(PARTS),
                        help="parts to write (default: every part; a fresh clone lacks only "
                        "posed)")  # fmt: skip
    args = parser.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    entries = [entry for entry in read_manifest() if entry.part in args.parts]
    for entry in entries:
        if entry.part in ("posed", "recording") or entry.file.startswith(SKIMAGE_PREFIX):
            continue
        git_dir = repository(entry.source_repository, entry.commit, args.repositories,
                             args.work)  # fmt: skip
        target = args.out / entry.file
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(git_bytes(git_dir, entry.commit, entry.source_path))
        print(f"wrote {target}", flush=True)
    from_recording = [e for e in entries if e.part in ("posed", "recording") and e.commit]
    if from_recording:
        recording = from_recording[0]
        git_dir = repository(recording.source_repository, recording.commit, args.repositories,
                             args.work, blobs=True)  # fmt: skip
        source = recording_source(git_dir, recording.commit, args.work)
    if "posed" in args.parts:
        subprocess.run([sys.executable, str(HERE / "make_posed.py"), str(source),
                        str(posed_root(args.out) / POSED_SCENE), "--start", POSED_START_STAMP,
                        "--frames", str(POSED_FRAMES)], check=True)  # fmt: skip
    if "recording" in args.parts:
        convert_tum(source, recording_root(args.out), RECORDING_SCENE, width=RECORDING_WIDTH,
                    overwrite=True)  # fmt: skip
    try:
        checked = verify(args.out, parts=args.parts)
    except DataError as error:
        sys.exit(f"the fetched set differs from the manifest: {error}")
    print(f"{len(checked)} files match the manifest's sha256 under {args.out}")


if __name__ == "__main__":
    main()
