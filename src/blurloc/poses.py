"""Camera poses as the package passes them around.

One quaternion convention holds everywhere in blurloc: unit quaternions are stored **scalar
first**, ``(w, x, y, z)``, in the **canonical hemisphere** ``w >= 0`` (``q`` and ``-q`` are the same
rotation). Every conversion goes through :class:`scipy.spatial.transform.Rotation`.

A :class:`PosePair` holds the reference (ground-truth) poses and the estimated poses of the same
frames, in that order (the order of evo and of the metrics in :mod:`blurloc.metrics`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation


def to_quaternions(rotations: Rotation) -> np.ndarray:
    r"""Unit quaternions ``(w, x, y, z)`` with ``w >= 0`` of ``rotations``.

    .. math::

        q = (w, x, y, z) = \bigl(\cos\tfrac{\alpha}{2},\; n \sin\tfrac{\alpha}{2}\bigr),
        \qquad q \leftarrow -q \text{ if } w < 0

    Parameters
    ----------
    rotations : scipy.spatial.transform.Rotation
        One or several rotations.

    Returns
    -------
    numpy.ndarray
        Shape (N, 4) (or (4,) for a single rotation), float64.

    References
    ----------
    Shoemake, "Animating rotation with quaternion curves", SIGGRAPH 1985.
    SciPy's ``Rotation.as_quat(canonical=True, scalar_first=True)``.
    The paper's eq. 14 (orientation as a quaternion :math:`R`).
    """
    return rotations.as_quat(canonical=True, scalar_first=True)


def from_quaternions(quaternions: np.ndarray) -> Rotation:
    r"""Rotations of quaternions ``(w, x, y, z)``; they are normalised first.

    .. math::

        q \leftarrow \frac{q}{\lVert q \rVert}

    Parameters
    ----------
    quaternions : numpy.ndarray
        Shape (N, 4) or (4,), scalar first, any non-zero norm.

    Returns
    -------
    scipy.spatial.transform.Rotation

    Raises
    ------
    ValueError
        If a quaternion is zero or not finite.

    References
    ----------
    Shoemake, "Animating rotation with quaternion curves", SIGGRAPH 1985.
    SciPy's ``Rotation.from_quat(scalar_first=True)``.
    The paper's eq. 14 (orientation as a quaternion :math:`R`).
    """
    q = np.asarray(quaternions, float)
    if q.shape[-1] != 4 or not np.all(np.isfinite(q)) or np.any(np.linalg.norm(q, axis=-1) < 1e-12):
        raise ValueError("quaternions must be finite, non-zero (..., 4) arrays (w, x, y, z)")
    return Rotation.from_quat(q, scalar_first=True)


def rotation_angles_deg(reference: Rotation, estimate: Rotation) -> np.ndarray:
    r"""Angle of the rotation taking each reference orientation to its estimate.

    The α of eq. 13, read from the rotation vector of ``R_ref^T R_est`` (which stays precise
    for small angles, where arccos of the trace does not):

    .. math::

        1 + 2 \cos \alpha = \operatorname{trace}(R_{\text{ref}}^\top R_{\text{est}}),
        \qquad \alpha = 2 \arccos |\langle q_{\text{ref}}, q_{\text{est}} \rangle|

    the second form being the PoseNet/AtLoc orientation error.

    Parameters
    ----------
    reference, estimate : scipy.spatial.transform.Rotation
        N rotations each (or one, broadcast against the other).

    Returns
    -------
    numpy.ndarray
        Shape (N,), degrees in [0, 180].

    References
    ----------
    Kendall, Grimes and Cipolla, "PoseNet: a convolutional network for real-time 6-DOF camera
    relocalization", ICCV 2015. Huynh, "Metrics for 3D rotations: comparison and analysis",
    J. Math. Imaging Vis. 35(2), 2009. Eq. 13 of the paper.
    """
    return np.degrees((reference.inv() * estimate).magnitude())


@dataclass(frozen=True)
class PosePair:
    """Reference and estimated poses of the same N frames, reference first.

    Attributes
    ----------
    reference_positions, estimate_positions : numpy.ndarray
        Camera positions (N, 3), metres, world frame.
    reference_quaternions, estimate_quaternions : numpy.ndarray
        Camera-to-world orientations (N, 4), ``(w, x, y, z)``, unit, ``w >= 0``
        (normalised and moved to that hemisphere on construction).
    """

    reference_positions: np.ndarray
    reference_quaternions: np.ndarray
    estimate_positions: np.ndarray
    estimate_quaternions: np.ndarray

    def __post_init__(self) -> None:
        for name in ("reference_positions", "estimate_positions"):
            value = np.asarray(getattr(self, name), float)
            if value.ndim != 2 or value.shape[1] != 3 or not np.all(np.isfinite(value)):
                raise ValueError(f"{name} must be a finite (N, 3) array, got shape {value.shape}")
            object.__setattr__(self, name, value)
        for name in ("reference_quaternions", "estimate_quaternions"):
            value = np.asarray(getattr(self, name), float)
            if value.ndim != 2:
                raise ValueError(f"{name} must be an (N, 4) array, got shape {value.shape}")
            object.__setattr__(self, name, to_quaternions(from_quaternions(value)))
        sizes = {len(getattr(self, n)) for n in self.__dataclass_fields__}
        if len(sizes) != 1:
            raise ValueError(f"pose arrays differ in length: {sorted(sizes)}")

    def __len__(self) -> int:
        return len(self.reference_positions)

    @property
    def reference_rotations(self) -> Rotation:
        """The reference orientations as a :class:`~scipy.spatial.transform.Rotation`."""
        return from_quaternions(self.reference_quaternions)

    @property
    def estimate_rotations(self) -> Rotation:
        """The estimated orientations as a :class:`~scipy.spatial.transform.Rotation`."""
        return from_quaternions(self.estimate_quaternions)
