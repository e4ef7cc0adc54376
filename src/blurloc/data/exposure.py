"""One frame of the stand-in: the camera's exposure rendered and averaged in linear light, and
how far image points moved during it (the frame's blur)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry import backproject, project
from .camera_motion import HandheldTrajectory
from .render import Scene, render_poses, render_reference, surface_depth
from .synth_config import SynthConfig

_BATCH_PIXELS = 400_000  # sub-exposure renders of a frame are rendered together, this many pixels


@dataclass(frozen=True)
class BlurInfo:
    """How far image points moved over one exposure (pixels) and in which direction.

    ``angle_deg`` is the dominant direction of motion, in [0, 180), counter-clockwise from the
    image's horizontal axis as displayed (y up).
    """

    mean_px: float
    max_px: float
    angle_deg: float
    samples: int


def path_lengths(track: np.ndarray) -> np.ndarray:
    """Length (px) of each point's image path; ``track`` is (samples, points, 2)."""
    return np.linalg.norm(np.diff(track, axis=0), axis=2).sum(axis=0)


def displacement_angles(track: np.ndarray) -> np.ndarray:
    """Direction of each point's start-to-end displacement, degrees in [0, 180), y up."""
    dx = track[-1, :, 0] - track[0, :, 0]
    dy = -(track[-1, :, 1] - track[0, :, 1])  # image rows grow downwards; angles use y up
    return np.degrees(np.arctan2(dy, dx)) % 180.0


def blur_from_motion(track: np.ndarray) -> tuple[float, float, float]:
    """Blur extent and direction from image tracks (samples, points, 2) over one exposure.

    Returns the mean and max over points of each point's path length, and the dominant
    direction (principal axis of the start-to-end displacements, degrees, y up).
    """
    path = path_lengths(track)
    dx = track[-1, :, 0] - track[0, :, 0]
    dy = -(track[-1, :, 1] - track[0, :, 1])
    angle = 0.5 * np.degrees(np.arctan2(2 * (dx * dy).sum(), (dx * dx - dy * dy).sum()))
    return float(path.mean()), float(path.max()), float(angle % 180.0)


def exposure_tracks(
    scene: Scene,
    trajectory: HandheldTrajectory,
    time_s: float,
    config: SynthConfig,
    camera: np.ndarray,
    depth: np.ndarray | None = None,
    grid_step: int | None = None,
    samples: int = 9,
) -> np.ndarray:
    """Image paths (samples, points, 2) of a grid of scene points over one exposure.

    The points are the surfaces seen at mid-exposure on a pixel grid (every ``grid_step`` px);
    each is projected at ``samples`` instants from the exposure's start to its end. Points at
    different depths and image positions move differently: that is why one blur kernel cannot
    describe a real camera-shake frame.
    """
    mid_pose = trajectory.poses([time_s])[0]
    step = grid_step or max(1, min(config.width, config.height) // 16)
    v, u = np.mgrid[step // 2 : config.height : step, step // 2 : config.width : step]
    grid = np.column_stack([u.ravel(), v.ravel()])
    z = surface_depth(scene, mid_pose, camera, grid) if depth is None else depth[v, u].ravel()
    valid = z > 0
    if not valid.any():
        raise RuntimeError(f"{scene.name}: the camera sees no surface at t = {time_s:.3f} s")
    points = backproject(grid[valid], z[valid], mid_pose, camera)
    exposure = config.blur_strength / config.fps
    times = time_s + exposure * np.linspace(-0.5, 0.5, samples)
    return np.stack([project(points, pose, camera)[:, :2] for pose in trajectory.poses(times)])


def render_exposure(
    scene: Scene,
    trajectory: HandheldTrajectory,
    time_s: float,
    config: SynthConfig,
    camera: np.ndarray,
    reference: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, BlurInfo]:
    """Render one frame: linear-light blurred image, sharp image at mid-exposure, depth, blur.

    The exposure [t - E/2, t + E/2] (E = blur_strength / fps) is integrated with the midpoint
    rule over an odd number of sharp renders, spaced at most ``max_sample_spacing_px`` apart in
    the image, so the middle render is the sharp frame itself and no motion gives a blurred
    frame equal to the sharp one. The renders other than the middle one are rasterised together
    (:func:`~blurloc.data.render.render_poses`). With ``config.supersample`` k > 1 every render
    is made at k times the size (the intrinsics scaled so that each pixel holds k x k evenly
    spaced rays) and each pixel is the mean of its k x k rays (a box filter over the pixel).

    Parameters
    ----------
    scene : Scene
        What the camera sees.
    trajectory : HandheldTrajectory
        The camera path (anything with ``poses(times) -> (N, 4, 4)``).
    time_s : float
        Mid-exposure time of the frame, seconds.
    config : SynthConfig
        Image size, exposure (``blur_strength``) and sample spacing.
    camera : np.ndarray
        (3, 3) intrinsics, pixels.
    reference : bool
        Render every sample with :func:`~blurloc.data.render.render_reference` (the slow ray
        cast the fast renderer is checked and timed against).

    Returns
    -------
    blurred, sharp : np.ndarray
        (height, width, 3) float32 linear-light images: the exposure's average and its middle.
    depth : np.ndarray
        (height, width) z-depth at mid-exposure, metres (0: no surface); with supersampling,
        that of the ray nearest each pixel's centre.
    blur : BlurInfo
        Blur extent and direction, and the number of renders averaged.
    """
    width, height = config.width, config.height
    exposure = config.blur_strength / config.fps
    tracks = exposure_tracks(scene, trajectory, time_s, config, camera)
    mean_px, max_px, angle = blur_from_motion(tracks)
    samples = int(np.clip(np.ceil(max_px / config.max_sample_spacing_px), 1, 41)) if exposure else 1
    samples += 1 - samples % 2  # odd, so the middle sample is the mid-exposure (sharp) render
    middle = samples // 2
    offsets = exposure * ((np.arange(samples) + 0.5) / samples - 0.5)
    offsets[middle] = 0.0
    poses = trajectory.poses(time_s + offsets)
    rays = config.supersample
    ray_camera = camera * np.array([[rays], [rays], [1.0]])  # rays at (k u + (k - 1) / 2, ...)
    ray_camera[:2, 2] += (rays - 1) / 2
    ray_width, ray_height = width * rays, height * rays
    batch = 1 if reference else max(1, _BATCH_PIXELS // (ray_width * ray_height))
    total = np.zeros((height, width, 3), np.float64)
    for first in range(0, samples, batch):
        if reference:
            image, depth = render_reference(scene, poses[first], ray_camera, ray_width, ray_height)
            images, depths = image[None], depth[None]
        else:
            images, depths = render_poses(
                scene, poses[first : first + batch], ray_camera, ray_width, ray_height
            )
        if rays > 1:
            images = images.reshape(len(images), height, rays, width, rays, 3).mean(axis=(2, 4))
            depths = depths[:, rays // 2 :: rays, rays // 2 :: rays]
        total += images.sum(axis=0, dtype=np.float64)
        if first <= middle < first + len(images):
            sharp, depth = images[middle - first], depths[middle - first]
    blurred = (total / samples).astype(np.float32)
    return blurred, sharp, depth, BlurInfo(mean_px, max_px, angle, samples)
