"""How much of the stand-in's blur a linear filter can undo: one filter learned for all frames,
and one fitted to each frame's own blur (an oracle that reads the sharp render).

    python benchmarks/linear_deblur_bounds.py --root data/standin-noise0 [--size 9]
        [--frames 100] [--every 5] [--out-dir figures]

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
the blurred input on those pixels; printed and written to ``<out-dir>/linear_deblur_bounds.md``/
``.csv``: the mean, median and 10th-90th percentiles.
"""

from __future__ import annotations

import argparse
from collections.abc import Iterable

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from blurloc.data import SequenceFrames, list_scenes, load_split
from blurloc.metrics import psnr
from blurloc.tables import add_out_dir_argument, save_benchmark_tables


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
    """PSNR (:func:`blurloc.metrics.psnr`, data range 1) of the three channels' pixels, as
    :func:`interior` lists them."""
    return psnr(truth.reshape(3, -1), estimate.reshape(3, -1), 1.0)


def fit_global_filter(pairs: Iterable[tuple[np.ndarray, np.ndarray]], size: int) -> np.ndarray:
    """The least-squares ``size`` x ``size`` filter (plus offset) that maps every blurred frame
    of ``pairs`` ((blurred, sharp) frames in [0, 1]) to its sharp frame."""
    normal, moment = 0.0, 0.0  # the normal equations
    for blurred, sharp in pairs:
        rows = neighbourhoods(blurred, size)
        normal = normal + rows.T @ rows
        moment = moment + rows.T @ interior(sharp, size)
    return np.linalg.solve(normal, moment)


def filter_gains(
    pairs: Iterable[tuple[np.ndarray, np.ndarray]], global_filter: np.ndarray, size: int
) -> dict[str, list[float]]:
    """PSNR gains (dB) over the blurred input on the bottom half of each (blurred, sharp) frame
    in [0, 1]: of ``global_filter``, and of a filter fitted to the frame's own top half (the
    oracle). Frames equal to their sharp frame there are left out (an infinite PSNR)."""
    gains: dict[str, list[float]] = {"global": [], "per frame": []}
    for blurred, sharp in pairs:
        rows, truth = neighbourhoods(blurred, size), interior(sharp, size)
        height = blurred.shape[0] - 2 * (size // 2)
        width = blurred.shape[1] - 2 * (size // 2)
        top = np.tile(np.repeat(np.arange(height), width), 3) < height // 2
        centre = interior(blurred, size)
        if np.array_equal(centre[~top], truth[~top]):
            continue
        before = psnr_db(centre[~top], truth[~top])
        own_filter, *_ = np.linalg.lstsq(rows[top], truth[top], rcond=None)
        for name, weights in (("global", global_filter), ("per frame", own_filter)):
            gains[name].append(psnr_db(rows[~top] @ weights, truth[~top]) - before)
    return gains


def print_gains(gains: dict[str, list[float]]) -> list[dict]:
    """Print and return the mean, median and 10th-90th percentiles of each filter's gains."""
    rows = []
    for name, values in gains.items():
        low, middle, high = np.percentile(values, [10, 50, 90])
        print(f"  {name:9s} mean {np.mean(values):+.2f} dB, median {middle:+.2f}, "
              f"10th-90th percentile {low:+.2f} to {high:+.2f}")  # fmt: skip
        rows.append(
            {
                "filter": name,
                "frames": len(values),
                "mean_gain_db": round(float(np.mean(values)), 3),
                "median_gain_db": round(float(middle), 3),
                "p10_db": round(float(low), 3),
                "p90_db": round(float(high), 3),
            }
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", required=True, help="a stand-in (best rendered with --noise 0)")
    parser.add_argument("--size", type=int, default=9, help="filter size, px (odd)")
    parser.add_argument("--frames", type=int, default=100, help="test frames per sequence")
    parser.add_argument("--every", type=int, default=5, help="score every n-th of them")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    scenes = list_scenes(args.root)
    training = (pair for scene in scenes for sequence in load_split(args.root, scene, "train")
                for pair in frame_pairs(sequence.first(170), every=10))  # fmt: skip
    global_filter = fit_global_filter(training, args.size)
    test = (pair for scene in scenes for sequence in load_split(args.root, scene, "test")
            for pair in frame_pairs(sequence.first(args.frames), every=args.every))  # fmt: skip
    gains = filter_gains(test, global_filter, args.size)
    print(f"{args.root}: {args.size} x {args.size} linear filters, bottom halves of "
          f"{len(gains['global'])} test frames; PSNR gain over the blurred input:")  # fmt: skip
    saved = save_benchmark_tables(
        "linear_deblur_bounds",
        {"gains": print_gains(gains)},
        args.out_dir,
        f"Linear deblurring bounds on {args.root}: {args.size} x {args.size} filters",
        notes="PSNR gain (dB) over the blurred input on the bottom halves of the test frames.",
    )
    print(f"wrote {saved.markdown}")


def frame_pairs(sequence: SequenceFrames, every: int) -> Iterable[tuple[np.ndarray, np.ndarray]]:
    """Every ``every``-th (blurred, sharp) frame of ``sequence``, in [0, 1]."""
    return zip(sequence.images()[::every] / 255, sequence.images("sharp")[::every] / 255,
               strict=True)  # fmt: skip


if __name__ == "__main__":
    main()
