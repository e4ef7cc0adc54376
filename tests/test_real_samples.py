"""The real development set: manifest, checksums, and what the reader returns."""

from __future__ import annotations

import csv
import os
import re
import shutil

import cv2
import numpy as np
import pytest

from blurloc.data import load_split
from blurloc.data.real import (
    PARTS,
    POSED_SCENE,
    RECORDING_SCENE,
    ROOT_VARIABLE,
    SKIMAGE_PREFIX,
    DataError,
    data_root,
    entry_path,
    files_present,
    load_pairs,
    load_photographs,
    manifest_path,
    part_entries,
    posed_camera,
    posed_frame_table,
    posed_root,
    read_manifest,
    recording_root,
    sha256_of,
    tum_files,
    verify,
)
from blurloc.data.sevenscenes import read_pose
from blurloc.experiments.real_frames import (
    blur_measures,
    motion_agreement,
    photograph_verdicts,
    posed_frames_with_motion,
    spearman_difference,
    video_motion_lengths,
)

ENTRIES = read_manifest()
FILES_PRESENT = all(entry_path(e).is_file() for e in ENTRIES)


def missing(*parts: str) -> str:
    """Why a test of ``parts`` cannot run, or "" when every file of them is where the reader
    looks: the posed 640x480 frames are fetched (``samples/real/fetch.py``), not committed."""
    present = files_present(*parts)
    if present:
        return ""
    return (f"the development set's {' and '.join(parts)} files are not present: "
            f"python samples/real/fetch.py --parts {' '.join(parts)}")  # fmt: skip


def needs(*parts: str) -> pytest.MarkDecorator:
    """Skip unless every file of ``parts`` is present (:func:`missing`)."""
    reason = missing(*parts)
    return pytest.mark.skipif(bool(reason), reason=reason or "present")


def test_manifest_lists_every_part_with_source_licence_and_commit():
    parts = {entry.part for entry in ENTRIES}
    assert parts == {"sharp", "blurred", "pairs", "posed", "tum", "recording"}
    for entry in ENTRIES:
        if "/" in entry.source_repository and entry.source_repository != "this repository":
            assert len(entry.commit) == 40 and entry.source_path, entry.file
        assert entry.description, entry.file


@pytest.mark.parametrize("part", [part for part in PARTS if part != "sharp"])
def test_every_staged_file_is_in_the_manifest(part):
    """Every file in a part's folder under its data root (the repository's samples/real for the
    committed parts, wherever the fetched ones were placed) is listed, and every listed file of
    the part is there; the sharp photographs ship with scikit-image."""
    if reason := missing(part):
        pytest.skip(reason)
    listed = {e.file for e in part_entries(part) if not e.file.startswith(SKIMAGE_PREFIX)}
    root = data_root(part)
    on_disk = {
        p.relative_to(root).as_posix()
        for p in (root / part).rglob("*")
        if p.is_file() and "__pycache__" not in p.parts
    }
    assert on_disk == listed


@pytest.mark.parametrize("part", PARTS)
def test_checksums_match_the_manifest(part):
    if reason := missing(part):
        pytest.skip(reason)
    for entry in part_entries(part):
        assert sha256_of(entry_path(entry)) == entry.sha256, entry.file


def test_the_committed_parts_are_read_from_the_repository():
    """Every part but the posed frames is committed: a fresh clone reads it from samples/real
    (unless BLURLOC_REAL_DATA names another folder)."""
    if os.environ.get(ROOT_VARIABLE):
        pytest.skip(f"{ROOT_VARIABLE} names the data root")
    for part in ("blurred", "pairs", "tum", "recording"):
        assert files_present(part) and data_root(part) == manifest_path().parent, part


def test_scikit_image_photographs_match_their_checksums(tmp_path):
    manifest = tmp_path / "MANIFEST.csv"
    with manifest_path().open() as source, manifest.open("w") as target:
        rows = [line for line in source if line.startswith(("file,", SKIMAGE_PREFIX))]
        target.writelines(rows)
    assert len(verify(tmp_path, manifest)) == len(rows) - 1 >= 17


