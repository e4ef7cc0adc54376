"""Measurements behind notebooks 01-03: blind-estimation accuracy on natural photographs,
per-frame PSNR/SSIM of single-image deblurring methods on a stand-in split, and how much of a
PSNR is sub-pixel misregistration."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable

import cv2
import numpy as np
import skimage.data
from scipy.optimize import minimize
from skimage.filters import window
from skimage.registration import phase_cross_correlation
from skimage.restoration import richardson_lucy, unsupervised_wiener, wiener
from tqdm.auto import tqdm

from .blur import blur_image, estimate_motion_blur, motion_kernel
from .data.render import srgb_to_linear
from .data.sevenscenes import list_scenes, load_split, read_image
from .data.synth import to_uint8
from .deconv import blind_kernel, wiener_deconvolve
from .images import as_float_image
from .metrics import psnr, ssim

#: scikit-image's bundled photographs used as natural test content (gray, [0, 1]).
PHOTOS = ("astronaut", "camera", "coffee", "chelsea", "rocket", "brick", "grass", "gravel",
          "immunohistochemistry", "hubble_deep_field", "coins", "moon", "clock", "retina",
          "cell")  # fmt: skip


def photo_crops(count: int, size: int = 256, seed: int = 0) -> list[np.ndarray]:
    """``count`` random ``size`` x ``size`` gray crops ([0, 1] float) of scikit-image's photos,
    cycling through PHOTOS."""
    rng = np.random.default_rng(seed)
    crops = []
    for index in range(count):
        photo = as_float_image(getattr(skimage.data, PHOTOS[index % len(PHOTOS)])())
        gray = photo.mean(axis=2) if photo.ndim == 3 else photo
        if min(gray.shape) < size:
            raise ValueError(f"photo {PHOTOS[index % len(PHOTOS)]} is smaller than {size} px")
        row = rng.integers(0, gray.shape[0] - size + 1)
        col = rng.integers(0, gray.shape[1] - size + 1)
        crops.append(gray[row : row + size, col : col + size])
    return crops


def angle_error_deg(a: float | np.ndarray, b: float | np.ndarray) -> np.ndarray:
    """Smallest difference between two line directions (degrees, modulo 180)."""
    difference = np.abs(np.asarray(a) - np.asarray(b)) % 180.0
    return np.minimum(difference, 180.0 - difference)


def estimation_trials(
    images: list[np.ndarray],
    lengths: Iterable[float],
    noise_sigmas: Iterable[float],
    seed: int = 0,
    progress: bool = False,
) -> list[dict]:
    """Blur every image by a linear kernel of each length at a random angle, add Gaussian noise
    of each sigma, estimate length and angle blindly. One row per trial: image, length_px,
    angle_deg, noise_sigma, estimated length and angle, their errors (px, degrees)."""
    rng = np.random.default_rng(seed)
    trials = [(i, float(L), float(s)) for i in range(len(images)) for L in lengths
              for s in noise_sigmas]  # fmt: skip
    rows = []
    for index, length, sigma in tqdm(trials, disable=not progress, desc="estimation"):
        angle = float(rng.uniform(0, 180))
        blurred = blur_image(images[index], motion_kernel(length, angle), sigma, rng=rng)
        estimate = estimate_motion_blur(blurred)
        rows.append({
            "image": index, "length_px": length, "angle_deg": angle, "noise_sigma": sigma,
            "estimated_length_px": estimate.length_px, "estimated_angle_deg": estimate.angle_deg,
            "length_error_px": abs(estimate.length_px - length),
            "angle_error_deg": float(angle_error_deg(estimate.angle_deg, angle)),
        })  # fmt: skip
    return rows


def _per_channel(restore: Callable[[np.ndarray], np.ndarray], image: np.ndarray) -> np.ndarray:
    return np.dstack([restore(image[..., c]) for c in range(image.shape[2])])


def deblurring_methods(
    skimage_balance: float, rl_iterations: int = 10, seed: int = 0
) -> dict[str, Callable[[np.ndarray, np.ndarray | None], np.ndarray]]:
    """Single-image methods compared in notebook 02, as functions (image, kernel) -> image on
    float [0, 1] RGB. ``kernel`` is the blind estimate (None when the detector found no blur,
    and then every method returns its input). ``blind_wiener`` is this package's eq. 4 with the
    NSR estimated from the noise; scikit-image's are fed the same kernel."""
    rng = np.random.default_rng(seed)

    def skip_if_sharp(method):
        def run(image: np.ndarray, kernel: np.ndarray | None) -> np.ndarray:
            return image if kernel is None else np.clip(method(image, kernel), 0.0, 1.0)

        return run

    return {
        "blurred": lambda image, kernel: image,
        "blind_wiener": skip_if_sharp(lambda im, k: wiener_deconvolve(im, k)),
        "skimage_wiener": skip_if_sharp(
            lambda im, k: _per_channel(lambda c: wiener(c, k, skimage_balance), im)
        ),
        "unsupervised_wiener": skip_if_sharp(
            lambda im, k: _per_channel(lambda c: unsupervised_wiener(c, k, rng=rng)[0], im)
        ),
        "richardson_lucy": skip_if_sharp(
            lambda im, k: _per_channel(lambda c: richardson_lucy(c, k, rl_iterations), im)
        ),
    }


