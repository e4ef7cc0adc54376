"""Which frames a pass over a split reads: a budget spread evenly over scenes and sequences."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from blurloc.data import load_split
from blurloc.data.samples import frame_stride, split_frames
from blurloc.experiments.blur_estimation import camera_motion_px, length_training_set
from blurloc.geometry import image_motion_px, intrinsics, make_pose


def test_frame_stride_reads_about_the_budget() -> None:
    assert frame_stride(17000) == 1
    assert frame_stride(17000, 850) == 20
    assert frame_stride(17000, 900) == 19  # 895 frames: never more than the budget allows
    assert frame_stride(52, 13) == 4
    assert frame_stride(52, 1000) == 1
    with pytest.raises(ValueError, match="at least 1"):
        frame_stride(52, 0)


def test_split_frames_spreads_the_budget_over_every_sequence(quick_root: Path) -> None:
    sequences = {(s.scene, s.number): s for scene in ("chess", "stairs")
                 for s in load_split(quick_root, scene, "test")}  # fmt: skip
    everything = split_frames(quick_root, "test")
    assert len(everything) == sum(len(s) for s in sequences.values()) == 12  # 8 + 4 frames
    chosen = split_frames(quick_root, "test", budget=3)  # stride 4
    assert [(scene, frame) for scene, _, frame in chosen] == [
        ("chess", 0), ("chess", 4), ("stairs", 0)]  # fmt: skip
    assert {(scene, s.number) for scene, s, _ in chosen} == set(sequences)
    assert split_frames(quick_root, "test", budget=100) == everything
    train = split_frames(quick_root, "train", budget=6)  # stride 2 over 12 frames
    assert [frame for _, _, frame in train] == [0, 2, 4, 6, 0, 2]


def test_sharp_renders_follow_the_frames_read(quick_root: Path) -> None:
    # stride 4 reads frames 0 and 4 of chess and 0 of stairs: the sharp render of every second
    # frame read per sequence is chess's frame 0 and stairs' frame 0 (not every frame number
    # divisible by 2)
    features, extents = length_training_set(quick_root, "train", sharp_every=2, budget=3)
    assert features.shape[0] == 3 + 2
    assert (extents == 0).sum() == 2 and extents[1] == 0 and extents[4] == 0


def test_camera_motion_of_chosen_frames_matches_all_frames() -> None:
    rng = np.random.default_rng(0)
    poses = np.tile(np.eye(4), (9, 1, 1))
    poses[:, :3, :3] = Rotation.from_rotvec(np.cumsum(rng.normal(0, 0.01, (9, 3)), 0)).as_matrix()
    poses[:, :3, 3] = np.cumsum(rng.normal(0, 0.01, (9, 3)), 0)
    distances = rng.uniform(1, 3, 9)
    camera, size = intrinsics(640, 480), (640, 480)
    every = camera_motion_px(poses, distances, camera, size)
    chosen = np.array([0, 4, 8])
    np.testing.assert_allclose(camera_motion_px(poses, distances[chosen], camera, size, chosen),
                               every[chosen])  # fmt: skip
    assert (every > 0).all()


def test_image_motion_follows_the_pinhole_camera() -> None:
    camera, size = intrinsics(640, 480), (640, 480)
    still = np.eye(4)
    # a sideways step of t at depth z moves every pixel by f t / z
    step = make_pose(np.eye(3), np.array([0.02, 0.0, 0.0]))
    assert image_motion_px(still, step, camera, size, 2.0) == pytest.approx(585 * 0.02 / 2.0)
    # a small pan by angle a moves the image by about f a (a little more off the axis); a roll
    # by the same angle moves each pixel by its distance from the centre times a, far less
    angle = np.radians(1.0)
    pan = make_pose(Rotation.from_euler("y", angle).as_matrix(), np.zeros(3))
    roll = make_pose(Rotation.from_euler("z", angle).as_matrix(), np.zeros(3))
    assert 585 * angle <= image_motion_px(still, pan, camera, size, 2.0) <= 1.15 * 585 * angle
    rolled = image_motion_px(still, roll, camera, size, 2.0)
    assert rolled < 0.5 * 585 * angle
    assert rolled == pytest.approx(angle * 200, rel=0.25)  # mean distance from the centre ~ 200 px
    with pytest.raises(ValueError, match="depth_m"):
        image_motion_px(still, step, camera, size, 0.0)