def test_verify_checks_the_parts_named(tmp_path):
    """Only the parts named are checked: the scikit-image photographs pass where every other
    part is missing, and an unknown part is refused by name."""
    manifest = tmp_path / "MANIFEST.csv"
    shutil.copyfile(manifest_path(), manifest)
    checked = verify(tmp_path, manifest, parts=["sharp"])
    assert {entry.part for entry in checked} == {"sharp"}
    assert len(checked) == len(part_entries("sharp")) >= 17
    with pytest.raises(DataError, match="missing"):
        verify(tmp_path, manifest, parts=["sharp", "tum"])
    with pytest.raises(ValueError, match="'tums'"):
        verify(tmp_path, manifest, parts=["tums"])


def test_a_changed_or_missing_file_is_named(tmp_path):
    entry = next(e for e in ENTRIES if e.file.startswith(SKIMAGE_PREFIX))
    copy = tmp_path / "photo.png"
    shutil.copyfile(entry_path(entry), copy)
    manifest = tmp_path / "MANIFEST.csv"
    header = manifest_path().read_text().splitlines()[0]
    with manifest.open("w", newline="") as handle:
        handle.write(header + "\n")
        csv.writer(handle).writerow(
            ["photo.png", "sharp", "x/y", "0" * 40, "a.png", "CC0", entry.sha256, "a copy"]
        )
    assert verify(tmp_path, manifest)[0].file == "photo.png"
    copy.write_bytes(copy.read_bytes() + b"\0")
    with pytest.raises(DataError, match=re.escape("photo.png: sha256")):
        verify(tmp_path, manifest)
    copy.unlink()
    with pytest.raises(DataError, match=re.escape("photo.png: missing")):
        verify(tmp_path, manifest)


def test_an_incomplete_manifest_row_is_refused(tmp_path):
    manifest = tmp_path / "MANIFEST.csv"
    lines = manifest_path().read_text().splitlines()
    manifest.write_text("\n".join([lines[0], lines[1].replace(ENTRIES[0].sha256, "abc")]) + "\n")
    with pytest.raises(DataError, match=r"MANIFEST.csv:2: sha256"):
        read_manifest(manifest)


def test_sharp_photographs_are_rgb_images():
    photographs = load_photographs("sharp")
    assert len(photographs) == len(part_entries("sharp")) >= 17
    for name, image in photographs.items():
        assert image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3, name
        assert min(image.shape[:2]) >= 64, name  # the blur analysis needs 64 px


@needs("posed")
def test_posed_frames_have_the_stated_size_and_rigid_poses():
    root = posed_root()
    frames = [s for split in ("train", "test") for s in load_split(root, POSED_SCENE, split)]
    assert sum(len(s) for s in frames) == len(posed_frame_table()) == 80
    video = frames[0].images(frame_ids=frames[0].frame_ids[:3])
    assert video.shape == (3, 480, 640, 3)
    poses = np.concatenate([s.poses() for s in frames])
    rotations = poses[:, :3, :3]
    assert np.allclose(rotations @ rotations.transpose(0, 2, 1), np.eye(3), atol=1e-6)
    assert np.allclose(np.linalg.det(rotations), 1.0, atol=1e-6)
    steps = np.linalg.norm(np.diff(poses[:, :3, 3], axis=0), axis=1)
    assert steps.max() < 0.05  # consecutive 30 Hz frames of a handheld camera
    camera = posed_camera()
    assert camera[0, 0] == pytest.approx(517.3) and camera[1, 2] == pytest.approx(255.3)


@needs("recording")
def test_the_recording_holds_every_frame_with_interleaved_test_sequences():
    train = load_split(recording_root(), RECORDING_SCENE, "train")
    test = load_split(recording_root(), RECORDING_SCENE, "test")
    assert [s.folder.name for s in test] == ["seq-04", "seq-08"]
    assert sum(len(s) for s in train + test) == len(part_entries("recording")) // 2 - 1 == 723
    assert train[0].images(frame_ids=train[0].frame_ids[:1]).shape == (1, 120, 160, 3)
    poses = np.concatenate([s.poses() for s in sorted(train + test, key=lambda s: s.folder)])
    steps = np.linalg.norm(np.diff(poses[:, :3, 3], axis=0), axis=1)
    assert steps.max() < 0.05  # one recording, consecutive across the sequence borders


@needs("recording", "posed")
def test_the_recording_and_the_posed_frames_give_a_frame_one_pose():
    posed = load_split(posed_root(), POSED_SCENE, "train")[0]
    first = posed_frame_table()[0]["stamp"]
    row = next(r for r in csv.DictReader((recording_root() / RECORDING_SCENE / "frames.csv").open())
               if r["stamp"] == first)  # fmt: skip
    same = read_pose(recording_root() / RECORDING_SCENE / row["frame"].replace("color.png",
                     "pose.txt"))  # fmt: skip
    assert np.allclose(same, posed.poses()[0], atol=1e-8)  # the same frame, the same pose


