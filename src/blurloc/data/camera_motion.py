"""Handheld camera paths of the stand-in: each sequence's trajectory and the route that the
sequences of one scene share."""

from __future__ import annotations

import numpy as np
from scipy.ndimage import gaussian_filter1d
from scipy.spatial.transform import Rotation

from ..geometry import frame_to_frame_motion, look_at, make_pose
from .layout import SCENE_NAMES
from .render import Scene
from .scenes import camera_region, make_scene
from .synth_config import SynthConfig

#: Length of a scene's shared route (:func:`scene_route`) in units of path time (one unit: the
#: correlation time of the walk), per 1000 frames of the scene's sequences: a 1000-frame
#: sequence travels about 30 units, so it goes about three times around its route. At least
#: one unit (short quick sequences).
ROUTE_UNITS_PER_1000_FRAMES = 10.0


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


def sequence_seed(seed: int, scene: str, sequence: int) -> list[int]:
    """Seed of one sequence's random draws: the stand-in's seed, the scene's index in
    SCENE_NAMES and the sequence number (0 for the scene's shared route)."""
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
    rng = np.random.default_rng(sequence_seed(seed, scene.name, 0))  # sequences count from 1
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
    """The scene (with ``config.scene_content``) and the exact trajectory that
    :func:`synthesize` used for one sequence. The trajectory keeps clear of the scene's shared
    geometry (:func:`~blurloc.data.scenes.make_scene`'s photographed rooms), so both contents
    are seen from the same poses."""
    config = config or SynthConfig()
    scene = make_scene(scene_name, "photographs")
    rng = np.random.default_rng(sequence_seed(seed, scene_name, sequence))
    duration = config.frames_for(scene_name) / config.fps
    route = scene_route(scene, config, seed)
    trajectory = HandheldTrajectory(scene, duration, rng, config, route)
    return make_scene(scene_name, config.scene_content), trajectory