def evaluate_deblurring(
    root: str | os.PathLike,
    split: str,
    methods: dict[str, Callable],
    every: int = 1,
    progress: bool = False,
) -> list[dict]:
    """PSNR and SSIM (data range 1) of each method's output against the stand-in's sharp
    mid-exposure render, for every ``every``-th frame of ``split``. One row per frame and
    method: scene, sequence, frame, method, psnr_db, ssim, blurred (detector verdict)."""
    frames = [(scene, sequence, frame) for scene in list_scenes(root)
              for sequence in load_split(root, scene, split)
              for frame in sequence.frame_ids[::every]]  # fmt: skip
    rows = []
    for scene, sequence, frame in tqdm(frames, disable=not progress, desc=f"deblur {split}"):
        blurred = as_float_image(read_image(sequence.path(frame, "color")))
        sharp = as_float_image(read_image(sequence.path(frame, "sharp")))
        kernel = blind_kernel(blurred)
        for name, method in methods.items():
            restored = method(blurred, kernel)
            rows.append({
                "scene": scene, "sequence": sequence.number, "frame": frame, "method": name,
                "psnr_db": psnr(sharp, restored, 1.0), "ssim": ssim(sharp, restored, 1.0),
                "blurred": kernel is not None,
            })  # fmt: skip
    return rows


def choose_skimage_balance(
    root: str | os.PathLike, candidates: Iterable[float], every: int = 1
) -> tuple[float, int]:
    """The ``balance`` of scikit-image's ``wiener`` with the best mean PSNR over every
    ``every``-th **training** frame that blind deblurring would touch (fed the same estimated
    kernel); returns it and the number of frames used."""
    candidates = list(candidates)
    scores: dict[float, list[float]] = {b: [] for b in candidates}
    for scene in list_scenes(root):
        for sequence in load_split(root, scene, "train"):
            for frame in sequence.frame_ids[::every]:
                observed = as_float_image(read_image(sequence.path(frame, "color")))
                kernel = blind_kernel(observed)
                if kernel is None:
                    continue
                truth = as_float_image(read_image(sequence.path(frame, "sharp")))
                for balance in candidates:
                    restored = _per_channel(
                        lambda c, b=balance, k=kernel: wiener(c, k, b), observed
                    )
                    scores[balance].append(psnr(truth, np.clip(restored, 0, 1), 1.0))
    used = len(scores[candidates[0]])
    if not used:
        raise ValueError(f"{root}: no blurred training frames to choose the balance on")
    return max(candidates, key=lambda b: float(np.mean(scores[b]))), used


def per_scene_means(rows: list[dict], metric: str) -> dict[str, dict[str, float]]:
    """{method: {scene: mean of ``metric``}} over per-frame rows (scenes in first-seen order),
    plus a ``mean`` entry per method: the mean of its per-scene means."""
    methods = list(dict.fromkeys(r["method"] for r in rows))
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    table = {}
    for method in methods:
        values = {scene: float(np.mean([r[metric] for r in rows
                                        if r["method"] == method and r["scene"] == scene]))
                  for scene in scenes}  # fmt: skip
        table[method] = {**values, "mean": float(np.mean(list(values.values())))}
    return table


