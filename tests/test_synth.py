"""The stand-in renderer: projection, exposure integration, blur metadata, rigid poses,
motion statistics and determinism."""

from __future__ import annotations

import filecmp
import hashlib
import json
import os
import shutil
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest
import skimage.data
from numpy._core._multiarray_umath import __cpu_features__
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

from blurloc.data import check_data, load_split
from blurloc.data.camera_model import capture, optics_blur, sensor_noise
from blurloc.data.manifest import render_settings
from blurloc.data.render import Light, Quad, Scene, render
from blurloc.data.scenes import REAL_MEAN_POSE_BASELINE, SCENE_NAMES, make_scene
from blurloc.data.synth import (
    HandheldTrajectory,
    SynthConfig,
    prepare_data_root,
    render_exposure,
    scene_route,
    sequence_trajectory,
    split_sequences,
    synthesize,
)
from blurloc.data.synth_config import PREVIOUS_LOOK
from blurloc.geometry import (
    frame_to_frame_motion,
    intrinsics,
    look_at,
    make_pose,
    orthonormality_error,
    project,
)
from blurloc.images import linear_to_srgb, srgb_to_linear

WIDTH, HEIGHT = 160, 120
#: Largest median distance from a test position to the nearest training position, as a share of
#: the mean-pose baseline.
NEAREST_POSITION_BAR = 0.16


def wall_scene(marker_center: tuple[float, float, float] | None = None) -> Scene:
    """A textured wall at y = 3 m facing the origin, optionally with a small white marker."""
    quads = [
        Quad(
            (-4.0, 3.0, 3.0),
            (8.0, 0.0, 0.0),
            (0.0, 0.0, -6.0),
            "brick",
            (8.0, 6.0),
            (0.3, 0.3, 0.3),
        )
    ]
    if marker_center is not None:
        x, y, z = marker_center
        quads.append(
            Quad(
                (x - 0.04, y - 0.01, z + 0.04),
                (0.08, 0.0, 0.0),
                (0.0, 0.0, -0.08),
                "moon",
                (1.0, 1.0),
                (40.0, 0.0, 0.0),
            )
        )  # bright red
    return Scene("wall", tuple(quads), (Light((0.0, 0.0, 1.0), 4.0),))


class LinearTrajectory:
    """Constant-velocity translation with a fixed orientation looking along +y."""

    def __init__(self, velocity: tuple[float, float, float]) -> None:
        self.velocity = np.asarray(velocity, float)
        self.rotation = look_at((0, 0, 0), (0, 1, 0))

    def poses(self, times: np.ndarray) -> np.ndarray:
        times = np.atleast_1d(np.asarray(times, float))
        return make_pose(
            np.repeat(self.rotation[None], times.size, 0), times[:, None] * self.velocity
        )


def test_intrinsics_are_the_7scenes_ones_scaled() -> None:
    np.testing.assert_allclose(intrinsics(640, 480), [[585, 0, 320], [0, 585, 240], [0, 0, 1]])
    camera = intrinsics(WIDTH, HEIGHT)
    assert camera[0, 0] == pytest.approx(585 / 4)
    assert camera[0, 2] == pytest.approx((320.5 / 4) - 0.5)


