"""Renderer of the synthetic stand-in for 7-Scenes, written in the 7-Scenes layout.

Each stored frame is made the way the GoPro deblurring benchmark is made: the camera moves along a
continuous handheld trajectory, sharp frames are rendered at poses spread over the exposure, and
their average *in linear light* (gamma 2.2) is the blurred frame, plus sensor noise. Beside it the
stand-in stores the sharp render at mid-exposure (the ground truth that real 7-Scenes lacks), the
pose at mid-exposure, the depth, and per-frame blur metadata.

Layout written under ``root``::

    standin.json                      the settings and seed that made it
    <scene>/TrainSplit.txt, TestSplit.txt   ("sequenceN" lines)
    <scene>/seq-XX/frame-XXXXXX.color.png   blurred, noisy (what the camera captured)
    <scene>/seq-XX/frame-XXXXXX.sharp.png   sharp render at mid-exposure (stand-in only)
    <scene>/seq-XX/frame-XXXXXX.pose.txt    4x4 camera-to-world at mid-exposure, metres
    <scene>/seq-XX/frame-XXXXXX.depth.png   uint16 z-depth in millimetres (0: no surface)
    <scene>/seq-XX/blur.csv                  per frame: blur extent (mean/max px), direction
"""

from __future__ import annotations

import csv
import json
import multiprocessing
import os
import shutil
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import cv2
import numpy as np
from scipy.ndimage import gaussian_filter1d
from scipy.spatial.transform import Rotation
from tqdm.auto import tqdm

from ..files import atomic_path
from ..geometry import (
    backproject,
    frame_to_frame_motion,
    intrinsics,
    look_at,
    make_pose,
    project,
)
from ..images import to_uint8
from ..processes import process_alive, watch_parent
from ..stored import complete
from .render import Scene, render_poses, render_reference, surface_depth
from .scenes import SCENE_NAMES, SEQUENCE_COUNTS, camera_region, make_scene

#: Per-frame motion of the real 7-Scenes trajectories (30 fps, handheld Kinect), quoted from the
#: package's design notes (measured on the real poses; not measurable here without the dataset).
REAL_7SCENES_MOTION = {
    "step_median_m": 0.009,
    "step_p95_m": (0.015, 0.032),
    "rotation_median_deg": 0.55,
    "rotation_p95_deg": (1.1, 2.0),
}

FORMAT_VERSION = 5  # bump whenever rendering changes, so stale stand-ins are rendered again
_BATCH_PIXELS = 400_000  # sub-exposure renders of a frame are rendered together, this many pixels
#: File that marks a folder as a rendered stand-in and records the settings and seed.
STANDIN_MANIFEST = "standin.json"
#: File held (created exclusively, holding the PID) while a render writes into a stand-in.
LOCK_FILE = ".synth.lock"


#: Image sizes accepted, px per side (the intrinsics are 7-Scenes' scaled to the size).
MIN_SIZE, MAX_SIZE = 8, 4096
#: Longest exposure accepted, in frame intervals (1/3 s at 30 fps). Beyond it a frame's image
#: motion outgrows the 41 sub-exposure renders per frame (they would lie over 1 px apart), and at
#: 30 it would leave the trajectory's 1 s margin.
MAX_BLUR_STRENGTH = 10.0
#: Most rays per pixel side (64 a pixel).
MAX_SUPERSAMPLE = 8
#: Length of a scene's shared route (:func:`scene_route`) in units of path time (one unit: the
#: correlation time of the walk), per 1000 frames of the scene's sequences: a 1000-frame
#: sequence travels about 30 units, so it goes about three times around its route. At least
#: one unit (short quick sequences).
ROUTE_UNITS_PER_1000_FRAMES = 10.0


def _is_int(value: object) -> bool:
    return isinstance(value, int | np.integer) and not isinstance(value, bool)


