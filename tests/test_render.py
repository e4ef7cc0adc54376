"""The fast renderer (rasterised quads) against the reference ray cast, on every scene."""

from __future__ import annotations

import numpy as np
import pytest

from blurloc.data.render import (
    render,
    render_poses,
    render_reference,
    surface_depth,
)
from blurloc.data.scenes import SCENE_NAMES
from blurloc.data.synth import SynthConfig, sequence_trajectory
from blurloc.geometry import intrinsics
from blurloc.images import linear_to_srgb

MIN_PSNR_DB = 40.0
DEPTH_TOLERANCE_M = 1e-4
# Pixels whose ray passes within float rounding of an edge shared by two quads at different
# depths may see either quad (or, on an outer edge, none) in one renderer and not the other.
MAX_EDGE_PIXELS = 2


def stand_in_poses(scene_name: str, count: int = 3) -> tuple:
    """The scene and ``count`` poses spread over the quick stand-in's first sequence."""
    config = SynthConfig.quick()
    scene, trajectory = sequence_trajectory(scene_name, 1, config)
    duration = config.frames_for(scene_name) / config.fps
    return scene, trajectory.poses(np.linspace(0.0, duration, count))


def psnr_db(reference: np.ndarray, image: np.ndarray) -> float:
    """PSNR of gamma-encoded [0, 1] images (linear-light inputs)."""
    error = np.mean((linear_to_srgb(reference) - linear_to_srgb(image)) ** 2)
    return float("inf") if error == 0 else float(10 * np.log10(1.0 / error))


def assert_same_render(reference: tuple, fast: tuple) -> None:
    (image_ref, depth_ref), (image, depth) = reference, fast
    assert psnr_db(image_ref, image) >= MIN_PSNR_DB
    hit_ref, hit = depth_ref > 0, depth > 0
    assert hit.mean() > 0.5  # the scene is seen, not an empty frame
    assert (hit_ref != hit).sum() <= MAX_EDGE_PIXELS
    both = hit_ref & hit
    assert (np.abs(depth_ref - depth)[both] >= DEPTH_TOLERANCE_M).sum() <= MAX_EDGE_PIXELS


@pytest.mark.parametrize("scene_name", SCENE_NAMES)
def test_fast_renderer_matches_the_ray_cast(scene_name: str) -> None:
    width, height = 160, 120
    camera = intrinsics(width, height)
    scene, poses = stand_in_poses(scene_name)
    images, depths = render_poses(scene, poses, camera, width, height)
    for pose, image, depth in zip(poses, images, depths, strict=True):
        assert_same_render(render_reference(scene, pose, camera, width, height), (image, depth))


@pytest.mark.parametrize("scene_name", SCENE_NAMES)
def test_fast_renderer_matches_the_ray_cast_at_640x480(scene_name: str) -> None:
    width, height = 640, 480
    camera = intrinsics(width, height)
    scene, poses = stand_in_poses(scene_name, count=1)
    assert_same_render(
        render_reference(scene, poses[0], camera, width, height),
        render(scene, poses[0], camera, width, height),
    )


def test_a_batch_of_poses_renders_as_each_pose_alone() -> None:
    width, height = 160, 120
    camera = intrinsics(width, height)
    scene, poses = stand_in_poses("office", count=4)
    images, depths = render_poses(scene, poses, camera, width, height)
    for pose, image, depth in zip(poses, images, depths, strict=True):
        alone = render(scene, pose, camera, width, height)
        np.testing.assert_array_equal(image, alone[0])
        np.testing.assert_array_equal(depth, alone[1])


def test_surface_depth_is_the_rendered_depth() -> None:
    width, height = 160, 120
    camera = intrinsics(width, height)
    scene, poses = stand_in_poses("redkitchen", count=1)
    depth = render(scene, poses[0], camera, width, height)[1]
    v, u = np.mgrid[3:height:7, 3:width:7]
    pixels = np.column_stack([u.ravel(), v.ravel()])
    np.testing.assert_allclose(
        surface_depth(scene, poses[0], camera, pixels), depth[v, u].ravel(), atol=1e-4
    )
