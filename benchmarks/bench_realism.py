"""How the stand-in's frames differ from real camera frames, before (the stand-in's first look)
and after (painted rooms and the camera model, the defaults): image statistics side by side.

    python benchmarks/bench_realism.py [--frames-per-scene 12] [--seed 0]
                                       [--out-dir figures]

The stand-in's frames are rendered here, before and after from the same poses: the first
``--frames-per-scene`` frames spread over each scene's first test sequence, through the camera
model that ``blurloc synth`` stores them through (:func:`blurloc.data.camera_model.capture`).
A third set renders the after look with the exposure of the real Kinect (one frame interval,
``blur_strength`` 1, where the stand-in stretches it to 2.2), to show how much of what still
differs is the stand-in's stronger motion blur.

Every image is turned gray and area-averaged to 160x120 (the stand-in's size; centre-cropped to
4:3 first), then measured:

- the slope of the radially averaged power spectrum (log power against log frequency, least
  squares over 0.05-0.4 cycles/px; natural images have about -2, a sharper or noisier image a
  shallower slope);
- the variance of the Laplacian ([0, 1] intensities): edges against flat regions;
- the share of flat pixels (gradient magnitude under 0.02 per px) and of edge pixels (over 0.1);
- the noise sigma in the darker and in the brighter half of each image's pixels (split at its
  median): Immerkær's estimate (as :func:`blurloc.blur.estimate_noise_sigma`) over each half,
  whose ratio shows whether the noise grows with brightness as a camera's shot noise does;
- the mean brightness ([0, 1] gray, gamma-encoded).

Real sets: the TUM RGB-D frames of the development set (``samples/real``, Kinect) and the
sharp photographs (scikit-image's). Each statistic is the median over a set with its 25th-75th
percentiles. Writes ``OUT.md`` and ``OUT.csv`` (with the command, the date and the render time
per frame of each look) and ``OUT.png``/``.pdf``: the statistics side by side and example frames
(real, before, after).
"""

from __future__ import annotations

import argparse
import itertools
import time

import cv2
import numpy as np

from blurloc.blur import to_gray
from blurloc.data import read_image
from blurloc.data.camera_model import capture
from blurloc.data.real import load_photographs, posed_root, verify
from blurloc.data.scenes import SCENE_NAMES
from blurloc.data.synth import SynthConfig, render_exposure, sequence_trajectory, split_sequences
from blurloc.geometry import intrinsics
from blurloc.plots import plot_realism, save_figure
from blurloc.tables import add_out_dir_argument, save_benchmark_tables

SIZE = (160, 120)
STATISTICS = (
    "spectral slope",
    "variance of Laplacian",
    "flat share",
    "edge share",
    "noise sigma, dark half",
    "noise sigma, bright half",
    "mean brightness",
)
REAL = "real Kinect frames (TUM fr1_rpy)"


