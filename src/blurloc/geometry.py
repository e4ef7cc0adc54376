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
    r"""Camera matrix of the 7-Scenes camera scaled to another image size.

    .. math::

        K = \begin{pmatrix} f s_x & 0 & (W_0/2 + \tfrac12) s_x - \tfrac12 \\
        0 & f s_y & (H_0/2 + \tfrac12) s_y - \tfrac12 \\ 0 & 0 & 1 \end{pmatrix},
        \qquad s_x = W / W_0,\; s_y = H / H_0

    Parameters
    ----------
    width, height : int
        Image size, pixels.

    Returns
    -------
    numpy.ndarray
        (3, 3): focal lengths and principal point in pixels (centres at integers).

    Raises
    ------
    ValueError
        If the size is not positive.

    References
    ----------
    Shotton, Glocker, Zach, Izadi, Criminisi and Fitzgibbon, "Scene coordinate regression
    forests for camera relocalization in RGB-D images", CVPR 2013 (7-Scenes).
    Hartley and Zisserman, *Multiple View Geometry in Computer Vision*, 2nd ed., Cambridge
    University Press, 2004, Section 6.1 (the pinhole camera).
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
    r"""Camera-to-world rotation(s) of a camera at ``eye`` looking at ``target``.

    .. math::

        z = \frac{t - e}{\lVert t - e \rVert}, \quad
        x = \frac{z \times u}{\lVert z \times u \rVert}, \quad
        y = z \times x, \qquad R = [x\; y\; z]

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

    Raises
    ------
    ValueError
        If the viewing direction is parallel to ``up``.

    References
    ----------
    Hartley and Zisserman, *Multiple View Geometry in Computer Vision*, 2nd ed., Cambridge
    University Press, 2004, Section 6.1 (the pinhole camera).
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
    r"""Camera-to-world pose matrices.

    .. math::

        T = \begin{pmatrix} R & c \\ 0^\top & 1 \end{pmatrix}

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

    References
    ----------
    Hartley and Zisserman, *Multiple View Geometry in Computer Vision*, 2nd ed., Cambridge
    University Press, 2004, Section 6.1 (the pinhole camera).
    """
    rotation = np.asarray(rotation, float)
    position = np.asarray(position, float)
    pose = np.zeros((*rotation.shape[:-2], 4, 4))
    pose[..., :3, :3] = rotation
    pose[..., :3, 3] = position
    pose[..., 3, 3] = 1.0
    return pose


def orthonormality_error(rotation: np.ndarray) -> float:
    r"""How far a matrix is from orthonormal.

    .. math::

        \epsilon(R) = \max_{i,j} \bigl| (R^\top R - I)_{ij} \bigr|

    Parameters
    ----------
    rotation : numpy.ndarray
        (3, 3).

    Returns
    -------
    float
        Largest absolute entry of ``R^T R - I``: 0 for an exact rotation (or mirror).

    References
    ----------
    Huynh, "Metrics for 3D rotations: comparison and analysis", J. Math. Imaging Vis. 35(2),
    2009.
    The paper's eq. 13 (which assumes :math:`R` is a rotation).
    """
    rotation = np.asarray(rotation, float)
    return float(np.abs(rotation.T @ rotation - np.eye(3)).max())


