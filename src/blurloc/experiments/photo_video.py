"""Blurred videos made the GoPro way from still photographs: the video benchmark's set, and
training videos from other photographs."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass

import cv2
import numpy as np
import skimage.data

from ..images import as_float_image, srgb_to_linear, to_uint8
from ..metrics import mean_frame_psnr
from .estimation import PHOTOS

#: The photographs (scikit-image names) and pan speeds (px per sub-frame) of the photo-video set:
#: 9 sub-frames per frame, so the blur spans about 4.5, 9 and 13.5 px at 160x120.
PHOTO_VIDEO_PHOTOS = ("astronaut", "coffee", "chelsea", "rocket", "immunohistochemistry")
PHOTO_VIDEO_SPEEDS = (0.5, 1.0, 1.5)
#: Frames of every photo training video (:func:`photo_training_videos`).
PHOTO_TRAINING_FRAMES = 30
#: Photographs for training videos: the other photographs of notebook 01's set, none of which the
#: photo-video set shows.
PHOTO_TRAINING_PHOTOS = tuple(photo for photo in PHOTOS if photo not in PHOTO_VIDEO_PHOTOS)


def photo_video(
    photo: np.ndarray,
    frames: int = 12,
    subframes: int = 9,
    step_px: float = 1.0,
    angle_deg: float = 0.0,
    size: tuple[int, int] = (160, 120),
    noise_sigma: float = 0.01,
    seed: int = 0,
    roll_deg: float = 0.0,
    zoom: float = 0.0,
    exposure_subframes: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """A blurred video made the GoPro way from a still photograph.

    A virtual high-frame-rate camera pans over ``photo`` (with a small wobble); each stored frame is
    the mean of ``subframes`` consecutive sub-frames in linear light (gamma 2.2) plus noise, its
    sharp frame the middle sub-frame. With ``exposure_subframes`` a stored frame averages that many
    sub-frames about its middle one instead, while frames stay ``subframes`` sub-frames apart: an
    exposure share of ``exposure_subframes / subframes`` (5 of 9: about a 180° shutter; above
    ``subframes`` an exposure longer than the frame interval, as the stand-in renders). With
    ``roll_deg`` or ``zoom`` the camera also turns about its optical axis, or moves towards the
    photograph, by that much per sub-frame (sub-frame n of the video is turned by n ``roll_deg`` and
    magnified by 1 + n ``zoom`` about the frame's centre): the image then moves differently in
    different parts of the frame, as it does in real footage, and :func:`photo_video_motion` gives
    the pan before the turn and magnification: the content at the frame's centre in sub-frame n
    moves on to sub-frame m by the pan's step :math:`p_m - p_n` turned by m ``roll_deg`` and
    magnified by 1 + m ``zoom``.

    Parameters
    ----------
    photo : numpy.ndarray
        RGB image (H, W, 3), uint8 or float in [0, 1].
    frames : int
        Number of stored frames.
    subframes : int
        Sub-frames averaged into each stored frame.
    step_px : float
        Pan per sub-frame, pixels at output scale.
    angle_deg : float
        Pan direction, degrees.
    size : (int, int)
        Output (width, height), pixels.
    noise_sigma : float
        Gaussian noise on the gamma-encoded [0, 1] intensities.
    seed : int
        Seed of the noise.
    roll_deg : float
        Turn about the optical axis per sub-frame, degrees (counter-clockwise in the image).
    zoom : float
        Relative magnification per sub-frame (0.003: 0.3 % larger each sub-frame), > -1 /
        (frames x subframes - 1).
    exposure_subframes : int, optional
        Sub-frames averaged into each stored frame, odd (default ``subframes``).

    Returns
    -------
    blurred, sharp : numpy.ndarray
        uint8, each (frames, height, width, 3).
    """
    photo = as_float_image(photo)
    if photo.ndim != 3 or frames < 1 or subframes < 1:
        raise ValueError("photo must be RGB; frames and subframes must be positive")
    exposure = subframes if exposure_subframes is None else exposure_subframes
    if exposure_subframes is not None and (exposure < 1 or exposure % 2 == 0):
        raise ValueError(f"exposure_subframes must be odd and positive, got {exposure}")
    if not 1.0 + zoom * (frames * subframes - 1) > 0:
        raise ValueError(f"zoom {zoom} shrinks the last sub-frames to nothing: it must be > "
                         f"-1 / {frames * subframes - 1}")  # fmt: skip
    width, height = size
    scale = 2  # sub-frames are rendered at twice the output size, then area-averaged down
    linear = srgb_to_linear(cv2.resize(np.float32(photo), (3 * width * scale, 3 * height * scale),
                                       interpolation=cv2.INTER_AREA))  # fmt: skip
    positions = photo_video_motion(frames, subframes, step_px, angle_deg, exposure)
    rng = np.random.default_rng(seed)
    blurred, sharp = [], []
    for frame in range(frames):
        views = []
        for sub in range(exposure):
            origin = (np.array([width, height]) - positions[frame, sub]) * scale  # view moves
            matrix = np.float32([[1, 0, -origin[0]], [0, 1, -origin[1]]])
            if roll_deg or zoom:  # then turn and magnify about the frame's centre
                count = frame * subframes + subframes // 2 - exposure // 2 + sub
                turn = cv2.getRotationMatrix2D((width * scale / 2, height * scale / 2),
                                               roll_deg * count, 1.0 + zoom * count)  # fmt: skip
                matrix = np.float32(
                    np.column_stack([turn[:, :2], turn[:, :2] @ -origin + turn[:, 2]])
                )
            view = cv2.warpAffine(
                linear, matrix, (width * scale, height * scale), borderMode=cv2.BORDER_REFLECT
            )  # bilinear
            views.append(cv2.resize(view, size, interpolation=cv2.INTER_AREA))
        noise = rng.normal(0, noise_sigma, views[0].shape)
        blurred.append(to_uint8(np.mean(views, axis=0), noise))
        sharp.append(to_uint8(views[exposure // 2]))
    return np.stack(blurred), np.stack(sharp)


def photo_video_motion(
    frames: int,
    subframes: int = 9,
    step_px: float = 1.0,
    angle_deg: float = 0.0,
    exposure_subframes: int | None = None,
) -> np.ndarray:
    r"""Where the photograph's content lies in every sub-frame of :func:`photo_video`.

    The virtual camera pans by ``step_px`` per sub-frame in direction :math:`\alpha` with a
    wobble, so the content at sub-frame :math:`n` (counted over the whole video) sits at

    .. math::

        p_n = -\left( n\, s \,(\cos\alpha, \sin\alpha) + 1.5\,(\sin(n/7), \cos(n/5)) \right)

    px of the output frames (x right, y down). A stored frame's exposure path is its sub-frames'
    positions less that of its middle one (its sharp frame), the path whose kernel
    (:func:`blurloc.blur.trajectory_kernel`) blurs the sharp frame into the blurred one; the
    middle positions' differences are the motion from frame to frame.

    Parameters
    ----------
    frames : int
        Stored frames.
    subframes : int
        Sub-frames per stored frame.
    step_px : float
        Pan per sub-frame, px.
    angle_deg : float
        Pan direction, degrees.
    exposure_subframes : int, optional
        Sub-frames averaged into each stored frame, about its middle one (default
        ``subframes``: sub-frames ``frame * subframes`` to ``frame * subframes + subframes - 1``).

    Returns
    -------
    numpy.ndarray
        (frames, exposure_subframes, 2) content positions, px.
    """
    exposure = subframes if exposure_subframes is None else exposure_subframes
    first = np.arange(frames) * subframes + subframes // 2 - exposure // 2
    time = (first[:, None] + np.arange(exposure)[None, :]).astype(float).ravel()
    direction = np.array([np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))])
    wobble = 1.5 * np.column_stack([np.sin(time / 7), np.cos(time / 5)])
    return -(step_px * time[:, None] * direction + wobble).reshape(frames, exposure, 2)


def restoration_psnr(
    restore: Callable[[np.ndarray], np.ndarray], blurred: np.ndarray, sharp: np.ndarray
) -> tuple[float, float]:
    """Mean PSNR (eq. 6) of a blurred video and of its restoration against the sharp frames.

    Parameters
    ----------
    restore : callable
        Function of a uint8 (T, H, W, 3) video returning one of that shape, e.g.
        :class:`blurloc.inference.VideoRestorer`.
    blurred, sharp : numpy.ndarray
        uint8 (T, H, W, 3) videos; ``blurred`` is restored as one video.

    Returns
    -------
    before, after : float
        Mean PSNR over the frames, dB, of ``blurred`` and of ``restore(blurred)``.
    """
    before = mean_frame_psnr([(blurred, sharp)])
    after = mean_frame_psnr([(restore(blurred), sharp)])
    return before, after


def photo_video_gains(
    restore: Callable[[np.ndarray], np.ndarray],
    frames: int = 8,
    noise_sigma: float = 0.01,
    roll_deg: float = 0.0,
    zoom: float = 0.0,
) -> list[dict]:
    """PSNR gain of a video restorer on the photo-video set, one row per video.

    Every video of :func:`photo_video_set` is restored as one video.

    Parameters
    ----------
    restore : callable
        Function of a uint8 (T, H, W, 3) video returning one of that shape, e.g.
        :class:`blurloc.inference.VideoRestorer`.
    frames : int
        Stored frames per video.
    noise_sigma : float
        Sensor noise of the blurred frames (:func:`photo_video`); the default is the stand-in's.
        Real footage averaged the GoPro way has less: averaging N frames divides a frame's
        noise by about sqrt(N).
    roll_deg, zoom : float
        The camera's turn about its optical axis and magnification per sub-frame
        (:func:`photo_video`).

    Returns
    -------
    list of dict
        ``photo``, ``step_px``, ``blurred_psnr_db``, ``restored_psnr_db`` and ``gain_db``
        (mean PSNR over the frames, eq. 6, against the sharp middle sub-frames).
    """
    rows = []
    for video in photo_video_set(frames, noise_sigma, roll_deg, zoom):
        before, after = restoration_psnr(restore, video.blurred, video.sharp)
        rows.append({"photo": video.photo, "step_px": video.step_px, "blurred_psnr_db": before,
                     "restored_psnr_db": after, "gain_db": after - before})  # fmt: skip
    return rows


@dataclass(frozen=True)
class PhotoVideo:
    """One video of :func:`photo_video_set`: the photograph's name, the pan (``step_px`` per
    sub-frame in direction ``angle_deg``) and the uint8 ``blurred`` and ``sharp`` frames."""

    photo: str
    step_px: float
    angle_deg: float
    blurred: np.ndarray
    sharp: np.ndarray


def photo_video_set(
    frames: int = 8,
    noise_sigma: float = 0.01,
    roll_deg: float = 0.0,
    zoom: float = 0.0,
    exposure_subframes: int | None = None,
) -> Iterator[PhotoVideo]:
    """The photo-video set, one video at a time.

    Every photograph of :data:`PHOTO_VIDEO_PHOTOS` panned at every speed of
    :data:`PHOTO_VIDEO_SPEEDS` (:func:`photo_video`, 9 sub-frames per frame), in direction 37°
    times the photograph's index, its noise seeded by that index; the true motion of each is
    :func:`photo_video_motion` of its pan.

    Parameters
    ----------
    frames : int
        Stored frames per video.
    noise_sigma : float
        Sensor noise of the blurred frames (:func:`photo_video`).
    roll_deg, zoom : float
        The camera's turn about its optical axis and magnification per sub-frame
        (:func:`photo_video`; with either, :func:`photo_video_motion` gives the pan before
        them).
    exposure_subframes : int, optional
        Sub-frames averaged into each frame (:func:`photo_video`; default 9, all of them).

    Yields
    ------
    PhotoVideo
    """
    for index, photo in enumerate(PHOTO_VIDEO_PHOTOS):
        image = getattr(skimage.data, photo)()
        angle = 37.0 * index
        for step in PHOTO_VIDEO_SPEEDS:
            blurred, sharp = photo_video(image, frames, step_px=step, angle_deg=angle,
                                         noise_sigma=noise_sigma, seed=index,
                                         roll_deg=roll_deg, zoom=zoom,
                                         exposure_subframes=exposure_subframes)  # fmt: skip
            yield PhotoVideo(photo, step, angle, blurred, sharp)


def photo_training_videos(
    count: int,
    frames: int = PHOTO_TRAINING_FRAMES,
    seed: int = 0,
    photos: tuple[str, ...] = PHOTO_TRAINING_PHOTOS,
    noise_sigma: float = 0.01,
    roll_deg: float = 0.0,
    zoom: float = 0.0,
    exposure_subframes: int | None = None,
) -> list[tuple[np.ndarray, np.ndarray]]:
    """Blurred videos with their sharp frames, made the GoPro way (:func:`photo_video`) from
    photographs, for training a video deblurrer on natural image content.

    Video ``i`` pans over photograph ``photos[i % len(photos)]`` after a random crop (70-100 %
    of each side, drawn apart, so that the crop, resized to 4:3 by :func:`photo_video`, is also
    magnified and stretched by up to about 2x), a random quarter turn and a random mirror, at a
    random speed of 0.25-1.75 px per sub-frame (blur of about 2-16 px at 160x120) in a random
    direction, with its own noise. Gray photographs (seven of the nine defaults) become gray
    RGB. The pan runs ``frames`` x 9 sub-frames: at 30 frames most videos leave the photograph
    and go on over its mirror image (:func:`photo_video` reflects at the border), so their
    frames can show mirror seams, in the blurred and the sharp frames alike.

    Parameters
    ----------
    count : int
        Number of videos.
    frames : int
        Stored frames per video.
    seed : int
        Seed of the crops, turns, speeds, directions and noise.
    photos : tuple of str
        scikit-image photograph names (default :data:`PHOTO_TRAINING_PHOTOS`, disjoint from the
        photo-video set that :func:`photo_video_gains` scores).
    noise_sigma : float
        Sensor noise of the blurred frames (:func:`photo_video`; 0: none, as the noise-free
        videos the network must deblur without denoising).
    roll_deg, zoom : float
        The camera's turn about its optical axis and magnification per sub-frame
        (:func:`photo_video`; default none: pans only).
    exposure_subframes : int, optional
        Sub-frames averaged into each frame (:func:`photo_video`; default 9, all of them).

    Returns
    -------
    list of (blurred, sharp)
        uint8 (frames, 120, 160, 3) pairs, as :func:`blurloc.train.video.load_video_splits`
        gives them.

    Raises
    ------
    ValueError
        If ``count`` or ``frames`` is not positive or no photograph is given.
    """
    if frames < 1:
        raise ValueError(f"frames must be positive, got {frames}")
    return [photo_video(photo, frames, step_px=step, angle_deg=angle, noise_sigma=noise_sigma,
                        seed=noise_seed, roll_deg=roll_deg, zoom=zoom,
                        exposure_subframes=exposure_subframes)
            for photo, step, angle, noise_seed in _training_pans(count, seed, photos)]  # fmt: skip


def photo_training_lines(
    count: int, seed: int = 0, photos: tuple[str, ...] = PHOTO_TRAINING_PHOTOS
) -> list[tuple[float, float]]:
    r"""The line blur of each video :func:`photo_training_videos` makes with the same
    ``count``, ``seed`` and ``photos``: its pan over :func:`photo_video`'s 9 sub-frames.

    .. math::

        L = 9\, s, \qquad \theta = (-\alpha) \bmod 180°

    with :math:`s` the pan per sub-frame and :math:`\alpha` its direction in the image's
    coordinates (rows downwards), so that :math:`\theta` follows the conventions of
    :mod:`blurloc.blur.estimation` (counter-clockwise, rows upwards). The pan's wobble (up to
    about 0.3 px per sub-frame) is left out: on slow pans (0.25-0.5 px per sub-frame) a frame's
    true blur can turn tens of degrees away from this line; on fast ones it stays close.

    Parameters
    ----------
    count : int
        Number of videos.
    seed : int
        Seed of :func:`photo_training_videos`.
    photos : tuple of str
        scikit-image photograph names.

    Returns
    -------
    list of (length_px, angle_deg)

    Raises
    ------
    ValueError
        If ``count`` is not positive or no photograph is given.
    """
    return [(9.0 * step, (-angle) % 180.0) for _, step, angle, _ in
            _training_pans(count, seed, photos)]  # fmt: skip


def _training_pans(
    count: int, seed: int, photos: tuple[str, ...]
) -> list[tuple[np.ndarray, float, float, int]]:
    """(photograph, pan per sub-frame, direction in degrees, noise seed) of each photo
    training video: a random crop, quarter turn and mirror, speed and direction."""
    if count < 1 or not photos:
        raise ValueError(f"count must be positive ({count}) and photos given")
    rng = np.random.default_rng(seed)
    pans = []
    for index in range(count):
        photo = as_float_image(getattr(skimage.data, photos[index % len(photos)])())
        if photo.ndim == 2:
            photo = np.repeat(photo[..., None], 3, axis=2)
        height, width = (int(side * rng.uniform(0.7, 1.0)) for side in photo.shape[:2])
        top = rng.integers(0, photo.shape[0] - height + 1)
        left = rng.integers(0, photo.shape[1] - width + 1)
        photo = np.rot90(photo[top : top + height, left : left + width, :3], rng.integers(4))
        if rng.random() < 0.5:
            photo = photo[:, ::-1]
        pans.append((np.ascontiguousarray(photo), float(rng.uniform(0.25, 1.75)),
                     float(rng.uniform(0.0, 360.0)), int(rng.integers(2**31))))  # fmt: skip
    return pans


def add_photo_videos(
    splits: dict[str, list[tuple[np.ndarray, np.ndarray]]],
    count: int,
    frames: int = PHOTO_TRAINING_FRAMES,
    noise_sigmas: tuple[float, ...] = (0.01,),
) -> dict[str, list[tuple[np.ndarray, np.ndarray]]]:
    """Training and validation videos with photo training videos appended.

    For each of ``noise_sigmas`` (index i), ``count`` videos of :func:`photo_training_videos`
    (seed 2i) with that noise join the training videos and half as many (at least one; seed
    2i + 1: other crops and motions of the same photographs) the validation videos. The trainer
    draws every training video equally often, so ``count`` sets the share of clips cut from
    photographs: 14 beside the default stand-in's 28 training sequences make a third. Every
    call adds the same videos (fixed seeds), whatever the training seed.

    Parameters
    ----------
    splits : dict
        ``train`` and ``validation`` lists of (blurred, sharp) uint8 videos, as
        :func:`blurloc.train.video.load_video_splits` gives them.
    count : int
        Photo videos to add for training per noise level (0: ``splits`` unchanged).
    frames : int
        Frames per photo video.
    noise_sigmas : tuple of float
        Sensor noise of the videos, one set of videos per value (0: none).

    Returns
    -------
    dict
        ``splits`` itself when ``count`` is 0; else a new dict with the two lists extended and
        the other keys kept.

    Raises
    ------
    ValueError
        If ``count`` is negative, ``noise_sigmas`` is empty or holds a negative value.
    """
    if count < 0:
        raise ValueError(f"count must be >= 0, got {count}")
    if not noise_sigmas or min(noise_sigmas) < 0:
        raise ValueError(f"noise_sigmas must be one or more values >= 0, got {noise_sigmas}")
    if count == 0:
        return splits
    train, validation = list(splits["train"]), list(splits["validation"])
    for index, sigma in enumerate(noise_sigmas):
        train += photo_training_videos(count, frames, seed=2 * index, noise_sigma=sigma)
        validation += photo_training_videos(max(1, count // 2), frames, seed=2 * index + 1,
                                            noise_sigma=sigma)  # fmt: skip
    return {**splits, "train": train, "validation": validation}