def test_known_point_projects_to_expected_pixel() -> None:
    point = (0.3, 2.99, -0.2)  # right of and below the optical axis, 2.99 m ahead
    camera = intrinsics(WIDTH, HEIGHT)
    pose = make_pose(look_at((0, 0, 0), (0, 1, 0)), (0, 0, 0))
    # by hand: camera x = world x, camera y = -world z, depth = world y
    expected = (camera[0, 0] * 0.3 / 2.99 + camera[0, 2], camera[1, 1] * 0.2 / 2.99 + camera[1, 2])
    np.testing.assert_allclose(project(np.array([point]), pose, camera)[0, :2], expected)
    image, depth = render(wall_scene(point), pose, camera, WIDTH, HEIGHT)
    red = image[..., 0] > 3 * image[..., 1] + 0.05
    rows, cols = np.nonzero(red)
    assert 4 <= rows.size <= 40  # an 8 cm marker at 3 m is about 4x4 px
    assert cols.mean() == pytest.approx(expected[0], abs=0.5)
    assert rows.mean() == pytest.approx(expected[1], abs=0.5)
    assert depth[HEIGHT // 2, WIDTH // 2] == pytest.approx(3.0, abs=1e-4)


def test_no_motion_gives_the_sharp_frame() -> None:
    config = SynthConfig(blur_strength=2.0)
    still = LinearTrajectory((0.0, 0.0, 0.0))
    blurred, sharp, _, blur = render_exposure(
        wall_scene(), still, 0.0, config, intrinsics(WIDTH, HEIGHT)
    )
    assert blur.mean_px == 0 and blur.max_px == 0
    np.testing.assert_array_equal(blurred, sharp)


def test_supersampling_integrates_each_pixel_without_moving_the_image() -> None:
    """Rays averaged over each pixel approach its area integral (approximated by 6 x 6 rays):
    edges and texture detail no longer depend on where one ray happens to fall, and a small
    marker's centroid lands on its projection (one ray per pixel quantises it)."""
    point = (0.3, 2.99, -0.2)
    pose = LinearTrajectory((0.0, 0.0, 0.0))
    camera = intrinsics(WIDTH, HEIGHT)

    def sharp(rays: int) -> np.ndarray:
        config = SynthConfig(blur_strength=0.0, supersample=rays)
        return render_exposure(wall_scene(point), pose, 0.0, config, camera)[1]

    one, three, integral = sharp(1), sharp(3), sharp(6)
    gray = {rays: image.mean(axis=2) for rays, image in ((1, one), (3, three), (6, integral))}
    assert np.abs(gray[3] - gray[6]).mean() < 0.5 * np.abs(gray[1] - gray[6]).mean()
    (dx, dy), _ = cv2.phaseCorrelate(gray[3].astype(np.float64), gray[6].astype(np.float64))
    assert np.hypot(dx, dy) < 0.05
    red = np.clip(integral[..., 0] - integral[..., 1], 0, None)
    rows, columns = np.mgrid[0:HEIGHT, 0:WIDTH]
    centroid = ((red * columns).sum() / red.sum(), (red * rows).sum() / red.sum())
    expected = (camera[0, 0] * 0.3 / 2.99 + camera[0, 2], camera[1, 1] * 0.2 / 2.99 + camera[1, 2])
    np.testing.assert_allclose(centroid, expected, atol=0.08)


def test_no_exposure_and_no_noise_stores_the_sharp_frame(tmp_path: Path) -> None:
    config = SynthConfig.quick(blur_strength=0.0, shot_noise=0.0, read_noise=0.0,
                               frames_per_sequence=3)  # fmt: skip
    synthesize(tmp_path, scenes=["heads"], config=config, workers=1, progress=False)
    sequence = load_split(tmp_path, "heads", "test")[0]
    for frame in sequence.frame_ids:
        assert filecmp.cmp(
            sequence.path(frame, "color"), sequence.path(frame, "sharp"), shallow=False
        )


@pytest.mark.parametrize(("velocity", "angle"), [((0.6, 0, 0), 0.0), ((0, 0, 0.6), 90.0)])
def test_blur_metadata_agrees_with_the_motion(velocity: tuple, angle: float) -> None:
    """Translating parallel to a wall 3 m away: every point moves fx * v * E / Z pixels."""
    config = SynthConfig(blur_strength=2.0)
    camera = intrinsics(WIDTH, HEIGHT)
    trajectory = LinearTrajectory(velocity)
    blurred, sharp, _, blur = render_exposure(wall_scene(), trajectory, 0.0, config, camera)
    exposure = config.blur_strength / config.fps
    expected = camera[0, 0] * 0.6 * exposure / 3.0  # 5.85 px
    assert blur.mean_px == pytest.approx(expected, rel=1e-3)
    assert blur.max_px == pytest.approx(expected, rel=1e-3)
    assert min(abs(blur.angle_deg - angle), 180 - abs(blur.angle_deg - angle)) < 0.5
    assert blur.samples >= expected  # sub-exposure renders at most 1 px apart
    # the rendered images agree: the first and last instants are `expected` px apart
    start = render(wall_scene(), trajectory.poses([-exposure / 2])[0], camera, WIDTH, HEIGHT)[0]
    end = render(wall_scene(), trajectory.poses([exposure / 2])[0], camera, WIDTH, HEIGHT)[0]
    (dx, dy), _ = cv2.phaseCorrelate(
        start.mean(axis=2).astype(np.float64), end.mean(axis=2).astype(np.float64)
    )
    assert np.hypot(dx, dy) == pytest.approx(expected, abs=0.3)

    # and blur removes detail along the motion more than across it
    def detail_kept(axis: int) -> float:
        return float(
            np.abs(np.diff(blurred.mean(2), axis=axis)).mean()
            / np.abs(np.diff(sharp.mean(2), axis=axis)).mean()
        )

    along, across = (1, 0) if angle == 0 else (0, 1)
    assert detail_kept(along) < 0.8 * detail_kept(across)


def test_stored_poses_are_rigid(quick_root: Path) -> None:
    for scene in ("chess", "stairs"):
        for split in ("train", "test"):
            for sequence in load_split(quick_root, scene, split):
                for pose in sequence.poses():
                    assert orthonormality_error(pose[:3, :3]) < 1e-8
                    assert np.linalg.det(pose[:3, :3]) == pytest.approx(1.0, abs=1e-8)
                    np.testing.assert_array_equal(pose[3], [0, 0, 0, 1])


def test_stored_depth_matches_the_render(quick_root: Path) -> None:
    sequence = load_split(quick_root, "chess", "test")[0]
    depth_mm = cv2.imread(str(sequence.path(0, "depth")), cv2.IMREAD_UNCHANGED)
    assert depth_mm.dtype == np.uint16
    pose = sequence.poses()[0]
    _, depth = render(make_scene("chess"), pose, intrinsics(WIDTH, HEIGHT), WIDTH, HEIGHT)
    np.testing.assert_allclose(depth_mm / 1000.0, depth, atol=6e-4)  # pose stored to 1e-9


@pytest.mark.parametrize("scene_name", SCENE_NAMES)
def test_trajectories_move_like_7scenes(scene_name: str) -> None:
    config = SynthConfig()
    frames = config.frames_for(scene_name)
    steps, turns = [], []
    for sequence in range(3):
        trajectory = HandheldTrajectory(
            make_scene(scene_name), frames / 30, np.random.default_rng(sequence), config
        )
        step, turn = frame_to_frame_motion(trajectory.poses(np.arange(frames) / 30))
        steps.append(step)
        turns.append(turn)
    steps, turns = np.concatenate(steps), np.concatenate(turns)
    assert np.median(steps) == pytest.approx(0.009, rel=0.1)
    assert np.median(turns) == pytest.approx(0.55, rel=0.1)
    # 95th percentile over median, real 7-Scenes: 1.7-3.6 (steps), 2.0-3.6 (rotations)
    assert 1.5 < np.percentile(steps, 95) / np.median(steps) < 4.5
    assert 1.5 < np.percentile(turns, 95) / np.median(turns) < 4.5


@pytest.mark.parametrize("scene_name", SCENE_NAMES)
def test_trajectories_wander_like_7scenes(scene_name: str) -> None:
    """Predicting the mean training pose misses the default stand-in's test frames by about as
    much as on the real scene: 0.4-1.4 m and 20-50 degrees (median), within a factor of 2 of
    the real scene's own baseline."""
    config = SynthConfig()
    frames = np.arange(config.frames_for(scene_name)) / config.fps
    train, test = split_sequences(scene_name, config)

    def poses(numbers: list[int]) -> np.ndarray:
        return np.concatenate(
            [sequence_trajectory(scene_name, n, config)[1].poses(frames) for n in numbers]
        )

    train_poses, test_poses = poses(train), poses(test)
    mean_rotation = Rotation.from_matrix(train_poses[:, :3, :3]).mean()
    position = np.median(
        np.linalg.norm(test_poses[:, :3, 3] - train_poses[:, :3, 3].mean(axis=0), axis=1)
    )
    rotation = np.degrees(
        np.median((mean_rotation.inv() * Rotation.from_matrix(test_poses[:, :3, :3])).magnitude())
    )
    real_position, real_rotation = REAL_MEAN_POSE_BASELINE[scene_name]
    assert 0.4 <= position <= 1.4 and 0.5 < position / real_position < 2.0
    assert 20.0 <= rotation <= 50.0 and 0.5 < rotation / real_rotation < 2.0
    # the test sequences walk where training sequences went (the scene's shared route): the
    # nearest training position lies 0.04-0.15x the baseline away (independent sequences:
    # 0.06-0.27x; fire, heads and stairs above this bar)
    nearest, _ = cKDTree(train_poses[:, :3, 3]).query(test_poses[:, :3, 3])
    assert np.median(nearest) < NEAREST_POSITION_BAR * position


def test_same_seed_gives_identical_files(quick_root: Path, tmp_path: Path) -> None:
    again = synthesize(
        tmp_path / "again",
        scenes=["chess", "stairs"],
        config=SynthConfig.quick(),
        seed=3,
        workers=2,
        progress=False,
    )
    files = sorted(p.relative_to(quick_root) for p in quick_root.rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(again) for p in again.rglob("*") if p.is_file())
    _, mismatch, errors = filecmp.cmpfiles(
        quick_root, again, [str(f) for f in files], shallow=False
    )
    assert mismatch == [] and errors == []
    other = synthesize(
        tmp_path / "other",
        scenes=["stairs"],
        config=SynthConfig.quick(),
        seed=4,
        workers=1,
        progress=False,
    )
    assert not filecmp.cmp(
        quick_root / "stairs/seq-01/frame-000000.color.png",
        other / "stairs/seq-01/frame-000000.color.png",
        shallow=False,
    )


def test_synthesize_is_idempotent(quick_root: Path) -> None:
    stamp = (quick_root / "standin.json").stat().st_mtime_ns
    synthesize(
        quick_root, scenes=["chess", "stairs"], config=SynthConfig.quick(), seed=3, progress=False
    )
    assert (quick_root / "standin.json").stat().st_mtime_ns == stamp
    assert check_data(quick_root)["scenes"]["chess"]["test"]["frames"] == 8


def test_a_stand_in_rendered_before_a_setting_existed_is_not_rendered_again(
    quick_root: Path, tmp_path: Path
) -> None:
    """Its manifest lacks the setting, which then takes its default (the earlier renderer)."""
    root = shutil.copytree(quick_root, tmp_path / "standin")
    path = root / "standin.json"
    manifest = json.loads(path.read_text())
    del manifest["config"]["supersample"]
    path.write_text(json.dumps(manifest))
    stamp = path.stat().st_mtime_ns
    config = SynthConfig.quick()
    synthesize(root, scenes=["chess", "stairs"], config=config, seed=3, progress=False)
    assert path.stat().st_mtime_ns == stamp
    synthesize(root, scenes=["chess", "stairs"], config=replace(config, supersample=2),
               seed=3, progress=False, workers=1)  # fmt: skip
    assert json.loads(path.read_text())["config"]["supersample"] == 2


def test_bad_settings_are_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="unknown scene"):
        synthesize(tmp_path, scenes=["kitchen"], progress=False)
    with pytest.raises(ValueError, match="--width"):
        SynthConfig(width=4)
    with pytest.raises(ValueError, match="--blur-strength"):
        SynthConfig(blur_strength=-1)
    with pytest.raises(ValueError, match="--route-share"):
        SynthConfig(route_share=1.01)
    for rays in (0, 2.5, 9):
        with pytest.raises(ValueError, match="--supersample"):
            SynthConfig(supersample=rays)


