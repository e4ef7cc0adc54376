"""Rotations, quaternions and camera poses.

Conventions (those of 7-Scenes): a pose is a 4x4 camera-to-world matrix in metres; the camera
frame is OpenCV's (x right, y down, z forward); pixel centres sit at integer coordinates.
Quaternions are (w, x, y, z), unit, on the hemisphere w >= 0.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

#: 7-Scenes colour intrinsics at 640x480 (Kinect v1): fx = fy = 585, principal point (320, 240).
SEVEN_SCENES_FOCAL = 585.0
SEVEN_SCENES_SIZE = (640, 480)


def intrinsics(width: int, height: int) -> np.ndarray:
    """3x3 camera matrix of the 7-Scenes camera scaled to ``width`` x ``height`` pixels."""
    if width <= 0 or height <= 0:
        raise ValueError(f"image size must be positive, got {width}x{height}")
    sx = width / SEVEN_SCENES_SIZE[0]
    sy = height / SEVEN_SCENES_SIZE[1]
    # Scale the continuous image plane, then return to integer pixel centres.
    cx = (SEVEN_SCENES_SIZE[0] / 2 + 0.5) * sx - 0.5
    cy = (SEVEN_SCENES_SIZE[1] / 2 + 0.5) * sy - 0.5
    return np.array(
        [[SEVEN_SCENES_FOCAL * sx, 0.0, cx], [0.0, SEVEN_SCENES_FOCAL * sy, cy], [0.0, 0.0, 1.0]]
    )


def look_at(eye: np.ndarray, target: np.ndarray, up: np.ndarray = (0.0, 0.0, 1.0)) -> np.ndarray:
    """Camera-to-world rotation(s) of a camera at ``eye`` looking at ``target`` (world z up).

    ``eye`` and ``target`` are (..., 3) arrays that broadcast; returns (..., 3, 3) whose columns
    are the camera's x (right), y (down) and z (forward) axes in the world.
    """
    forward = np.asarray(target, float) - np.asarray(eye, float)
    forward = forward / np.linalg.norm(forward, axis=-1, keepdims=True)
    right = np.cross(forward, np.broadcast_to(np.asarray(up, float), forward.shape))
    norm = np.linalg.norm(right, axis=-1, keepdims=True)
    if np.any(norm < 1e-9):
        raise ValueError("viewing direction is parallel to the up vector")
    right = right / norm
    down = np.cross(forward, right)
    return np.stack([right, down, forward], axis=-1)


def make_pose(rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    """4x4 camera-to-world pose(s) from rotation(s) (..., 3, 3) and position(s) (..., 3)."""
    rotation = np.asarray(rotation, float)
    position = np.asarray(position, float)
    pose = np.zeros((*rotation.shape[:-2], 4, 4))
    pose[..., :3, :3] = rotation
    pose[..., :3, 3] = position
    pose[..., 3, 3] = 1.0
    return pose


def orthonormality_error(rotation: np.ndarray) -> float:
    """Largest absolute entry of R^T R - I: 0 for an exact rotation."""
    rotation = np.asarray(rotation, float)
    return float(np.abs(rotation.T @ rotation - np.eye(3)).max())


def project(points_world: np.ndarray, pose: np.ndarray, camera: np.ndarray) -> np.ndarray:
    """Pixel coordinates (N, 2) and depths (N,) of world points seen from a camera-to-world pose.

    Returns an (N, 3) array: u, v (pixels, centres at integers) and z (metres, along the axis).
    """
    points_world = np.asarray(points_world, float).reshape(-1, 3)
    rotation, position = pose[:3, :3], pose[:3, 3]
    points_camera = (points_world - position) @ rotation
    z = points_camera[:, 2]
    uv = points_camera[:, :2] / z[:, None] * [camera[0, 0], camera[1, 1]] + camera[:2, 2]
    return np.column_stack([uv, z])


def backproject(
    uv: np.ndarray, depth: np.ndarray, pose: np.ndarray, camera: np.ndarray
) -> np.ndarray:
    """World points (N, 3) of pixels ``uv`` (N, 2) at z-depths ``depth`` (N,) metres."""
    uv = np.asarray(uv, float).reshape(-1, 2)
    x = (uv[:, 0] - camera[0, 2]) / camera[0, 0]
    y = (uv[:, 1] - camera[1, 2]) / camera[1, 1]
    points_camera = np.column_stack([x, y, np.ones_like(x)]) * np.asarray(depth, float)[:, None]
    return points_camera @ pose[:3, :3].T + pose[:3, 3]


def rotation_to_quaternion(rotation: np.ndarray) -> np.ndarray:
    """Unit quaternion(s) (w, x, y, z) with w >= 0 of rotation matrices (..., 3, 3)."""
    xyzw = Rotation.from_matrix(np.asarray(rotation, float)).as_quat()
    wxyz = np.concatenate([xyzw[..., 3:], xyzw[..., :3]], axis=-1)
    return np.where(wxyz[..., :1] < 0, -wxyz, wxyz)


def quaternion_to_rotation(quaternion: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of quaternions (w, x, y, z); normalised first."""
    q = np.asarray(quaternion, float)
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    if np.any(norm < 1e-12) or not np.all(np.isfinite(q)):
        raise ValueError("quaternion is zero or not finite")
    q = q / norm
    return Rotation.from_quat(np.concatenate([q[..., 1:], q[..., :1]], axis=-1)).as_matrix()


def rotation_angle_deg(rotation_a: np.ndarray, rotation_b: np.ndarray) -> np.ndarray:
    """Angle (degrees) of the rotation taking ``rotation_a`` to ``rotation_b``: the α of eq. 13
    (2 cos α = trace(R_a^T R_b) - 1), taken from the rotation vector, which stays precise for
    the small angles between consecutive frames where arccos of the trace does not."""
    relative = np.swapaxes(np.asarray(rotation_a, float), -1, -2) @ np.asarray(rotation_b, float)
    return np.degrees(Rotation.from_matrix(relative).magnitude())


def frame_to_frame_motion(poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Camera step (metres) and rotation (degrees) between consecutive poses (N, 4, 4)."""
    poses = np.asarray(poses, float)
    steps = np.linalg.norm(np.diff(poses[:, :3, 3], axis=0), axis=1)
    angles = rotation_angle_deg(poses[:-1, :3, :3], poses[1:, :3, :3])
    return steps, angles