def _shifted(image: np.ndarray, dx: float, dy: float) -> np.ndarray:
    matrix = np.float32([[1, 0, dx], [0, 1, dy]])
    return cv2.warpAffine(np.float32(image), matrix, image.shape[1::-1], flags=cv2.INTER_CUBIC,
                          borderMode=cv2.BORDER_REFLECT)  # fmt: skip


def registered_psnr(
    reference: np.ndarray, estimate: np.ndarray, border: int = 8
) -> tuple[float, float, float]:
    """How much of a PSNR loss is misregistration: the global sub-pixel shift of ``reference``
    that best matches ``estimate`` (a Hann-windowed phase correlation, 1/20 px, refined by
    minimising the squared error), and the PSNR before and after that shift. Returns (shift in
    px, PSNR, registered PSNR); both PSNRs skip a ``border`` of pixels."""
    reference, estimate = as_float_image(reference), as_float_image(estimate)
    if reference.shape != estimate.shape or min(reference.shape[:2]) <= 2 * border + 8:
        raise ValueError(f"images must share a shape larger than the border, got "
                         f"{reference.shape} and {estimate.shape}")  # fmt: skip
    gray = [x if x.ndim == 2 else x.mean(axis=2) for x in (reference, estimate)]
    hann = window("hann", gray[0].shape)
    (dy, dx), _, _ = phase_cross_correlation(gray[1] * hann, gray[0] * hann, upsample_factor=20)
    inner = (slice(border, -border), slice(border, -border))

    def error(shift: np.ndarray) -> float:
        moved = np.clip(_shifted(reference, *shift), 0.0, 1.0)
        return float(np.mean((moved[inner] - estimate[inner]) ** 2))

    best = minimize(error, [dx, dy], method="Nelder-Mead", options={"xatol": 0.01, "fatol": 1e-10})
    registered = np.clip(_shifted(reference, *best.x), 0.0, 1.0)
    return (float(np.hypot(*best.x)), psnr(reference[inner], estimate[inner], 1.0),
            psnr(registered[inner], estimate[inner], 1.0))  # fmt: skip


def photo_video(
    photo: np.ndarray,
    frames: int = 12,
    subframes: int = 9,
    step_px: float = 1.0,
    angle_deg: float = 0.0,
    size: tuple[int, int] = (160, 120),
    noise_sigma: float = 0.01,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """A blurred video made the GoPro way from a still photograph: a virtual high-frame-rate
    camera pans over ``photo`` (``step_px`` per sub-frame at output scale, along ``angle_deg``,
    with a small wobble); each stored frame is the mean of ``subframes`` consecutive sub-frames
    in linear light (gamma 2.2) plus noise, its sharp frame the middle sub-frame. Returns uint8
    (blurred, sharp), each (frames, height, width, 3)."""
    photo = as_float_image(photo)
    if photo.ndim != 3 or frames < 1 or subframes < 1:
        raise ValueError("photo must be RGB; frames and subframes must be positive")
    width, height = size
    scale = 2  # sub-frames are rendered at twice the output size, then area-averaged down
    linear = srgb_to_linear(cv2.resize(np.float32(photo), (3 * width * scale, 3 * height * scale),
                                       interpolation=cv2.INTER_AREA))  # fmt: skip
    direction = np.array([np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))])
    rng = np.random.default_rng(seed)
    blurred, sharp = [], []
    for frame in range(frames):
        views = []
        for sub in range(subframes):
            time = frame * subframes + sub
            wobble = 1.5 * np.array([np.sin(time / 7), np.cos(time / 5)])
            origin = (np.array([width, height]) + step_px * time * direction + wobble) * scale
            matrix = np.float32([[1, 0, -origin[0]], [0, 1, -origin[1]]])
            view = cv2.warpAffine(linear, matrix, (width * scale, height * scale),
                                  borderMode=cv2.BORDER_REFLECT)  # bilinear
            views.append(cv2.resize(view, size, interpolation=cv2.INTER_AREA))
        noise = rng.normal(0, noise_sigma, views[0].shape)
        blurred.append(to_uint8(np.mean(views, axis=0), noise))
        sharp.append(to_uint8(views[subframes // 2]))
    return np.stack(blurred), np.stack(sharp)