def test_a_real_dataset_root_is_never_rendered_into(tmp_path: Path) -> None:
    real = tmp_path / "7scenes"
    (real / "chess").mkdir(parents=True)
    (real / "chess" / "TrainSplit.txt").write_text("sequence1\n")
    with pytest.raises(ValueError, match="not a stand-in"):
        synthesize(real, scenes=["chess"], config=SynthConfig.quick(), progress=False)
    assert prepare_data_root(real, quick=True, progress=False) == real
    assert sorted(p.name for p in real.rglob("*")) == ["TrainSplit.txt", "chess"]


def test_clearance_is_the_distance_to_the_nearest_surface() -> None:
    from blurloc.data.scenes import room

    scene = Scene(
        "room",
        tuple(room(4.0, 4.0, 2.5, ("brick", 1.0, (1, 1, 1)), ("brick", 1.0, (1, 1, 1)))),
        (),
    )
    clearance = scene.clearance(np.array([[2.0, 2.0, 1.0], [0.5, 2.0, 2.0], [5.0, 2.0, 1.0]]))
    np.testing.assert_allclose(clearance, [1.0, 0.5, -1.0])


def test_an_interrupted_render_is_rendered_again(tmp_path: Path) -> None:
    root = tmp_path / "standin"
    (root / "chess").mkdir(parents=True)
    (root / "standin.json").write_text('{"incomplete": true}')  # what a render leaves if killed
    synthesize(root, scenes=["chess"], config=SynthConfig.quick(), progress=False, workers=1)
    assert check_data(root)["scenes"]["chess"]["test"]["frames"] == 8
    assert "incomplete" not in (root / "standin.json").read_text()