def at_standin_size(image: np.ndarray) -> np.ndarray:
    """Gray float32 in [0, 1], centre-cropped to 4:3 and area-averaged to 160x120."""
    gray = to_gray(image).astype(np.float32)  # [0, 1]
    height, width = gray.shape
    if width * 3 > height * 4:
        keep = height * 4 // 3
        gray = gray[:, (width - keep) // 2 : (width - keep) // 2 + keep]
    else:
        keep = width * 3 // 4
        gray = gray[(height - keep) // 2 : (height - keep) // 2 + keep]
    return cv2.resize(gray, SIZE, interpolation=cv2.INTER_AREA)


def spectral_slope(gray: np.ndarray) -> float:
    """Least-squares slope of log radial power against log frequency, 0.05-0.4 cycles/px."""
    window = np.outer(np.hanning(gray.shape[0]), np.hanning(gray.shape[1]))
    power = np.abs(np.fft.fftshift(np.fft.fft2((gray - gray.mean()) * window))) ** 2
    fy = np.fft.fftshift(np.fft.fftfreq(gray.shape[0]))[:, None]
    fx = np.fft.fftshift(np.fft.fftfreq(gray.shape[1]))[None, :]
    radius = np.hypot(fx, fy)
    edges = np.geomspace(0.05, 0.4, 13)
    centres, means = [], []
    for low, high in itertools.pairwise(edges):
        ring = (radius >= low) & (radius < high)
        centres.append(np.sqrt(low * high))
        means.append(power[ring].mean())
    return float(np.polyfit(np.log(centres), np.log(np.asarray(means) + 1e-20), 1)[0])


_IMMERKAER = np.float32([[1, -2, 1], [-2, 4, -2], [1, -2, 1]])


def noise_by_brightness(gray: np.ndarray) -> tuple[float, float]:
    """Immerkær's noise sigma, sqrt(pi / 2) / 6 times the mean absolute response to a kernel that
    cancels smooth structure, over the darker and over the brighter half of the pixels."""
    response = np.abs(cv2.filter2D(gray, cv2.CV_32F, _IMMERKAER))[1:-1, 1:-1]
    inner = gray[1:-1, 1:-1]
    dark = inner <= np.median(inner)
    scale = np.sqrt(np.pi / 2) / 6
    return float(scale * response[dark].mean()), float(scale * response[~dark].mean())


def statistics(image: np.ndarray) -> list[float]:
    """The STATISTICS of one image, in order."""
    gray = at_standin_size(image)
    dx, dy = cv2.Sobel(gray, cv2.CV_32F, 1, 0) / 8, cv2.Sobel(gray, cv2.CV_32F, 0, 1) / 8
    gradient = np.hypot(dx, dy)
    return [
        spectral_slope(gray),
        float(cv2.Laplacian(gray, cv2.CV_32F).var()),
        float((gradient < 0.02).mean()),
        float((gradient > 0.1).mean()),
        *noise_by_brightness(gray),
        float(gray.mean()),
    ]


def render_looks(
    looks: dict[str, SynthConfig], frames_per_scene: int, seed: int
) -> dict[str, tuple[list, list, float]]:
    """Per look: its captured (blurred) and sharp frames (uint8 RGB) and its render time per
    frame in seconds (exposure and camera model). The looks take turns frame by frame, so that
    other work on the machine slows them alike."""
    blurred = {label: [] for label in looks}
    sharp = {label: [] for label in looks}
    seconds = dict.fromkeys(looks, 0.0)
    for scene_name in SCENE_NAMES:
        paths = {}
        for label, config in looks.items():
            sequence = split_sequences(scene_name, config)[1][0]
            paths[label] = (*sequence_trajectory(scene_name, sequence, config, seed),
                            np.random.default_rng([seed, sequence]))  # fmt: skip
        count = next(iter(looks.values())).frames_for(scene_name)
        for frame in np.linspace(0, count - 1, frames_per_scene).round():
            for label, config in looks.items():
                scene, trajectory, rng = paths[label]
                camera = intrinsics(config.width, config.height)
                start = time.perf_counter()
                linear, middle, _, _ = render_exposure(
                    scene, trajectory, frame / config.fps, config, camera
                )
                color, sharp_frame = capture(linear, middle, config, rng)
                seconds[label] += time.perf_counter() - start
                blurred[label].append(color)
                sharp[label].append(sharp_frame)
    return {label: (blurred[label], sharp[label], seconds[label] / len(blurred[label]))
            for label in looks}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames-per-scene", type=int, default=12,
                        help="stand-in frames per scene and look")  # fmt: skip
    parser.add_argument("--seed", type=int, default=0, help="seed of the trajectories and noise")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    verify()
    looks = {
        "before": SynthConfig.previous_look(),
        "after": SynthConfig(),
        "after, blur strength 1": SynthConfig(blur_strength=1.0),
    }
    sets = {
        REAL: [read_image(path) for path in sorted(posed_root().glob("*/seq-*/frame-*.color.png"))]
    }
    render_looks(looks, 1, args.seed)  # textures and atlases made before any render is timed
    seconds = {}
    for label, (blurred, sharp, seconds[label]) in render_looks(
        looks, args.frames_per_scene, args.seed
    ).items():
        sets[f"{label}: blurred"] = blurred
        if label != "after, blur strength 1":
            sets[f"{label}: sharp"] = sharp
    sets["real sharp photographs"] = list(load_photographs("sharp").values())
    summary: dict[str, dict[str, tuple[float, float, float]]] = {name: {} for name in STATISTICS}
    for label, images in sets.items():
        values = np.array([statistics(image) for image in images])
        low, median, high = np.percentile(values, [25, 50, 75], axis=0)
        for name, a, b, c in zip(STATISTICS, low, median, high, strict=True):
            summary[name][label] = (float(a), float(b), float(c))
        print(label, len(images), [f"{v:.4g}" for v in median])
    table = [{"statistic": name} | {f"{label} (n = {len(sets[label])})":
             f"{b:.4g} ({a:.4g} to {c:.4g})" for label, (a, b, c) in summary[name].items()}
             for name in STATISTICS]  # fmt: skip
    ratio = seconds["after"] / seconds["before"]
    notes = (
        "Gray, centre-cropped to 4:3, area-averaged to 160x120; median (25th to 75th "
        "percentile) over each set. Before: the stand-in's first look (`blurloc synth "
        "--previous-look`); after: the defaults (painted rooms, camera model); both from the "
        "same poses. Render time per frame (exposure and camera model, one process): before "
        f"{seconds['before'] * 1000:.0f} ms, after {seconds['after'] * 1000:.0f} ms "
        f"({ratio:.2f}x)."
    )
    save_benchmark_tables(
        "bench_realism",
        {"statistics": table},
        args.out_dir,
        "The stand-in's frames beside real camera frames (at 160x120), before and after",
        notes=notes,
    )
    examples = {
        "real": sets[REAL][:: max(1, len(sets[REAL]) // 6)][:6],
        "before": sets["before: blurred"][:: args.frames_per_scene][:6],
        "after": sets["after: blurred"][:: args.frames_per_scene][:6],
    }
    save_figure(plot_realism(summary, examples), args.out_dir, "bench_realism")
    print(f"wrote {args.out_dir}/bench_realism.md, .csv, .png and .pdf")


if __name__ == "__main__":
    main()
