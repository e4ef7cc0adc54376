"""How the stand-in's frames differ from real camera frames: image statistics side by side.

    python benchmarks/bench_realism.py [--standin data/standin] [--budget 200]
                                       [--out figures/bench_realism]

Every image is turned gray and area-averaged to 160x120 (the stand-in's size; centre-cropped to
4:3 first), then measured:

- the slope of the radially averaged power spectrum (log power against log frequency, least
  squares over 0.05-0.4 cycles/px; natural images have about -2, a sharper or noisier image a
  shallower slope);
- the variance of the Laplacian ([0, 1] intensities): edges against flat regions;
- the share of flat pixels (gradient magnitude under 0.02 per px) and of edge pixels (over 0.1);
- the noise sigma in the darker and in the brighter half of each image's pixels (split at its
  median): Immerkær's estimate (as :func:`blurloc.blur.estimate_noise_sigma`) over each half,
  whose ratio shows whether the noise grows with brightness as a camera's shot noise does.

Image sets: the stand-in's sharp renders and blurred frames (test split, about ``--budget`` of
each), the real TUM RGB-D frames of the development set (``samples/real``, Kinect), and the real
sharp photographs (scikit-image's). Each statistic is the median over a set with its 25th-75th
percentiles. Writes ``OUT.md`` and ``OUT.csv`` with the command and the date.
"""

from __future__ import annotations

import argparse
import datetime
import itertools
import sys
from pathlib import Path

import cv2
import numpy as np

from blurloc.blur import to_gray
from blurloc.config import write_rows
from blurloc.data import read_image
from blurloc.data.real import load_photographs, posed_root, verify
from blurloc.data.samples import split_frames
from blurloc.files import atomic_path

SIZE = (160, 120)
STATISTICS = (
    "spectral slope",
    "variance of Laplacian",
    "flat share",
    "edge share",
    "noise sigma, dark half",
    "noise sigma, bright half",
)


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
    ]


def image_sets(standin: Path, budget: int) -> dict[str, list[np.ndarray]]:
    """The images of each set, by the set's label."""
    frames = split_frames(standin, "test", budget)
    return {
        "stand-in sharp renders": [read_image(s.path(f, "sharp")) for _, s, f in frames],
        "stand-in blurred frames": [read_image(s.path(f, "color")) for _, s, f in frames],
        "real TUM RGB-D frames (Kinect)": [
            read_image(path) for path in sorted(posed_root().glob("*/seq-*/frame-*.color.png"))
        ],
        "real sharp photographs": list(load_photographs("sharp").values()),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--standin", default="data/standin", help="stand-in root")
    parser.add_argument("--budget", type=int, default=200, help="stand-in test frames to read")
    parser.add_argument("--out", default="figures/bench_realism", help="output path, no suffix")
    args = parser.parse_args()
    if not (Path(args.standin) / "standin.json").is_file():
        parser.error(f"--standin {args.standin}: no stand-in there (make one with blurloc synth)")
    verify()
    rows = []
    for label, images in image_sets(Path(args.standin), args.budget).items():
        values = np.array([statistics(image) for image in images])
        low, median, high = np.percentile(values, [25, 50, 75], axis=0)
        for name, a, b, c in zip(STATISTICS, low, median, high, strict=True):
            rows.append({"images": label, "n": len(images), "statistic": name,
                         "median": f"{b:.4g}", "25th-75th": f"{a:.4g} to {c:.4g}"})  # fmt: skip
        print(label, len(images), [f"{v:.4g}" for v in median])
    command = "python " + " ".join(sys.argv)
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_rows(rows, out.with_suffix(".csv"))
    lines = [
        "# The stand-in's frames beside real camera frames (at 160x120)",
        "",
        f"Command: `{command}`; {date}. Gray, centre-cropped to 4:3, area-averaged to 160x120.",
        "",
        "| statistic | " + " | ".join(dict.fromkeys(r["images"] for r in rows)) + " |",
        "|---|" + "---|" * len(dict.fromkeys(r["images"] for r in rows)),
    ]
    for name in STATISTICS:
        cells = [f"{r['median']} ({r['25th-75th']})" for r in rows if r["statistic"] == name]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    with atomic_path(out.with_suffix(".md")) as path:
        path.write_text("\n".join(lines) + "\n")
    print(f"wrote {out.with_suffix('.md')} and .csv")


if __name__ == "__main__":
    main()