def test_independent_sequences_are_the_trajectories_of_before() -> None:
    """route_share 0 draws exactly the paths that stand-ins were rendered with before shared
    routes existed (values recorded from that code), so such stand-ins need no new render."""
    config = SynthConfig(frames_per_sequence=30, route_share=0.0)
    assert scene_route(make_scene("heads"), config) is None
    recorded = {"heads": (120.60368712086166, [0.99980083, 0.01349007, -0.01470759]),
                "stairs": (36.16495287565469, [0.97934822, 0.02636272, -0.20045467])}  # fmt: skip
    for scene_name, (position_sum, last_row) in recorded.items():
        _, trajectory = sequence_trajectory(scene_name, 2, config)
        poses = trajectory.poses(np.arange(config.frames_for(scene_name)) / config.fps)
        assert poses[:, :3, 3].sum() == pytest.approx(position_sum, abs=1e-9)
        np.testing.assert_allclose(poses[-1, 0, :3], last_row, atol=1e-8)


@pytest.mark.parametrize("scene_name", SCENE_NAMES)
def test_sequences_on_a_shared_route_keep_clear_and_move_like_7scenes(scene_name: str) -> None:
    config = SynthConfig()
    scene = make_scene(scene_name)
    route = scene_route(scene, config)
    assert route.shape[1] == 6
    np.testing.assert_allclose(route.mean(axis=0), 0.0, atol=1e-12)
    np.testing.assert_allclose(route.std(axis=0), 1.0, atol=1e-12)
    frames = np.arange(config.frames_for(scene_name)) / config.fps
    poses = [sequence_trajectory(scene_name, n, config)[1].poses(frames) for n in (1, 2)]
    for pose in poses:
        assert scene.clearance(pose[:, :3, 3]).min() >= scene.min_clearance_m
    steps, turns = np.concatenate([frame_to_frame_motion(pose) for pose in poses], axis=1)
    assert np.median(steps) == pytest.approx(0.009, rel=0.1)
    # the route's own turns can exceed the target in a small room (heads: 0.62 deg)
    assert np.median(turns) == pytest.approx(0.55, rel=0.15)
    # both sequences follow the same route, each from its own place on it: not the same path
    assert np.abs(poses[0][:, :3, 3] - poses[1][:, :3, 3]).max() > 0.1


