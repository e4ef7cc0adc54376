"""Image retrieval as a pose estimate: the pose of the training frame that looks most alike.

What a user would pick instead of a pose regressor: describe every training frame by one small
global descriptor, and give each query frame the pose of the training frame whose descriptor is
nearest. The descriptor is the frame in gray, shrunk with area interpolation to a thumbnail
(default 16x12 px), minus its mean and divided by its norm, so that a global change of
brightness or contrast does not move it; nearest means the largest dot product (cosine
similarity). Reference: Torii, Arandjelović, Sivic, Okutomi and Pajdla, "24/7 place recognition
by view synthesis", CVPR 2015, and Sattler, Zhou, Pollefeys and Leal-Taixé, "Understanding the
limitations of CNN-based absolute camera pose regression", CVPR 2019 (retrieval as the baseline
pose regressors are to be compared with).
"""

from __future__ import annotations

import os

import cv2
import numpy as np
from scipy.spatial.transform import Rotation

from ..data.sevenscenes import SequenceFrames, load_split, read_image
from ..metrics import pose_summary
from ..poses import PosePair, to_quaternions

#: Thumbnail size of :func:`global_descriptor`, (width, height) px.
THUMBNAIL = (16, 12)


def global_descriptor(image: np.ndarray, size: tuple[int, int] = THUMBNAIL) -> np.ndarray:
    r"""A frame's global descriptor: its normalised gray thumbnail.

    .. math::

        g = \mathrm{shrink}(\mathrm{gray}(I)), \quad d = \frac{g - \bar g}{\lVert g - \bar g
        \rVert_2}

    Parameters
    ----------
    image : numpy.ndarray
        (H, W, 3) RGB or (H, W) gray, uint8 or float.
    size : (int, int)
        Thumbnail (width, height), px.

    Returns
    -------
    numpy.ndarray
        (width * height,) float64 with zero mean and unit norm (all zeros for a flat image).
    """
    gray = np.asarray(image, np.float32)
    if gray.ndim == 3:
        gray = cv2.cvtColor(gray, cv2.COLOR_RGB2GRAY)
    thumbnail = cv2.resize(gray, size, interpolation=cv2.INTER_AREA).astype(np.float64).ravel()
    thumbnail -= thumbnail.mean()
    norm = np.linalg.norm(thumbnail)
    return thumbnail / norm if norm > 0 else thumbnail


def describe(
    sequences: list[SequenceFrames], size: tuple[int, int] = THUMBNAIL
) -> tuple[np.ndarray, np.ndarray]:
    """Descriptors and poses of every frame of ``sequences``, in sequence then frame order.

    Parameters
    ----------
    sequences : list of SequenceFrames
        The frames (their ``color`` images are read one at a time).
    size : (int, int)
        Thumbnail (width, height), px (:func:`global_descriptor`).

    Returns
    -------
    descriptors : numpy.ndarray
        (N, width * height).
    poses : numpy.ndarray
        (N, 4, 4) camera-to-world poses.
    """
    descriptors = [global_descriptor(read_image(s.path(i)), size)
                   for s in sequences for i in s.frame_ids]  # fmt: skip
    return np.stack(descriptors), np.concatenate([s.poses() for s in sequences])


def nearest_frames(queries: np.ndarray, database: np.ndarray) -> np.ndarray:
    """Index of the database descriptor most similar to each query (largest dot product).

    Parameters
    ----------
    queries : numpy.ndarray
        (M, D) descriptors.
    database : numpy.ndarray
        (N, D) descriptors.

    Returns
    -------
    numpy.ndarray
        (M,) indices into ``database``.
    """
    return np.argmax(queries @ database.T, axis=1)


def retrieval_baseline(
    root: str | os.PathLike, scene: str, size: tuple[int, int] = THUMBNAIL
) -> dict:
    """Errors of giving every test frame the pose of its nearest training frame by descriptor.

    Parameters
    ----------
    root : str or os.PathLike
        A 7-Scenes-layout root.
    scene : str
        The scene: its whole training split is the database, its test split the queries.
    size : (int, int)
        Thumbnail (width, height), px (:func:`global_descriptor`).

    Returns
    -------
    dict
        :func:`~blurloc.metrics.pose_summary` of the test frames against the retrieved poses.
    """
    database, train = describe(load_split(root, scene, "train"), size)
    queries, test = describe(load_split(root, scene, "test"), size)
    found = train[nearest_frames(queries, database)]
    true_q, found_q = (to_quaternions(Rotation.from_matrix(p[:, :3, :3])) for p in (test, found))
    pair = PosePair(test[:, :3, 3], true_q, found[:, :3, 3], found_q)
    return pose_summary(pair)