def project(points_world: np.ndarray, pose: np.ndarray, camera: np.ndarray) -> np.ndarray:
    r"""Pixel coordinates and depths of world points seen from a camera.

    .. math::

        X_c = R^\top (X_w - c), \qquad
        \begin{pmatrix} u \\ v \end{pmatrix} =
        \begin{pmatrix} f_x X_c / Z_c + c_x \\ f_y Y_c / Z_c + c_y \end{pmatrix}

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

    References
    ----------
    Hartley and Zisserman, *Multiple View Geometry in Computer Vision*, 2nd ed., Cambridge
    University Press, 2004, Section 6.1 (the pinhole camera).
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
    r"""World points of pixels at known depths.

    .. math::

        X_w = R\, z \begin{pmatrix} (u - c_x) / f_x \\ (v - c_y) / f_y \\ 1 \end{pmatrix} + c

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

    References
    ----------
    Hartley and Zisserman, *Multiple View Geometry in Computer Vision*, 2nd ed., Cambridge
    University Press, 2004, Section 6.1 (the pinhole camera).
    """
    uv = np.asarray(uv, float).reshape(-1, 2)
    x = (uv[:, 0] - camera[0, 2]) / camera[0, 0]
    y = (uv[:, 1] - camera[1, 2]) / camera[1, 1]
    points_camera = np.column_stack([x, y, np.ones_like(x)]) * np.asarray(depth, float)[:, None]
    return points_camera @ pose[:3, :3].T + pose[:3, 3]


def rotation_to_quaternion(rotation: np.ndarray) -> np.ndarray:
    r"""Quaternions of rotation matrices, in the convention of :mod:`blurloc.poses`.

    .. math::

        q = (w, x, y, z), \quad w = \tfrac12 \sqrt{1 + \operatorname{trace} R} \ge 0

    Parameters
    ----------
    rotation : numpy.ndarray
        Rotation matrices, shape (N, 3, 3) or (3, 3).

    Returns
    -------
    numpy.ndarray
        Shape (N, 4) or (4,): unit ``(w, x, y, z)`` with ``w >= 0``.

    References
    ----------
    Shoemake, "Animating rotation with quaternion curves", SIGGRAPH 1985.
    SciPy's ``Rotation.from_matrix``.
    The paper's eq. 14 (orientation as a quaternion :math:`R`).
    """
    return to_quaternions(Rotation.from_matrix(np.asarray(rotation, float)))


def quaternion_to_rotation(quaternion: np.ndarray) -> np.ndarray:
    r"""Rotation matrices of quaternions ``(w, x, y, z)``; they are normalised first.

    .. math::

        R(q) = \begin{pmatrix}
        1 - 2(y^2 + z^2) & 2(xy - wz) & 2(xz + wy) \\
        2(xy + wz) & 1 - 2(x^2 + z^2) & 2(yz - wx) \\
        2(xz - wy) & 2(yz + wx) & 1 - 2(x^2 + y^2)
        \end{pmatrix}, \qquad q \leftarrow q / \lVert q \rVert

    Parameters
    ----------
    quaternion : numpy.ndarray
        Shape (N, 4) or (4,), finite and non-zero.

    Returns
    -------
    numpy.ndarray
        Shape (N, 3, 3) or (3, 3).

    References
    ----------
    Shoemake, "Animating rotation with quaternion curves", SIGGRAPH 1985.
    SciPy's ``Rotation.from_quat``.
    The paper's eq. 14 (orientation as a quaternion :math:`R`).
    """
    return from_quaternions(quaternion).as_matrix()


def rotation_defect(rotation: np.ndarray, tolerance: float = 1e-2) -> str | None:
    r"""Why a 3x3 matrix is not a rotation, in words, or None when it is one.

    .. math::

        R \in SO(3) \iff R^\top R = I \text{ and } \det R = +1

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

    References
    ----------
    Huynh, "Metrics for 3D rotations: comparison and analysis", J. Math. Imaging Vis. 35(2),
    2009.
    The paper's eq. 13 (which assumes :math:`R` is a rotation).
    """
    error = orthonormality_error(rotation)
    if error > tolerance:
        return f"not orthonormal: max |R^T R - I| = {error:.3g} > {tolerance:g}"
    determinant = float(np.linalg.det(rotation))
    if determinant <= 0:
        return f"not a rotation: determinant {determinant:.3g}"
    return None


def frame_to_frame_motion(poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r"""Camera step and rotation between consecutive poses.

    .. math::

        s_k = \lVert c_{k+1} - c_k \rVert_2, \qquad
        2 \cos \alpha_k = \operatorname{trace}(R_k^\top R_{k+1}) - 1

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

    References
    ----------
    The paper's eq. 12-13, applied to neighbouring frames.
    """
    poses = np.asarray(poses, float)
    steps = np.linalg.norm(np.diff(poses[:, :3, 3], axis=0), axis=1)
    rotations = Rotation.from_matrix(poses[:, :3, :3])
    return steps, rotation_angles_deg(rotations[:-1], rotations[1:])


def image_motion_px(
    pose_from: np.ndarray,
    pose_to: np.ndarray,
    camera: np.ndarray,
    image_size: tuple[int, int],
    depth_m: float,
    grid: tuple[int, int] = (16, 12),
) -> float:
    r"""Mean distance that the image moves between two camera poses.

    A grid of pixels over the image is back-projected at ``depth_m`` from the first pose,
    projected into the second, and the displacements are averaged:

    .. math::

        m = \frac{1}{|G|} \sum_{u \in G}
            \bigl\lVert \pi\bigl(T_2^{-1}\, T_1\, z\, K^{-1} \tilde u\bigr) - u \bigr\rVert_2

    Unlike the rotation angle times the focal length, this follows what a camera sees: a roll
    about the optical axis moves the image centre by nothing and its corners the most, and a
    translation moves near scenes more than far ones.

    Parameters
    ----------
    pose_from, pose_to : numpy.ndarray
        (4, 4) camera-to-world poses, metres.
    camera : numpy.ndarray
        (3, 3) camera matrix, pixels.
    image_size : tuple of int
        (width, height), pixels.
    depth_m : float
        Depth of the scene (> 0), metres: e.g. the frame's median depth.
    grid : tuple of int
        Pixels of the grid across and down the image.

    Returns
    -------
    float
        Mean image motion, pixels. Points that end behind the camera count as not moved.

    References
    ----------
    Hartley and Zisserman, *Multiple View Geometry in Computer Vision*, 2nd ed., Cambridge
    University Press, 2004, Section 6.1 (the pinhole camera).
    """
    if not depth_m > 0:
        raise ValueError(f"depth_m must be > 0, got {depth_m}")
    width, height = image_size
    u, v = np.meshgrid((np.arange(grid[0]) + 0.5) * width / grid[0],
                       (np.arange(grid[1]) + 0.5) * height / grid[1])  # fmt: skip
    pixels = np.column_stack([u.ravel(), v.ravel()])
    world = backproject(pixels, np.full(len(pixels), float(depth_m)), pose_from, camera)
    moved = project(world, pose_to, camera)
    ahead = moved[:, 2] > 0
    shift = np.zeros(len(pixels))
    shift[ahead] = np.linalg.norm(moved[ahead, :2] - pixels[ahead], axis=1)
    return float(shift.mean())