#: sha256 over the relative paths and bytes of every file that ``blurloc synth --quick --scenes
#: heads --seed 0`` wrote under ``heads/`` before the painted rooms and the camera model existed.
FIRST_LOOK_HEADS_SHA256 = "1ac1b6bae9ddaa2d45e52ecfc05ebccc64b0755c1b66e78ba656f6f528ffaa9a"


def _tree_sha256(folder: Path) -> str:
    digest = hashlib.sha256()
    for path in sorted(p for p in folder.rglob("*") if p.is_file()):
        digest.update(str(path.relative_to(folder.parent)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


#: NumPy's dispatched instruction sets beyond AVX2 that this machine has: their exp, sin and the
#: like round differently from AVX2's in the last bit, which changes rendered bytes. The first
#: renderer's files were hashed on a machine without them.
WIDER_THAN_AVX2 = [name for name in ("X86_V4", "AVX512_ICL", "AVX512_SPR")
                   if __cpu_features__.get(name)]  # fmt: skip


def _render_heads_with_avx2(root: Path, previous_look: bool) -> Path:
    """``heads`` of the quick stand-in rendered in a process of its own, with NumPy limited to
    AVX2 (:data:`WIDER_THAN_AVX2`), in the previous look or the default one."""
    look = "**PREVIOUS_LOOK" if previous_look else ""
    script = (
        "import sys; from blurloc.data.synth import SynthConfig, synthesize; "
        "from blurloc.data.synth_config import PREVIOUS_LOOK; "
        f"synthesize(sys.argv[1], scenes=['heads'], config=SynthConfig.quick({look}), "
        "workers=1, progress=False)"
    )
    environment = {**os.environ, "NPY_DISABLE_CPU_FEATURES": " ".join(WIDER_THAN_AVX2)}
    subprocess.run([sys.executable, "-c", script, str(root)], env=environment, check=True)
    return root


def test_the_previous_look_renders_what_the_first_renderer_rendered(tmp_path: Path) -> None:
    root = _render_heads_with_avx2(tmp_path / "previous", previous_look=True)
    assert _tree_sha256(root / "heads") == FIRST_LOOK_HEADS_SHA256
    new = _render_heads_with_avx2(tmp_path / "new", previous_look=False)
    assert _tree_sha256(new / "heads") != FIRST_LOOK_HEADS_SHA256
    for frame in ("pose.txt", "depth.png"):  # the same camera path and geometry behind the look
        path = "heads/seq-01/frame-000004." + frame
        assert filecmp.cmp(root / path, new / path, shallow=False) == (frame == "pose.txt")


def test_a_stand_in_rendered_before_the_look_settings_is_the_previous_look(
    quick_root: Path, tmp_path: Path
) -> None:
    """A manifest without the look's settings reads them as the previous look: rendering that
    look again leaves the stand-in alone, rendering the default look renders it again."""
    config = SynthConfig.quick(**PREVIOUS_LOOK)
    root = synthesize(tmp_path / "old", scenes=["heads"], config=config, workers=1,
                      progress=False)  # fmt: skip
    path = root / "standin.json"
    manifest = json.loads(path.read_text())
    for name in PREVIOUS_LOOK:
        if name != "noise_sigma":
            del manifest["config"][name]
    path.write_text(json.dumps(manifest))
    stamp = path.stat().st_mtime_ns
    synthesize(root, scenes=["heads"], config=config, progress=False)
    assert path.stat().st_mtime_ns == stamp
    synthesize(root, scenes=["heads"], config=SynthConfig.quick(), workers=1, progress=False)
    assert json.loads(path.read_text())["config"]["scene_content"] == "painted"


def test_sensor_noise_grows_with_brightness() -> None:
    """Shot noise: the variance grows linearly with the linear signal, from the read noise's."""
    rng = np.random.default_rng(0)
    levels = np.float32([0.0, 0.1, 0.4, 0.9])
    signal = np.broadcast_to(levels[:, None], (4, 20_000))
    variance = sensor_noise(signal, 2e-4, 0.006, rng).var(axis=1)
    assert np.all(np.diff(variance) > 0)
    np.testing.assert_allclose(variance, 2e-4 * levels + 0.006**2, rtol=0.05)
    config = SynthConfig(optics_blur_px=0.0, exposure_gain=1.0)
    flat = np.full((120, 160, 3), 0.05, np.float32)
    dark, _ = capture(flat, flat, config, rng)
    bright, _ = capture(flat * 16, flat * 16, config, rng)
    linear = [srgb_to_linear(image / 255.0) for image in (dark, bright)]
    assert linear[1].std() > 2 * linear[0].std()  # in linear light, as a sensor's


def test_optics_blur_lowers_the_high_frequencies() -> None:
    """On a real photograph (scikit-image's astronaut), the optics' blur takes power from the
    high frequencies and keeps the low ones and the mean."""
    image = cv2.resize(skimage.data.astronaut(), (WIDTH, HEIGHT), interpolation=cv2.INTER_AREA)
    linear = srgb_to_linear(image.astype(np.float32) / 255.0).mean(axis=2).astype(np.float32)
    blurred = optics_blur(linear, 0.4)

    def band_power(values: np.ndarray, low: float, high: float) -> float:
        power = np.abs(np.fft.fft2(values - values.mean())) ** 2
        radius = np.hypot(*np.meshgrid(np.fft.fftfreq(WIDTH), np.fft.fftfreq(HEIGHT)))
        return float(power[(radius >= low) & (radius < high)].sum())

    assert band_power(blurred, 0.3, 0.5) < 0.6 * band_power(linear, 0.3, 0.5)
    assert band_power(blurred, 0.0, 0.05) > 0.95 * band_power(linear, 0.0, 0.05)
    assert blurred.mean() == pytest.approx(linear.mean(), rel=1e-3)
    assert optics_blur(linear, 0.0) is linear


def test_painted_rooms_have_more_strong_edges() -> None:
    """Seen from the same poses, the painted scenes have more strong edges (gradient over 0.1
    per px on [0, 1] intensities) than the photographed ones."""
    config = SynthConfig(frames_per_sequence=60)
    edges = {}
    for content in ("photographs", "painted"):
        shares = []
        for name in ("chess", "office"):
            scene, trajectory = sequence_trajectory(name, 1, replace(config, scene_content=content))
            linear, _ = render(scene, trajectory.poses([0.5])[0], intrinsics(WIDTH, HEIGHT),
                               WIDTH, HEIGHT)  # fmt: skip
            gray = (linear_to_srgb(linear) @ np.float32([0.299, 0.587, 0.114])).astype(np.float32)
            dx, dy = cv2.Sobel(gray, cv2.CV_32F, 1, 0), cv2.Sobel(gray, cv2.CV_32F, 0, 1)
            shares.append((np.hypot(dx, dy) / 8 > 0.1).mean())
        edges[content] = np.mean(shares)
    assert edges["painted"] > 1.5 * edges["photographs"]


def test_bad_look_settings_are_refused() -> None:
    for field, value in (("scene_content", "marble"), ("exposure_gain", 0.0),
                         ("optics_blur_px", float("nan")), ("jpeg_quality", 50.0)):  # fmt: skip
        with pytest.raises(ValueError, match=field):
            SynthConfig(**{field: value})
    with pytest.raises(ValueError, match="unknown scene content"):
        make_scene("chess", "marble")


def test_render_settings_are_read_from_the_stand_ins_manifest(quick_root: Path, tmp_path: Path):
    """The settings a stand-in records are those it was rendered with; a folder without a
    manifest is named in the error."""
    settings = render_settings(quick_root)
    assert settings["blur_strength"] == SynthConfig.quick().blur_strength
    assert settings["width"] == SynthConfig.quick().width
    with pytest.raises(ValueError, match="no stand-in settings"):
        render_settings(tmp_path)