@dataclass(frozen=True)
class SynthConfig:
    """Settings of the stand-in. ``blur_strength`` is the exposure time in frame intervals.

    The real Kinect exposes for at most one frame interval (1/30 s); at the stand-in's 160x120
    that would give about 1-2 px of blur. The default 2.2 stretches it so that blur at 160x120 is
    about as strong, relative to the image, as in strongly blurred real 7-Scenes frames at
    640x480: over the default trajectories the blur extent has a median of about 3 px and a
    90th percentile of about 5 px (notebook 00 measures it).

    Every field is checked on construction; a ValueError names the field and its ``blurloc
    synth`` option: width and height in [MIN_SIZE, MAX_SIZE] px, at least 2 frames per
    sequence, ``blur_strength`` in [0, MAX_BLUR_STRENGTH], ``noise_sigma`` in [0, 1],
    ``route_share`` in [0, 1], ``supersample`` an integer in [1, MAX_SUPERSAMPLE].

    ``supersample`` is how many rays per pixel side every render of the exposure casts (their
    mean is the pixel, in linear light): a camera's pixel integrates the light over its area,
    where one ray samples the scene at the pixel's centre (jagged edges, a coarser texture
    level). The default, one ray, is the stand-in's; three (nine rays) take about four times
    as long to render and leave what the video network can undo much as it was (README).

    ``route_share`` is how much of each sequence's walk and gaze follows a route shared by all
    sequences of its scene (:func:`scene_route`), the rest being the sequence's own wander
    (each part keeps unit variance: ``share * route + sqrt(1 - share**2) * own``). People
    recording one room walk much the same way, so the test views of real 7-Scenes lie near
    training views (published regressors reach 0.1-0.3x the mean-pose error there); with
    independent sequences (``route_share`` 0) a test sequence wanders where no training
    sequence went. The default 0.9 brings the nearest training view to 0.08-0.27x the
    mean-pose error on every scene, while that error stays near the real one
    (:data:`~blurloc.data.scenes.REAL_MEAN_POSE_BASELINE`; notebook 00 measures both).
    """

    width: int = 160
    height: int = 120
    frames_per_sequence: int = 1000  # as 7-Scenes; stairs gets half (500)
    blur_strength: float = 2.2
    noise_sigma: float = 0.01  # Gaussian sensor noise on [0, 1] gamma-encoded intensities
    route_share: float = 0.9  # part of each walk that follows the scene's shared route
    max_sample_spacing_px: float = 1.0  # sub-exposure renders at most this far apart
    fps: float = 30.0
    step_median_m: float = REAL_7SCENES_MOTION["step_median_m"]
    rotation_median_deg: float = REAL_7SCENES_MOTION["rotation_median_deg"]
    sequence_counts: dict[str, tuple[int, int]] = field(
        default_factory=lambda: dict(SEQUENCE_COUNTS)
    )
    supersample: int = 1  # rays per pixel side (1: one ray through each pixel's centre)

    def __post_init__(self) -> None:
        for name, option in (("width", "--width"), ("height", "--height"),
                             ("frames_per_sequence", "--frames")):  # fmt: skip
            value = getattr(self, name)
            low, high = (2, None) if name == "frames_per_sequence" else (MIN_SIZE, MAX_SIZE)
            if not _is_int(value) or value < low or (high is not None and value > high):
                bounds = f">= {low}" if high is None else f"in [{low}, {high}]"
                raise ValueError(f"{name} ({option}) must be an integer {bounds}, got {value!r}")
        for name, option, high in (("blur_strength", "--blur-strength", MAX_BLUR_STRENGTH),
                                   ("noise_sigma", "--noise", 1.0),
                                   ("route_share", "--route-share", 1.0)):  # fmt: skip
            value = getattr(self, name)
            if not (np.isfinite(value) and 0 <= value <= high):
                raise ValueError(f"{name} ({option}) must be a finite number in [0, {high}], "
                                 f"got {value!r}")  # fmt: skip
        if not _is_int(self.supersample) or not 1 <= self.supersample <= MAX_SUPERSAMPLE:
            raise ValueError(f"supersample (--supersample) must be an integer in "
                             f"[1, {MAX_SUPERSAMPLE}], got {self.supersample!r}")  # fmt: skip
        for name in ("max_sample_spacing_px", "fps", "step_median_m", "rotation_median_deg"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
        for scene, counts in self.sequence_counts.items():
            if (
                scene not in SCENE_NAMES
                or len(counts) != 2
                or not all(_is_int(n) and n >= 1 for n in counts)
            ):
                raise ValueError(f"sequence_counts[{scene!r}] must be (train, test) counts >= 1 "
                                 f"of one of {', '.join(SCENE_NAMES)}, got {counts!r}")  # fmt: skip

    @classmethod
    def quick(cls, **overrides) -> SynthConfig:
        """Tiny settings for CI: one training and one test sequence of 8 frames per scene."""
        counts = {name: (1, 1) for name in SCENE_NAMES}
        return replace(cls(frames_per_sequence=8, sequence_counts=counts), **overrides)

    def frames_for(self, scene: str) -> int:
        """Frames per sequence of ``scene`` (stairs sequences are half as long)."""
        return (
            max(2, self.frames_per_sequence // 2) if scene == "stairs" else self.frames_per_sequence
        )


def _unit_noise(
    rng: np.random.Generator, count: int, sigma_samples: float, dims: int
) -> np.ndarray:
    """Gaussian-smoothed white noise, each column scaled to unit standard deviation."""
    noise = gaussian_filter1d(
        rng.standard_normal((count, dims)), sigma_samples, axis=0, mode="wrap"
    )
    return noise / noise.std(axis=0, keepdims=True)


class HandheldTrajectory:
    """A handheld camera path that wanders a room the way the 7-Scenes recordings do.

    The camera walks a smooth random path through the scene's walking region (``CameraRegion``:
    a box, reached through ``tanh`` so the path never leaves it) while looking at a point that
    wanders over the scene's region of interest; on top of that sits hand shake (small,
    fast position and angle noise), and a log-normal speed envelope warps the time axis so
    some moments are much faster than others. Two scales are calibrated per path: how fast the
    camera travels along its path (so that the median step between frames is ``step_median_m``)
    and the amplitude of the angular shake (so that the median rotation between frames is
    ``rotation_median_deg``). The extent of the path is the region's, not a by-product of the
    speed: real sequences move about 9 mm per frame yet span a room over 1000 frames. A path
    that comes closer than ``scene.min_clearance_m`` to a surface is drawn again. With a
    ``route`` (:func:`scene_route`, None when ``config.route_share`` is 0), the walk and the
    gaze join that route at a random place and follow it, mixed with their own wander.
    """

    SAMPLE_RATE = 600.0  # Hz of the fine grid (hand shake, exposures)
    SLOW_RATE = 30.0  # Hz of the grid of the slow components (wander, gaze)
    CALIBRATION_S = 30.0  # the scales are set on at least this long a stretch, so that short
    # (quick) sequences move like long ones
    SHAKE_POSITION_M = 0.002  # standard deviation of the positional hand shake
    MAX_DRAWS = 200

    def __init__(
        self,
        scene: Scene,
        duration_s: float,
        rng: np.random.Generator,
        config: SynthConfig,
        route: np.ndarray | None = None,
    ) -> None:
        self._region = camera_region(scene.name)
        self._route = route
        margin = config.blur_strength / config.fps
        checks = np.arange(-margin, duration_s + margin, 1.0 / 120.0)
        self.draws = 0  # how many paths were drawn until one kept clear
        while self.draws < self.MAX_DRAWS:
            self.draws += 1
            self._draw(duration_s, rng, config)
            if scene.clearance(self.poses(checks)[:, :3, 3]).min() >= scene.min_clearance_m:
                return
        raise RuntimeError(f"{scene.name}: no handheld path kept clear of the surfaces")

    def _draw(self, duration_s: float, rng: np.random.Generator, config: SynthConfig) -> None:
        region = self._region
        span = max(duration_s, self.CALIBRATION_S)
        self.times = np.arange(-1.0, span + 1.0, 1.0 / self.SAMPLE_RATE)
        count = self.times.size
        envelope = np.exp(
            0.25 * np.clip(_unit_noise(rng, count, 0.5 * self.SAMPLE_RATE, 1)[:, 0], -2.0, 1.6)
        )
        self._clock = np.cumsum(envelope / envelope.mean()) / self.SAMPLE_RATE  # warped time
        # slow components on a coarse grid of path time: 1 unit = the correlation time
        slow_count = int(np.ceil((8.0 * span + 100.0) * self.SLOW_RATE))
        self._path_grid = np.arange(slow_count) / self.SLOW_RATE
        walk = _unit_noise(rng, slow_count, self.SLOW_RATE, 3)
        gaze = _unit_noise(rng, slow_count, self.SLOW_RATE, 3)
        if self._route is not None:  # join the route somewhere (scene_route: None at share 0)
            along = (rng.integers(len(self._route)) + np.arange(slow_count)) % len(self._route)
            own = np.sqrt(1.0 - config.route_share**2)
            walk = config.route_share * self._route[along, :3] + own * walk
            gaze = config.route_share * self._route[along, 3:] + own * gaze
        offset = np.tanh(walk) * region.half_extent
        self._walk = np.asarray(region.center) + offset
        self._gaze = (
            np.asarray(region.focus)
            + region.gaze_follow * offset
            + np.tanh(gaze) * region.focus_half_extent
        )
        self._shake_position = self.SHAKE_POSITION_M * _unit_noise(
            rng, count, 0.04 * self.SAMPLE_RATE, 3
        )
        self._shake_angles = _unit_noise(rng, count, 0.03 * self.SAMPLE_RATE, 3) * [1.0, 1.0, 0.5]
        self._path_rate = 0.2  # path-time units per (warped) second
        self._angle_scale = 1.0

        frame_times = np.arange(int(np.rint(span * config.fps))) / config.fps
        for _ in range(6):  # both scales act nearly linearly: a few rescalings converge
            steps, _ = frame_to_frame_motion(self.poses(frame_times))
            self._path_rate *= config.step_median_m / np.median(steps)
            self._path_rate = min(
                self._path_rate,
                (slow_count - 2) / self.SLOW_RATE / (self._clock[-1] - self._clock[0]),
            )
            _, turns = frame_to_frame_motion(self.poses(frame_times))
            self._angle_scale *= config.rotation_median_deg / np.median(turns)

    def poses(self, times: np.ndarray) -> np.ndarray:
        """Camera-to-world poses (N, 4, 4) at ``times`` (seconds from the first frame)."""
        times = np.atleast_1d(np.asarray(times, float))
        if times.min() < self.times[0] or times.max() > self.times[-1]:
            raise ValueError("time outside the trajectory")
        clock = np.interp(times, self.times, self._clock - self._clock[0])
        path = clock * self._path_rate
        walk = np.stack([np.interp(path, self._path_grid, c) for c in self._walk.T], 1)
        gaze = np.stack([np.interp(path, self._path_grid, c) for c in self._gaze.T], 1)
        shake = np.stack([np.interp(times, self.times, c) for c in self._shake_position.T], 1)
        angles = self._angle_scale * np.stack(
            [np.interp(times, self.times, c) for c in self._shake_angles.T], 1
        )
        # yaw about the camera's y (down) axis, pitch about x, roll about the optical axis
        offset = Rotation.from_euler("YXZ", angles, degrees=True).as_matrix()
        return make_pose(look_at(walk, gaze) @ offset, walk + shake)


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


def split_sequences(scene: str, config: SynthConfig) -> tuple[list[int], list[int]]:
    """Sequence numbers (1-based) of the training and test splits, test ones interleaved."""
    n_train, n_test = config.sequence_counts[scene]
    total = n_train + n_test
    test = sorted({int(np.rint(x)) for x in np.linspace(1, total, n_test + 2)[1:-1]})
    while len(test) < n_test:  # tiny counts: fill from the end
        test.append(max(set(range(1, total + 1)) - set(test)))
    train = [s for s in range(1, total + 1) if s not in test]
    return train, sorted(test)


def _sequence_seed(seed: int, scene: str, sequence: int) -> list[int]:
    return [seed, SCENE_NAMES.index(scene), sequence]


def scene_route(scene: Scene, config: SynthConfig, seed: int = 0) -> np.ndarray | None:
    """The route that every sequence of a scene follows in part (``config.route_share``).

    A closed loop of smooth noise in the six slow components of :class:`HandheldTrajectory`
    (walk and gaze offsets; zero mean and unit variance, as the walks' own noise), as long as
    :data:`ROUTE_UNITS_PER_1000_FRAMES` says for the scene's sequence length, drawn from the
    scene and the seed alone (so the same for all its sequences) and drawn again until the
    walk it leads to keeps ``scene.min_clearance_m`` from every surface.

    Parameters
    ----------
    scene : Scene
        A stand-in scene (:func:`~blurloc.data.scenes.make_scene`).
    config : SynthConfig
        Settings; ``route_share`` 0 means no route.
    seed : int
        The stand-in's seed.

    Returns
    -------
    numpy.ndarray or None
        Shape (K, 6) on the slow grid (walk x, y, z, gaze x, y, z), or None when
        ``config.route_share`` is 0.

    Raises
    ------
    RuntimeError
        If no route of the scene keeps clear of its surfaces.
    """
    if config.route_share == 0:
        return None
    rng = np.random.default_rng(_sequence_seed(seed, scene.name, 0))  # sequences count from 1
    rate = HandheldTrajectory.SLOW_RATE
    units = max(1.0, ROUTE_UNITS_PER_1000_FRAMES * config.frames_for(scene.name) / 1000.0)
    count = int(units * rate)
    region = camera_region(scene.name)
    center, half_extent = np.asarray(region.center), np.asarray(region.half_extent)
    for _ in range(HandheldTrajectory.MAX_DRAWS):
        route = gaussian_filter1d(rng.standard_normal((count, 6)), rate, axis=0, mode="wrap")
        route = (route - route.mean(axis=0)) / route.std(axis=0)  # spans the region as walks do
        walk = center + np.tanh(config.route_share * route[:, :3]) * half_extent
        if scene.clearance(walk).min() >= scene.min_clearance_m:
            return route
    raise RuntimeError(f"{scene.name}: no route kept clear of the surfaces")


def sequence_trajectory(
    scene_name: str, sequence: int, config: SynthConfig | None = None, seed: int = 0
) -> tuple[Scene, HandheldTrajectory]:
    """The scene and the exact trajectory that :func:`synthesize` used for one sequence."""
    config = config or SynthConfig()
    scene = make_scene(scene_name)
    rng = np.random.default_rng(_sequence_seed(seed, scene_name, sequence))
    duration = config.frames_for(scene_name) / config.fps
    route = scene_route(scene, config, seed)
    return scene, HandheldTrajectory(scene, duration, rng, config, route)


def render_sequence(
    root: Path, scene_name: str, sequence: int, config: SynthConfig, seed: int
) -> int:
    """Render and write one sequence; returns its number of frames."""
    cv2.setNumThreads(1)
    scene, trajectory = sequence_trajectory(scene_name, sequence, config, seed)
    frames = config.frames_for(scene_name)
    noise_rng = np.random.default_rng([*_sequence_seed(seed, scene_name, sequence), 1])
    camera = intrinsics(config.width, config.height)
    folder = root / scene_name / f"seq-{sequence:02d}"
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for frame in range(frames):
        blurred, sharp, depth, blur = render_exposure(
            scene, trajectory, frame / config.fps, config, camera
        )
        noise = (
            noise_rng.normal(0.0, config.noise_sigma, blurred.shape) if config.noise_sigma else None
        )
        stem = folder / f"frame-{frame:06d}"
        cv2.imwrite(f"{stem}.color.png", to_uint8(blurred, noise)[..., ::-1])
        cv2.imwrite(f"{stem}.sharp.png", to_uint8(sharp)[..., ::-1])
        depth_mm = np.clip(np.round(depth * 1000.0), 0, 65535).astype(np.uint16)
        cv2.imwrite(f"{stem}.depth.png", depth_mm)
        pose = trajectory.poses([frame / config.fps])[0]
        np.savetxt(f"{stem}.pose.txt", pose, fmt="%.9e", delimiter="\t")
        rows.append(
            [
                frame,
                f"{blur.mean_px:.4f}",
                f"{blur.max_px:.4f}",
                f"{blur.angle_deg:.2f}",
                blur.samples,
            ]
        )
    with open(folder / "blur.csv", "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["frame", "mean_px", "max_px", "angle_deg", "samples"])
        writer.writerows(rows)
    return frames


def _render_job(job: tuple) -> int:
    return render_sequence(*job)


def _manifest(config: SynthConfig, seed: int, scenes: list[str]) -> dict:
    settings = asdict(config)
    settings["sequence_counts"] = {k: list(v) for k, v in config.sequence_counts.items()}
    return {"format": FORMAT_VERSION, "seed": seed, "scenes": scenes, "config": settings}


def _foreign_dataset(root: Path) -> bool:
    """True when ``root`` holds something other than a stand-in (non-empty, no manifest)."""
    return (
        root.is_dir()
        and any(entry.name != LOCK_FILE for entry in root.iterdir())
        and not (root / STANDIN_MANIFEST).exists()
    )


@contextmanager
def render_lock(root: Path) -> Iterator[None]:
    """Hold ``root/.synth.lock`` (created exclusively, holding this PID) while rendering.

    A lock left by a process that no longer runs is taken over.

    Parameters
    ----------
    root : pathlib.Path
        The stand-in folder (it exists).

    Raises
    ------
    ValueError
        Naming the lock file and the PID holding it, when another process renders into ``root``.
    """
    lock = root / LOCK_FILE
    for _ in range(2):
        try:
            handle = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            text = lock.read_text().strip() if lock.exists() else ""
            holder = int(text) if text.isdigit() else None
            if holder is None or process_alive(holder):
                raise ValueError(
                    f"{lock}: another synth (PID {holder or 'unknown'}) is rendering into "
                    f"{root}; wait for it, or delete the lock if that process is gone"
                ) from None
            lock.unlink(missing_ok=True)  # its holder died: take it over
            continue
        with os.fdopen(handle, "w") as file:
            file.write(f"{os.getpid()}\n")
        break
    else:
        raise ValueError(f"{lock}: cannot take over the lock; try again")
    try:
        yield
    finally:
        lock.unlink(missing_ok=True)


def _clear_scenes(root: Path) -> None:
    """Remove the scene folders a stand-in holds (and only those), so a render with other
    settings leaves no stale frames beside the new ones."""
    for name in SCENE_NAMES:
        if (root / name).is_dir():
            shutil.rmtree(root / name)


def manifest_expectations(root: str | os.PathLike) -> dict[str, tuple[int, int, int]] | None:
    """What ``root/standin.json`` promises: per scene, frames per sequence, height and width.

    Parameters
    ----------
    root : str or os.PathLike
        A 7-Scenes-layout root.

    Returns
    -------
    dict or None
        ``{scene: (frames, height_px, width_px)}``; None when ``root`` has no manifest (not a
        stand-in, e.g. the real 7-Scenes).

    Raises
    ------
    ValueError
        Naming the manifest, when it is unreadable or marks an unfinished render.
    """
    path = Path(root) / STANDIN_MANIFEST
    if not path.is_file():
        return None
    try:
        manifest = json.loads(path.read_text())
        if manifest.get("incomplete"):
            raise ValueError("the render that made this stand-in did not finish; run "
                             "blurloc synth again")  # fmt: skip
        settings = manifest["config"]
        config = SynthConfig(width=settings["width"], height=settings["height"],
                             frames_per_sequence=settings["frames_per_sequence"])  # fmt: skip
        return {scene: (config.frames_for(scene), config.height, config.width)
                for scene in manifest["scenes"]}  # fmt: skip
    except (ValueError, KeyError, TypeError, AttributeError) as error:
        detail = f"lacks {error}" if isinstance(error, KeyError) else error
        raise ValueError(f"{path}: not a usable stand-in manifest ({detail})") from None


def prepare_data_root(
    root: str | os.PathLike, quick: bool = False, seed: int = 0, progress: bool = True
) -> Path:
    """The root a notebook reads: the stand-in at ``root``, rendered if missing or out of date
    (:func:`synthesize` with the default or quick settings), or, when ``root`` holds another
    dataset (a non-empty folder without ``standin.json``, e.g. the real 7-Scenes), ``root``
    untouched."""
    root = Path(root)
    if _foreign_dataset(root):
        return root
    config = SynthConfig.quick() if quick else SynthConfig()
    return synthesize(root, config=config, seed=seed, progress=progress)


def synthesize(
    root: str | os.PathLike,
    scenes: list[str] | None = None,
    config: SynthConfig | None = None,
    seed: int = 0,
    workers: int | None = None,
    progress: bool = True,
    overwrite: bool = False,
) -> Path:
    """Render the stand-in into ``root`` in the 7-Scenes layout and return ``root``.

    Idempotent: if ``root/standin.json`` records the same settings, nothing is rendered again.
    Otherwise the scene folders of the earlier stand-in are removed first, so frames of other
    settings never stay beside the new ones; an interrupted render (its manifest says
    ``"incomplete": true``) is rendered again in full. The same seed gives byte-identical
    files, whatever the number of workers. One render at a time holds ``root/.synth.lock``;
    workers stop when the parent process dies.

    Parameters
    ----------
    root : str or os.PathLike
        Folder to write: missing, empty, or an earlier stand-in (with ``standin.json``). A
        folder holding anything else is never written into.
    scenes : list of str, optional
        Scenes to render (default: all of SCENE_NAMES).
    config : SynthConfig, optional
        Settings (default: ``SynthConfig()``).
    seed : int
        Non-negative seed of every trajectory and of the sensor noise.
    workers : int, optional
        Processes (>= 1; default: one per core, at most one per sequence).
    progress : bool
        Show a progress bar of frames.
    overwrite : bool
        Render even when the manifest records the same settings.

    Returns
    -------
    pathlib.Path
        ``root``.

    Raises
    ------
    ValueError
        On a bad argument (naming it and its ``blurloc synth`` option), a foreign ``root``, or a
        render already running into ``root``; all before anything is written.
    """
    root = Path(root)
    config = config or SynthConfig()
    scenes = list(scenes or SCENE_NAMES)
    unknown = sorted(set(scenes) - set(SCENE_NAMES))
    if unknown:
        raise ValueError(f"unknown scene(s) {unknown} (--scenes); choose from "
                         f"{', '.join(SCENE_NAMES)}")  # fmt: skip
    if not _is_int(seed) or seed < 0:
        raise ValueError(f"seed (--seed) must be an integer >= 0, got {seed!r}")
    if workers is not None and (not _is_int(workers) or workers < 1):
        raise ValueError(f"workers (--workers) must be an integer >= 1, got {workers!r}")
    if root.exists() and not root.is_dir():
        raise ValueError(f"{root}: exists and is not a folder")
    manifest = _manifest(config, seed, scenes)
    manifest_path = root / STANDIN_MANIFEST
    if not overwrite and _up_to_date(manifest_path, manifest):
        return root
    if _foreign_dataset(root):
        raise ValueError(f"{root}: not empty and not a stand-in (no {STANDIN_MANIFEST}); "
                         "refusing to render into it")  # fmt: skip
    root.mkdir(parents=True, exist_ok=True)
    with render_lock(root):
        if not overwrite and _up_to_date(manifest_path, manifest):  # another run just finished it
            return root
        # an interrupted render stays a stand-in, marked unfinished
        manifest_path.write_text(json.dumps({"incomplete": True}))
        _clear_scenes(root)
        _render(root, scenes, config, seed, workers, progress)
        with atomic_path(manifest_path) as temporary:
            temporary.write_text(json.dumps(manifest, indent=2))
    return root


def _up_to_date(manifest_path: Path, manifest: dict) -> bool:
    """True when the stand-in at ``manifest_path`` was rendered as ``manifest`` describes. A
    setting added to :class:`SynthConfig` after it was rendered counts as its default
    (:func:`blurloc.stored.complete`)."""
    try:
        stored = json.loads(manifest_path.read_text())
        defaults = _manifest(SynthConfig(), 0, [])["config"]
        stored["config"] = complete(stored["config"], defaults)
        return stored == manifest
    except (OSError, ValueError, KeyError, TypeError):
        return False


def _render(
    root: Path,
    scenes: list[str],
    config: SynthConfig,
    seed: int,
    workers: int | None,
    progress: bool,
) -> None:
    """Write the split files and render every sequence of ``scenes``, long jobs first."""
    jobs = []
    for scene in scenes:
        train, test = split_sequences(scene, config)
        (root / scene).mkdir(parents=True, exist_ok=True)
        for name, numbers in (("TrainSplit.txt", train), ("TestSplit.txt", test)):
            (root / scene / name).write_text("".join(f"sequence{n}\n" for n in numbers))
        jobs += [(root, scene, n, config, seed) for n in sorted(train + test)]
    jobs.sort(key=lambda job: -config.frames_for(job[1]))  # long jobs first: better balance
    total = sum(config.frames_for(job[1]) for job in jobs)

    workers = workers or min(len(jobs), os.cpu_count() or 1)
    with tqdm(total=total, unit="frame", desc="stand-in", disable=not progress) as bar:
        if workers == 1:
            for job in jobs:
                bar.update(_render_job(job))
        else:
            method = "forkserver" if sys.platform.startswith("linux") else "spawn"
            context = multiprocessing.get_context(method)
            with context.Pool(workers, watch_parent, (os.getpid(),)) as pool:
                for frames in pool.imap_unordered(_render_job, jobs):
                    bar.update(frames)
