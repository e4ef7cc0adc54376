"""The 7-Scenes reader: layout, counts, preprocessing, and an error naming the file for each
kind of bad input."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import cv2
import numpy as np
import pytest
import torch

from blurloc.cli import main
from blurloc.data import (
    DataError,
    check_data,
    load_split,
    read_depth,
    read_image,
    read_pose,
    read_split,
    split_one_sequence,
    validation_root,
)
from blurloc.files import link_or_copy
from blurloc.geometry import quaternion_to_rotation
from blurloc.image_headers import MAX_PIXELS_VARIABLE
from blurloc.train.datasets import PoseSequenceDataset


@pytest.fixture
def root(quick_root: Path, tmp_path: Path) -> Path:
    """A private copy of the quick stand-in that a test may damage."""
    copy = tmp_path / "root"
    shutil.copytree(quick_root, copy)
    return copy


def test_check_data_counts_the_layout(quick_root: Path) -> None:
    summary = check_data(quick_root)
    assert summary == {
        "scenes": {
            "chess": {
                "train": {"sequences": 1, "frames": 8},
                "test": {"sequences": 1, "frames": 8},
            },
            "stairs": {
                "train": {"sequences": 1, "frames": 4},
                "test": {"sequences": 1, "frames": 4},
            },
        }
    }


def test_cli_check_data_prints_exact_json(quick_root: Path, capsys: pytest.CaptureFixture) -> None:
    assert main(["check-data", str(quick_root)]) == 0
    out = capsys.readouterr().out
    assert json.loads(out) == check_data(quick_root)
    assert out.count("\n") == 1


def test_real_layout_with_crlf_poses_and_unlisted_extras(root: Path) -> None:
    """Real 7-Scenes pose files use CRLF and 7-Scenes sequences may hold no sharp frames."""
    sequence = load_split(root, "chess", "train")[0]
    pose_path = sequence.path(sequence.frame_ids[0], "pose")
    expected = read_pose(pose_path)
    pose_path.write_bytes(pose_path.read_bytes().replace(b"\n", b"\r\n"))
    for sharp in sequence.folder.glob("*.sharp.png"):
        sharp.unlink()
    np.testing.assert_array_equal(read_pose(pose_path), expected)
    assert check_data(root)["scenes"]["chess"]["train"]["frames"] == 8


def test_frames_are_in_order(quick_root: Path) -> None:
    sequence = load_split(quick_root, "chess", "test")[0]
    assert list(sequence.frame_ids) == list(range(8))
    assert sequence.number == 2


def _first(root: Path, kind: str) -> Path:
    sequence = load_split(root, "chess", "train")[0]
    return sequence.path(sequence.frame_ids[3], kind)


POSE_TEXTS = {
    "nan": "1 0 0 0\n0 1 0 0\n0 0 1 nan\n0 0 0 1\n",
    "inf": "1 0 0 0\n0 1 0 inf\n0 0 1 0\n0 0 0 1\n",
    "skewed": "1.1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n",
    "mirrored": "-1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n",
    "3x3": "1 0 0\n0 1 0\n0 0 1\n",
}


@pytest.mark.parametrize(
    ("kind", "damage", "message"),
    [
        ("color", Path.unlink, "color file is missing"),
        ("pose", Path.unlink, "pose file is missing"),
        ("pose", lambda p: p.write_text(POSE_TEXTS["nan"]), "NaN or inf"),
        ("pose", lambda p: p.write_text(POSE_TEXTS["inf"]), "NaN or inf"),
        ("pose", lambda p: p.write_text(POSE_TEXTS["skewed"]), "not orthonormal"),
        ("pose", lambda p: p.write_text(POSE_TEXTS["mirrored"]), "not a rotation: determinant -1"),
        ("pose", lambda p: p.write_text(POSE_TEXTS["3x3"]), "16 numbers"),
        ("color", lambda p: p.write_bytes(b"\x89PNG\r\n\x1a\n broken"), "cannot be read"),
    ],
    ids=[
        "missing-colour",
        "missing-pose",
        "nan-pose",
        "inf-pose",
        "non-orthonormal",
        "mirrored",
        "wrong-shape",
        "unreadable-image",
    ],
)
def test_bad_frame_files_are_named(root: Path, kind: str, damage, message: str) -> None:
    bad_file = _first(root, kind)
    damage(bad_file)
    with pytest.raises(DataError, match=message) as error:
        check_data(root)
    assert str(bad_file) in str(error.value)


def test_depth_is_read_in_metres_and_a_truncated_or_oversized_one_is_refused_by_name(
    root: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    depth_file = _first(root, "depth")
    millimetres = cv2.imread(str(depth_file), cv2.IMREAD_UNCHANGED)
    assert millimetres.dtype == np.uint16
    np.testing.assert_array_equal(read_depth(depth_file), millimetres / np.float32(1000))

    data = depth_file.read_bytes()
    depth_file.write_bytes(data[: int(len(data) * 0.8)])
    with pytest.raises(DataError, match="truncated") as error:
        read_depth(depth_file)
    assert str(depth_file) in str(error.value)

    depth_file.write_bytes(data)
    height, width = millimetres.shape
    monkeypatch.setenv(MAX_PIXELS_VARIABLE, str(height * width - 1))
    with pytest.raises(DataError, match="more than the cap") as error:
        read_depth(depth_file)
    assert str(depth_file) in str(error.value)


def test_a_colour_depth_image_is_refused_by_name(root: Path) -> None:
    depth_file = _first(root, "depth")
    cv2.imwrite(str(depth_file), np.zeros((4, 4, 3), np.uint8))
    with pytest.raises(DataError, match="3 channels, expected one") as error:
        read_depth(depth_file)
    assert str(depth_file) in str(error.value)


def test_small_rotation_noise_is_tolerated(root: Path) -> None:
    """Real 7-Scenes rotations are off orthonormal by up to 4e-4: that must pass."""
    path = _first(root, "pose")
    pose = read_pose(path)
    pose[:3, :3] *= 1 + 4e-4
    np.savetxt(path, pose)
    np.testing.assert_allclose(read_pose(path), pose, atol=1e-12)


def test_split_naming_a_missing_sequence(root: Path) -> None:
    (root / "chess" / "TrainSplit.txt").write_text("sequence1\nsequence9\n")
    with pytest.raises(DataError, match="seq-09") as error:
        check_data(root)
    assert "missing" in str(error.value)


def test_bad_split_line_is_named(root: Path) -> None:
    (root / "chess" / "TestSplit.txt").write_text("sequence2\nseq 3\n")
    with pytest.raises(DataError, match=r"TestSplit\.txt:2"):
        read_split(root / "chess", "test")


def test_empty_scene(root: Path) -> None:
    (root / "chess" / "TrainSplit.txt").write_text("")
    (root / "chess" / "TestSplit.txt").write_text("\n")
    with pytest.raises(DataError, match="no frames") as error:
        check_data(root)
    assert str(root / "chess") in str(error.value)


def test_empty_sequence_folder(root: Path) -> None:
    folder = root / "chess" / "seq-01"
    shutil.rmtree(folder)
    folder.mkdir()
    with pytest.raises(DataError, match="no frames"):
        check_data(root)


def test_cli_exits_1_naming_the_file(root: Path, capsys: pytest.CaptureFixture) -> None:
    bad = _first(root, "pose")
    bad.write_text("garbage")
    assert main(["check-data", str(root)]) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    assert str(bad) in captured.err


def test_dataset_windows_and_preprocessing(quick_root: Path) -> None:
    sequences = load_split(quick_root, "chess", "train") + load_split(quick_root, "stairs", "train")
    dataset = PoseSequenceDataset(
        sequences, window=3, stride=2, resize=96, crop=(64, 80), kinds=("color", "sharp")
    )
    # chess: 8 frames -> starts 0, 2, 4; stairs: 4 frames -> start 0
    assert len(dataset) == 4
    item = dataset[1]
    assert item["color"].shape == (3, 3, 64, 80)
    assert item["sharp"].shape == (3, 3, 64, 80)
    assert item["color"].min() >= -1 and item["color"].max() <= 1
    assert int(item["frame"]) == 2
    poses = sequences[0].poses()[2:5]
    np.testing.assert_allclose(item["position"].numpy(), poses[:, :3, 3], atol=1e-6)
    rotation = quaternion_to_rotation(item["quaternion"].numpy().astype(float))
    np.testing.assert_allclose(rotation, poses[:, :3, :3], atol=1e-5)
    assert torch.all(item["quaternion"][:, 0] >= 0)


def test_dataset_center_crop_matches_manual_crop(quick_root: Path) -> None:
    sequence = load_split(quick_root, "chess", "test")[0]
    dataset = PoseSequenceDataset([sequence], window=1, resize=120, crop=100)
    image = dataset[0]["color"][0]
    raw = read_image(sequence.path(0)).astype(np.float32)  # 160x120 already: no resize
    expected = raw[10:110, 30:130] / 127.5 - 1
    np.testing.assert_allclose(image.permute(1, 2, 0).numpy(), expected, atol=1e-6)


def test_random_crop_is_shared_by_the_window(quick_root: Path) -> None:
    sequence = load_split(quick_root, "chess", "test")[0]
    torch.manual_seed(0)
    dataset = PoseSequenceDataset(
        [sequence], window=2, resize=120, crop=64, random_crop=True, kinds=("color", "sharp")
    )
    full = PoseSequenceDataset([sequence], window=2, resize=120, crop=None, kinds=("sharp",))
    item, whole = dataset[0], full[0]["sharp"]
    # find the crop offset of the sharp frame 0 inside the full image; it must fit frame 1 too
    crop = item["sharp"]
    matches = [
        (t, s)
        for t in range(120 - 64 + 1)
        for s in range(160 - 64 + 1)
        if torch.equal(whole[0, :, t : t + 64, s : s + 64], crop[0])
    ]
    assert matches
    top, left = matches[0]
    assert torch.equal(whole[1, :, top : top + 64, left : left + 64], crop[1])


def test_window_longer_than_sequence(quick_root: Path) -> None:
    sequence = load_split(quick_root, "stairs", "test")[0]
    with pytest.raises(DataError, match="shorter than the window"):
        PoseSequenceDataset([sequence], window=5)


def test_a_sequence_cut_to_its_first_frames(quick_root: Path) -> None:
    sequence = load_split(quick_root, "chess", "train")[0]
    cut = sequence.first(3)
    assert cut.frame_ids == sequence.frame_ids[:3] and cut.folder == sequence.folder
    assert sequence.first(None) == sequence and len(sequence.first(10**6)) == len(sequence)


def test_a_sequence_reads_as_one_video_and_refuses_mixed_sizes_by_name(root: Path) -> None:
    sequence = load_split(root, "chess", "test")[0]
    video = sequence.images()
    assert video.dtype == np.uint8 and video.shape[0] == len(sequence)
    np.testing.assert_array_equal(video[2], read_image(sequence.path(sequence.frame_ids[2])))
    picked = sequence.images("sharp", sequence.frame_ids[::-2])
    np.testing.assert_array_equal(picked[0], read_image(sequence.path(sequence.frame_ids[-1],
                                                                      "sharp")))  # fmt: skip
    assert not np.array_equal(picked[0], video[-1])  # the sharp render, not the blurred frame
    odd = sequence.path(sequence.frame_ids[3])
    cv2.imwrite(str(odd), np.zeros((10, 12, 3), np.uint8))
    with pytest.raises(DataError, match=f"{odd.name}: 12x10 px, but .*frame-000000"):
        sequence.images()
    with pytest.raises(DataError, match="no frames"):
        sequence.images(frame_ids=[])


def test_link_or_copy_carries_a_file_over_and_replaces_the_target(tmp_path: Path) -> None:
    source, target = tmp_path / "a.txt", tmp_path / "b.txt"
    source.write_text("pose")
    target.write_text("stale")
    link_or_copy(source, target)
    assert target.read_text() == "pose"
    assert target.stat().st_ino == source.stat().st_ino  # a hard link on this file system


def test_one_recording_is_cut_into_a_training_and_a_test_sequence(
    quick_root: Path, tmp_path: Path
) -> None:
    (train_sequence,) = load_split(quick_root, "chess", "train")
    root = split_one_sequence(train_sequence.folder, tmp_path / "cut", "chess", 6)
    (train,), (test,) = load_split(root, "chess", "train"), load_split(root, "chess", "test")
    assert (len(train), len(test)) == (6, 2)
    np.testing.assert_array_equal(test.poses(), train_sequence.poses()[6:])
    np.testing.assert_array_equal(read_image(test.path(1, "sharp")),
                                  read_image(train_sequence.path(7, "sharp")))  # fmt: skip
    assert not list((tmp_path / "cut").glob(".*partial"))
    with pytest.raises(DataError, match="already exists"):
        split_one_sequence(train_sequence.folder, root, "chess", 6)
    with pytest.raises(DataError, match="cannot be cut"):
        split_one_sequence(train_sequence.folder, tmp_path / "other", "chess", 7)
    with pytest.raises(DataError, match="stand-in root"):
        split_one_sequence(train_sequence.folder, quick_root, "cut", 4)
    blocks = split_one_sequence(train_sequence.folder, tmp_path / "blocks", "chess", 4, blocks=2)
    train, test = load_split(blocks, "chess", "train"), load_split(blocks, "chess", "test")
    assert [len(s) for s in train] == [2, 2] and [len(s) for s in test] == [2, 2]
    # 8 frames in two blocks of 4: frames 0-1 and 4-5 train, 2-3 and 6-7 test
    np.testing.assert_array_equal(np.concatenate([s.poses() for s in train]),
                                  train_sequence.poses()[[0, 1, 4, 5]])  # fmt: skip
    np.testing.assert_array_equal(np.concatenate([s.poses() for s in test]),
                                  train_sequence.poses()[[2, 3, 6, 7]])  # fmt: skip
    with pytest.raises(DataError, match="cannot be cut into 3 block"):
        split_one_sequence(train_sequence.folder, tmp_path / "other", "chess", 4, blocks=3)
    odd = tmp_path / "odd" / "chess" / "seq-001"
    shutil.copytree(train_sequence.folder, odd)
    with pytest.raises(DataError, match="seq-XX"):
        split_one_sequence(odd, tmp_path / "other", "chess", 4)


def test_a_validation_root_holds_training_sequences_out_and_the_test_ones_out_of_reach(
    quick_root: Path, tmp_path: Path
) -> None:
    (recording,) = load_split(quick_root, "chess", "train")
    cut = split_one_sequence(recording.folder, tmp_path / "cut", "chess", 4, blocks=2)
    assert read_split(cut / "chess", "test") == [3, 4]
    root = validation_root(cut, "chess", [2], tmp_path / "validation")
    (train,), (held,) = load_split(root, "chess", "train"), load_split(root, "chess", "test")
    np.testing.assert_array_equal(train.poses(), recording.poses()[[0, 1]])
    np.testing.assert_array_equal(held.poses(), recording.poses()[[4, 5]])
    assert sorted(p.name for p in (root / "chess").glob("seq-*")) == ["seq-01", "seq-02"]
    for bad in ([3], [1, 2]):  # a test sequence; no training sequence left
        with pytest.raises(DataError, match="must be some, not all, of the training"):
            validation_root(cut, "chess", bad, tmp_path / "other")
