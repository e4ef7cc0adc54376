"""How much of the stand-in's blur a linear filter can undo: one filter learned for all frames,
and one fitted to each frame's own blur (an oracle that reads the sharp render).

    python benchmarks/linear_deblur_bounds.py --root data/standin-noise0 [--size 9]
        [--frames 100] [--every 5]

For a stand-in rendered without sensor noise (``blurloc synth --noise 0``, see
``train_without_noise.py``) the blurred frames differ from their sharp renders by the blur
alone. Two least-squares ``--size`` x ``--size`` filters (one for the three colour channels,
plus an offset) map a blurred frame to its sharp render:

- ``global``: one filter for every frame, fitted on every tenth of the first 170 frames of
  every training sequence: what a learner that cannot tell one frame's blur from another's
  gains (sharpening in general).
- ``per frame``: a filter fitted on the top half of each test frame against its sharp render
  and scored on the bottom half: what knowing the frame's own blur is worth to a linear filter
  (an oracle: a blind method has to find that blur in the frame itself). The blur of a moving
  camera varies across the frame, so the half it is scored on is not exactly the half it was
  fitted on.

Both are scored on the bottom half of every ``--every``-th of the first ``--frames`` frames of
every test sequence (frames equal to their sharp render are left out), as the PSNR gain over
the blurred input on those pixels; printed: the mean, median and 10th-90th percentiles.
"""

from __future__ import annotations

import argparse

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from blurloc.data import list_scenes, load_split


def neighbourhoods(frame: np.ndarray, size: int) -> np.ndarray:
    """Every ``size`` x ``size`` neighbourhood of each channel of an (H, W, 3) frame in [0, 1],
    one row per interior pixel and channel (channel by channel, rows top to bottom), with a
    trailing 1 for the offset."""
    rows = np.concatenate([sliding_window_view(frame[..., channel], (size, size))
                           .reshape(-1, size * size) for channel in range(3)])  # fmt: skip
    return np.hstack([rows, np.ones((len(rows), 1))])


def interior(frame: np.ndarray, size: int) -> np.ndarray:
    """The pixels :func:`neighbourhoods` is centred on, in its order."""
    margin = size // 2
    return np.concatenate([frame[margin:-margin, margin:-margin, channel].reshape(-1)
                           for channel in range(3)])  # fmt: skip


def psnr_db(estimate: np.ndarray, truth: np.ndarray) -> float:
    """PSNR (data range 1) of two arrays of pixels."""
    return float(10 * np.log10(1 / np.mean((estimate - truth) ** 2)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="a stand-in (best rendered with --noise 0)")
    parser.add_argument("--size", type=int, default=9, help="filter size, px (odd)")
    parser.add_argument("--frames", type=int, default=100, help="test frames per sequence")
    parser.add_argument("--every", type=int, default=5, help="score every n-th of them")
    args = parser.parse_args()
    scenes = list_scenes(args.root)

    normal, moment = 0.0, 0.0  # the global filter's normal equations
    for scene in scenes:
        for sequence in load_split(args.root, scene, "train"):
            part = sequence.first(170)
            pairs = zip(part.images()[::10] / 255, part.images("sharp")[::10] / 255, strict=True)
            for blurred, sharp in pairs:
                rows = neighbourhoods(blurred, args.size)
                normal = normal + rows.T @ rows
                moment = moment + rows.T @ interior(sharp, args.size)
    global_filter = np.linalg.solve(normal, moment)

    gains: dict[str, list[float]] = {"global": [], "per frame": []}
    for scene in scenes:
        for sequence in load_split(args.root, scene, "test"):
            part = sequence.first(args.frames)
            pairs = zip(part.images()[:: args.every] / 255,
                        part.images("sharp")[:: args.every] / 255, strict=True)  # fmt: skip
            for blurred, sharp in pairs:
                rows, truth = neighbourhoods(blurred, args.size), interior(sharp, args.size)
                height = blurred.shape[0] - 2 * (args.size // 2)
                width = blurred.shape[1] - 2 * (args.size // 2)
                top = np.tile(np.repeat(np.arange(height), width), 3) < height // 2
                centre = interior(blurred, args.size)
                if np.array_equal(centre[~top], truth[~top]):
                    continue  # no blur: an infinite PSNR
                before = psnr_db(centre[~top], truth[~top])
                own_filter, *_ = np.linalg.lstsq(rows[top], truth[top], rcond=None)
                for name, weights in (("global", global_filter), ("per frame", own_filter)):
                    gains[name].append(psnr_db(rows[~top] @ weights, truth[~top]) - before)
    print(f"{args.root}: {args.size} x {args.size} linear filters, bottom halves of "
          f"{len(gains['global'])} test frames; PSNR gain over the blurred input:")  # fmt: skip
    for name, values in gains.items():
        low, middle, high = np.percentile(values, [10, 50, 90])
        print(f"  {name:9s} mean {np.mean(values):+.2f} dB, median {middle:+.2f}, "
              f"10th-90th percentile {low:+.2f} to {high:+.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