@needs("pairs")
def test_pairs_are_aligned():
    pairs = load_pairs()
    assert pairs
    margin = 4
    for name, blurred, sharp in pairs:
        assert blurred.shape == sharp.shape, name
        gray = [np.float32(cv2.cvtColor(image, cv2.COLOR_RGB2GRAY)) for image in (blurred, sharp)]
        inside = (slice(margin, -margin), slice(margin, -margin))
        errors = {
            (dy, dx): np.mean(
                (np.roll(gray[0], (dy, dx), axis=(0, 1))[inside] - gray[1][inside]) ** 2
            )
            for dy in range(-3, 4)
            for dx in range(-3, 4)
        }
        dy, dx = min(errors, key=errors.get)
        assert abs(dy) <= 1 and abs(dx) <= 1, name  # the blur is centred on the sharp frame


@needs("tum")
def test_tum_files_hold_unit_quaternions():
    for path in tum_files():
        table = np.loadtxt(path, comments="#")
        assert table.shape[1] == 8 and len(table) > 1000, path
        assert np.allclose(np.linalg.norm(table[:, 4:], axis=1), 1.0, atol=1e-3), path


def test_files_present_answers_per_part(tmp_path):
    assert files_present("sharp")  # scikit-image's photographs ship with it
    assert not files_present("posed", root=tmp_path)
    assert files_present() == FILES_PRESENT


@needs("posed", "blurred")
def test_real_stages_measure_the_real_files():
    images, motion = posed_frames_with_motion(step=10)
    assert images.shape[1:] == (480, 640, 3) and len(images) == len(motion) == 8
    assert (motion > 0).all()
    measures = blur_measures(images[:3], scale=4)
    assert set(measures) == {"blind length (px)", "detector score (px)",
                             "negated variance of the Laplacian"}  # fmt: skip
    assert all(values.shape == (3,) and np.isfinite(values).all() for values in measures.values())
    agreement = motion_agreement(measures, motion[:3])
    lengths = video_motion_lengths(images[:3], scale=4)
    assert lengths.shape == (3,) and np.isfinite(lengths).all() and (lengths >= 0).all()
    assert [row["frames"] for row in agreement] == [3, 3, 3]
    verdicts = photograph_verdicts()
    assert {row["part"] for row in verdicts} == {"sharp", "blurred"}
    assert all(row["reported"] in ("sharp", "blurred") for row in verdicts)


def test_spearman_difference_resolves_a_better_measure_and_not_an_equal_one():
    rng = np.random.default_rng(3)
    motion = np.cumsum(rng.normal(size=80)) + 40  # correlated from frame to frame, as a camera's
    follows = motion + rng.normal(0, 1, 80)
    ignores = rng.normal(size=80)
    better = spearman_difference(follows, ignores, motion, resamples=400)
    assert better.mean > 0.8 and better.low > 0.5 and better.pairs == 80
    same = spearman_difference(follows, follows, motion, resamples=400)
    assert same.mean == same.low == same.high == 0.0
    swapped = spearman_difference(ignores, follows, motion, resamples=400)
    assert swapped.mean == pytest.approx(-better.mean) and swapped.high < 0
    with pytest.raises(ValueError, match="differ in length"):
        spearman_difference(follows[:79], ignores, motion)
    with pytest.raises(ValueError, match="two blocks"):
        spearman_difference(follows[:15], ignores[:15], motion[:15])


def test_the_named_folder_is_looked_in_first_part_by_part(tmp_path, monkeypatch):
    """A folder named by BLURLOC_REAL_DATA that holds one part serves that part; the parts it
    lacks are still read from the repository."""
    tum = part_entries("tum")
    if reason := missing("tum"):
        pytest.skip(reason)
    for entry in tum:
        (tmp_path / entry.file).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(entry_path(entry), tmp_path / entry.file)
    monkeypatch.setenv(ROOT_VARIABLE, str(tmp_path))
    assert data_root("tum") == tmp_path
    assert entry_path(tum[0]) == tmp_path / tum[0].file
    if (manifest_path().parent / part_entries("recording")[0].file).is_file():
        assert data_root("recording") == manifest_path().parent
