"""TUM RGB-D recordings written as 7-Scenes scenes: poses at frame stamps, sequences, split."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from blurloc.cli import main
from blurloc.data import load_split
from blurloc.data.real import POSED_SCENE, posed_frame_table, posed_root, tum_files
from blurloc.data.sevenscenes import DataError, read_image, read_pose
from blurloc.data.tum import convert_tum, pose_at, read_groundtruth, split_sequences

GROUND_TRUTH = next(path for path in tum_files() if "fr1_rpy" in path.name)
needs_files = pytest.mark.skipif(
    not GROUND_TRUTH.is_file() or not (posed_root() / POSED_SCENE).is_dir(),
    reason="the development set's TUM files or posed frames (which these tests read) are not "
    "present: python samples/real/fetch.py --parts tum posed",
)


@needs_files
def test_pose_at_gives_the_committed_poses_of_real_frames():
    stamps, rows = read_groundtruth(GROUND_TRUTH)
    for row in posed_frame_table()[::7]:
        committed = read_pose(posed_root() / POSED_SCENE / row["frame"].replace(
            ".color.png", ".pose.txt"))  # fmt: skip
        assert np.allclose(pose_at(stamps, rows, float(row["stamp"])), committed, atol=1e-8)


def test_pose_at_interpolates_position_linearly_and_rotation_by_slerp():
    stamps = np.array([0.0, 1.0, 2.0])
    quaternions = Rotation.from_rotvec([[0, 0, 0], [0, 0, np.pi / 2], [0, 0, np.pi / 2]]).as_quat()
    rows = np.hstack([[[0, 0, 0], [2, 0, 0], [2, 4, 0]], quaternions])
    assert np.allclose(pose_at(stamps, rows, 1.0)[:3, 3], [2, 0, 0])
    quarter = pose_at(stamps, rows, 0.25)
    assert np.allclose(quarter[:3, 3], [0.5, 0, 0])
    angle = Rotation.from_matrix(quarter[:3, :3]).as_rotvec()
    assert np.allclose(angle, [0, 0, np.pi / 8])  # a quarter of the way, at constant speed
    assert np.allclose(pose_at(stamps, rows, 1.5)[:3, 3], [2, 2, 0])
    with pytest.raises(ValueError, match="outside the ground truth"):
        pose_at(stamps, rows, 2.5)


def test_a_damaged_ground_truth_is_named(tmp_path):
    path = tmp_path / "groundtruth.txt"
    path.write_text("# comment\n1.0 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n")
    with pytest.raises(DataError, match=r"groundtruth\.txt: stamps do not increase"):
        read_groundtruth(path)
    path.write_text("1.0 0 0 0 0 0 0\n2.0 0 0 0 0 0 0\n")
    with pytest.raises(DataError, match=r"groundtruth\.txt: needs at least two lines"):
        read_groundtruth(path)


def test_sequences_are_contiguous_and_test_sequences_interleaved():
    plan = split_sequences(723, 10, 4)
    numbers = [number for number, _ in plan]
    assert numbers == sorted(numbers) and set(numbers) == set(range(1, 11))
    assert {numbers.count(k) for k in range(1, 11)} == {72, 73}
    assert sorted({number for number, test in plan if test}) == [4, 8]
    with pytest.raises(ValueError, match="test_every"):
        split_sequences(10, 3, 4)
    with pytest.raises(ValueError, match="sequences"):
        split_sequences(3, 5, 2)


def _recording(folder: Path, count: int) -> Path:
    """A TUM recording folder holding ``count`` of the development set's real frames."""
    (folder / "rgb").mkdir(parents=True)
    lines = ["# color images"]
    for row in posed_frame_table()[:count]:
        shutil.copyfile(posed_root() / POSED_SCENE / row["frame"], folder / row["source"])
        lines.append(f"{row['stamp']} {row['source']}")
    (folder / "rgb.txt").write_text("\n".join(lines) + "\n")
    shutil.copyfile(GROUND_TRUTH, folder / "groundtruth.txt")
    return folder


@needs_files
def test_a_real_recording_converts_to_a_readable_scene(tmp_path):
    source = _recording(tmp_path / "recording", 12)
    scene = convert_tum(source, tmp_path / "root", "rpy", sequences=4, test_every=2, width=80)
    train = load_split(tmp_path / "root", "rpy", "train")
    test = load_split(tmp_path / "root", "rpy", "test")
    assert [len(s) for s in train] == [3, 3] and [len(s) for s in test] == [3, 3]
    assert (scene / "TestSplit.txt").read_text() == "sequence2\nsequence4\n"
    assert read_image(train[0].path(0)).shape == (60, 80, 3)
    committed = [read_pose(posed_root() / POSED_SCENE / row["frame"].replace(".color.png",
                 ".pose.txt")) for row in posed_frame_table()[:12]]  # fmt: skip
    converted = np.concatenate([s.poses() for s in sorted(train + test, key=lambda s: s.folder)])
    assert np.allclose(converted, committed, atol=1e-8)
    assert not list((tmp_path / "root").rglob(".*")), "a temporary file of a writer is left over"
    with pytest.raises(ValueError, match="exists"):
        convert_tum(source, tmp_path / "root", "rpy")


@needs_files
def test_convert_tum_command_copies_frames_and_refuses_a_missing_file(tmp_path, capsys):
    source = _recording(tmp_path / "recording", 6)
    assert main(["convert-tum", str(source), str(tmp_path / "root"), "--scene", "rpy",
                 "--sequences", "3", "--test-every", "3"]) == 0  # fmt: skip
    first = tmp_path / "root" / "rpy" / "seq-01" / "frame-000000.color.png"
    assert first.read_bytes() == (posed_root() / POSED_SCENE / "seq-01" /
                                  "frame-000000.color.png").read_bytes()  # fmt: skip
    (source / "groundtruth.txt").unlink()
    assert main(["convert-tum", str(source), str(tmp_path / "other"), "--scene", "rpy"]) == 1
    assert "groundtruth.txt: missing" in capsys.readouterr().err


@pytest.mark.parametrize("scene", ["", ".", "..", "a/b"])
def test_convert_tum_refuses_a_scene_that_is_not_a_plain_name(tmp_path, scene):
    (tmp_path / "dataset").mkdir()
    kept = tmp_path / "dataset" / "kept.txt"
    kept.write_text("x")
    with pytest.raises(ValueError, match="plain folder name"):
        convert_tum(tmp_path / "recording", tmp_path / "dataset", scene, overwrite=True)
    assert kept.read_text() == "x"


def test_convert_tum_never_deletes_the_recording_it_reads(tmp_path):
    recording = tmp_path / "root" / "rec"
    recording.mkdir(parents=True)
    for name in ("rgb.txt", "groundtruth.txt"):
        (recording / name).write_text("# kept\n")
    with pytest.raises(ValueError, match="output is the input"):  # out/scene is the recording
        convert_tum(recording, tmp_path / "root", "rec", overwrite=True)
    with pytest.raises(ValueError, match="recording"):  # out/scene holds the recording
        convert_tum(tmp_path / "root" / "rec", tmp_path, "root", overwrite=True)
    with pytest.raises(ValueError, match="inside the input"):  # out/scene inside the recording
        convert_tum(recording, recording, "scene", overwrite=True)
    assert sorted(p.name for p in recording.iterdir()) == ["groundtruth.txt", "rgb.txt"]
