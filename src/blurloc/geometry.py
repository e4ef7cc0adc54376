"""Rotations, quaternions and camera poses.

Conventions (those of 7-Scenes): a pose is a 4x4 camera-to-world matrix in metres; the camera
frame is OpenCV's (x right, y down, z forward); pixel centres sit at integer coordinates.
Quaternions follow :mod:`blurloc.poses`: (w, x, y, z), unit, w >= 0.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from .poses import from_quaternions, rotation_angles_deg, to_quaternions

#: 7-Scenes colour intrinsics at 640x480 (Kinect v1): fx = fy = 585, principal point (320, 240).
SEVEN_SCENES_FOCAL = 585.0
SEVEN_SCENES_SIZE = (640, 480)


def intrinsics(width: int, height: int) -> np.ndarray:
    """Camera matrix of the 7-Scenes camera scaled to another image size.

    Parameters
    ----------
    width, height : int
        Image size, pixels.

    Returns
    -------
    numpy.ndarray
        (3, 3): focal lengths and principal point in pixels (centres at integers).
    """
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
    """Camera-to-world rotation(s) of a camera at ``eye`` looking at ``target``.

    Parameters
    ----------
    eye, target : numpy.ndarray
        (..., 3), metres, world frame; they broadcast against each other.
    up : numpy.ndarray
        (3,), the world's up direction (z).

    Returns
    -------
    numpy.ndarray
        (..., 3, 3), columns: camera x (right), y (down), z (forward) in world coordinates.
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
    """Camera-to-world pose matrices.

    Parameters
    ----------
    rotation : numpy.ndarray
        (..., 3, 3).
    position : numpy.ndarray
        (..., 3), metres.

    Returns
    -------
    numpy.ndarray
        (..., 4, 4).
    """
    rotation = np.asarray(rotation, float)
    position = np.asarray(position, float)
    pose = np.zeros((*rotation.shape[:-2], 4, 4))
    pose[..., :3, :3] = rotation
    pose[..., :3, 3] = position
    pose[..., 3, 3] = 1.0
    return pose


def orthonormality_error(rotation: np.ndarray) -> float:
    """How far a matrix is from orthonormal.

    Parameters
    ----------
    rotation : numpy.ndarray
        (3, 3).

    Returns
    -------
    float
        Largest absolute entry of ``R^T R - I``: 0 for an exact rotation (or mirror).
    """
    rotation = np.asarray(rotation, float)
    return float(np.abs(rotation.T @ rotation - np.eye(3)).max())


def project(points_world: np.ndarray, pose: np.ndarray, camera: np.ndarray) -> np.ndarray:
    """Pixel coordinates and depths of world points seen from a camera.

    Parameters
    ----------
    points_world : numpy.ndarray
        (N, 3), metres.
    pose : numpy.ndarray
        (4, 4), camera-to-world.
    camera : numpy.ndarray
        (3, 3) camera matrix, pixels.

    Returns
    -------
    numpy.ndarray
        (N, 3): u, v (pixels, centres at integers) and z (metres, along the optical axis).
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
    """World points of pixels at known depths.

    Parameters
    ----------
    uv : numpy.ndarray
        (N, 2), pixels.
    depth : numpy.ndarray
        (N,), z-depths, metres.
    pose : numpy.ndarray
        (4, 4), camera-to-world.
    camera : numpy.ndarray
        (3, 3) camera matrix, pixels.

    Returns
    -------
    numpy.ndarray
        (N, 3), metres, world frame.
    """
    uv = np.asarray(uv, float).reshape(-1, 2)
    x = (uv[:, 0] - camera[0, 2]) / camera[0, 0]
    y = (uv[:, 1] - camera[1, 2]) / camera[1, 1]
    points_camera = np.column_stack([x, y, np.ones_like(x)]) * np.asarray(depth, float)[:, None]
    return points_camera @ pose[:3, :3].T + pose[:3, 3]


def rotation_to_quaternion(rotation: np.ndarray) -> np.ndarray:
    """Quaternions of rotation matrices, in the convention of :mod:`blurloc.poses`.

    Parameters
    ----------
    rotation : numpy.ndarray
        Rotation matrices, shape (N, 3, 3) or (3, 3).

    Returns
    -------
    numpy.ndarray
        Shape (N, 4) or (4,): unit ``(w, x, y, z)`` with ``w >= 0``.
    """
    return to_quaternions(Rotation.from_matrix(np.asarray(rotation, float)))


def quaternion_to_rotation(quaternion: np.ndarray) -> np.ndarray:
    """Rotation matrices of quaternions ``(w, x, y, z)``; they are normalised first.

    Parameters
    ----------
    quaternion : numpy.ndarray
        Shape (N, 4) or (4,), finite and non-zero.

    Returns
    -------
    numpy.ndarray
        Shape (N, 3, 3) or (3, 3).
    """
    return from_quaternions(quaternion).as_matrix()


def rotation_defect(rotation: np.ndarray, tolerance: float = 1e-2) -> str | None:
    """Why a 3x3 matrix is not a rotation, in words, or None when it is one.

    Parameters
    ----------
    rotation : numpy.ndarray
        Shape (3, 3).
    tolerance : float
        Largest accepted entry of ``|R^T R - I|``.

    Returns
    -------
    str or None
        ``"not a rotation: determinant -1"`` for a mirror, ``"not orthonormal: ..."`` when
        ``R^T R`` is not the identity, None for a proper rotation.
    """
    error = orthonormality_error(rotation)
    if error > tolerance:
        return f"not orthonormal: max |R^T R - I| = {error:.3g} > {tolerance:g}"
    determinant = float(np.linalg.det(rotation))
    if determinant <= 0:
        return f"not a rotation: determinant {determinant:.3g}"
    return None


def frame_to_frame_motion(poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Camera step and rotation between consecutive poses.

    Parameters
    ----------
    poses : numpy.ndarray
        Camera-to-world poses, shape (N, 4, 4), metres.

    Returns
    -------
    steps : numpy.ndarray
        Shape (N - 1,), metres.
    angles : numpy.ndarray
        Shape (N - 1,), degrees (the α of eq. 13 between neighbours).
    """
    poses = np.asarray(poses, float)
    steps = np.linalg.norm(np.diff(poses[:, :3, 3], axis=0), axis=1)
    rotations = Rotation.from_matrix(poses[:, :3, :3])
    return steps, rotation_angles_deg(rotations[:-1], rotations[1:])
