"""Is the stand-in's camera blur restorable? The blur model b = c * x and the gains of
deconvolution and linear oracles, per frame, on renders that differ in one setting.

    python benchmarks/deblur_bounds.py --roots data/bounds-ss1 data/bounds-ss2 data/bounds-ss3
        [--lens-sigma 0.8] [--frames 30] [--every 3] [--out-dir figures]

Each ``--roots`` entry is a stand-in rendered without noise (``blurloc synth --shot-noise 0
--read-noise 0 --optics-blur 0``, or ``--previous-look --noise 0``) with the same seed, scenes and
size, so that frame i of every root has the same pose and blur and the roots differ in one setting
(e.g. ``--supersample``). The first root is also scored with a Gaussian lens blur of
``--lens-sigma`` px applied in linear light to its blurred AND sharp frames after rendering (so
that the same renders serve). A reference where b = c * x holds by
construction: the photo-video photographs at 160x120, each blurred with a 9 px line PSF in
linear light and quantised to 8 bits.

Per frame (every ``--every``-th of the first ``--frames`` of each test sequence), scored on the
tiles' pixels less an 8 px border (``blurloc.experiments.restoration_bounds``):
the blurred frame's PSNR, the forward consistency PSNR(b, c * x) with each 40 px tile's true PSF
and with each tile's best-fitting 13 x 13 kernel (a ceiling on any per-tile PSF),
the gain of Wiener deconvolution with those PSFs in linear light at the best of a few NSRs
(an oracle), and the gain of the per-frame 9 x 9
least-squares oracle of ``linear_deblur_bounds.py`` (fitted on the frame's top half against its
sharp frame, scored on the bottom half). Every setting is compared with the first root by the
paired per-frame difference and its 95 % bootstrap interval. Writes ``<out-dir>/deblur_bounds.md``
and ``.csv``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np
import skimage.data
from linear_deblur_bounds import filter_gains

from blurloc.blur.kernels import motion_kernel
from blurloc.data import list_scenes, load_split
from blurloc.experiments.photo_video import PHOTO_VIDEO_PHOTOS
from blurloc.experiments.restoration_bounds import (
    TileKernel,
    blur_linear,
    lens_blur,
    restoration_bounds,
    standin_tile_kernels,
)
from blurloc.intervals import paired_interval
from blurloc.tables import add_out_dir_argument, save_benchmark_tables

ORACLE_SIZE = 9
MEASURES = ("blurred_psnr", "forward_psnr", "best_forward_psnr", "wiener_gain", "oracle_gain")


def oracle_gain(blurred: np.ndarray, sharp: np.ndarray) -> float:
    """The per-frame least-squares oracle's gain (dB) on the frame's bottom half."""
    identity = np.zeros(ORACLE_SIZE * ORACLE_SIZE + 1)  # the unused global filter: no change
    identity[ORACLE_SIZE * ORACLE_SIZE // 2] = 1.0
    gains = filter_gains([(blurred, sharp)], identity, ORACLE_SIZE)["per frame"]
    return gains[0] if gains else float("nan")


def frame_scores(blurred: np.ndarray, sharp: np.ndarray, tiles: list[TileKernel]) -> dict:
    """Every measure of one (blurred, sharp) pair in [0, 1]."""
    return {**restoration_bounds(blurred, sharp, tiles), "oracle_gain": oracle_gain(blurred, sharp)}


def standin_scores(root: str, frames: int, every: int, lens_sigma: float = 0.0) -> list[dict]:
    """Scores of every scored test frame of a stand-in root, in a fixed order."""
    rows = []
    for scene in list_scenes(root):
        for sequence in load_split(root, scene, "test"):
            for frame in range(0, min(frames, len(sequence)), every):
                stem = Path(sequence.folder) / f"frame-{frame:06d}"
                blurred = cv2.imread(f"{stem}.color.png")[..., ::-1] / 255.0
                sharp = cv2.imread(f"{stem}.sharp.png")[..., ::-1] / 255.0
                if lens_sigma:
                    blurred, sharp = lens_blur(blurred, lens_sigma), lens_blur(sharp, lens_sigma)
                tiles = standin_tile_kernels(root, scene, sequence.number, frame)
                rows.append(frame_scores(blurred, sharp, tiles))
    return rows


def photo_scores(length_px: float = 9.0) -> list[dict]:
    """Scores of the photo-video photographs, line-blurred at 0, 45 and 90 degrees."""
    rows = []
    for name in PHOTO_VIDEO_PHOTOS:
        photo = getattr(skimage.data, name)()
        photo = np.dstack([photo] * 3) if photo.ndim == 2 else photo[..., :3]
        sharp = np.round(cv2.resize(photo, (160, 120), interpolation=cv2.INTER_AREA)) / 255.0
        for angle in (0.0, 45.0, 90.0):
            kernel = motion_kernel(length_px, angle)
            blurred = np.round(blur_linear(sharp, kernel) * 255) / 255.0
            tiles = [TileKernel(0, 120, 0, 160, kernel)]
            rows.append(frame_scores(blurred, sharp, tiles))
    return rows


def summary_row(name: str, scores: list[dict], baseline: list[dict] | None) -> dict:
    """Mean of each measure; with a baseline of the same frames, the paired difference of the
    oracle and Wiener gains and their 95 % intervals."""
    row = {"setting": name, "frames": len(scores)}
    for measure in MEASURES:
        row[measure] = f"{np.nanmean([s[measure] for s in scores]):+.2f}"
    if baseline is not None:
        for measure in ("forward_psnr", "best_forward_psnr", "wiener_gain", "oracle_gain"):
            diff = np.array([s[measure] - b[measure] for s, b in zip(scores, baseline,
                                                                        strict=True)])  # fmt: skip
            interval = paired_interval(diff[np.isfinite(diff)])
            low, high = interval.low, interval.high
            row[f"{measure} - first"] = f"{interval.mean:+.2f} [{low:+.2f}, {high:+.2f}]"
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--roots", nargs="+", required=True, help="noise-free stand-ins")
    parser.add_argument("--lens-sigma", type=float, default=0.8, help="Gaussian lens blur, px")
    parser.add_argument("--frames", type=int, default=30, help="test frames per sequence")
    parser.add_argument("--every", type=int, default=3, help="score every n-th of them")
    add_out_dir_argument(parser)
    args = parser.parse_args()
    first = standin_scores(args.roots[0], args.frames, args.every)
    rows = [summary_row(args.roots[0], first, None)]
    for root in args.roots[1:]:
        rows.append(summary_row(root, standin_scores(root, args.frames, args.every), first))
    lensed = standin_scores(args.roots[0], args.frames, args.every, args.lens_sigma)
    rows.append(summary_row(f"{args.roots[0]} + lens {args.lens_sigma} px", lensed, first))
    rows.append(summary_row("photographs, 9 px line PSF", photo_scores(), None))
    compared = ("forward_psnr", "best_forward_psnr", "wiener_gain", "oracle_gain")
    columns = ["setting", "frames", *MEASURES, *(f"{m} - first" for m in compared)]
    saved = save_benchmark_tables(
        "deblur_bounds",
        {"settings": [{column: row.get(column, "") for column in columns} for row in rows]},
        args.out_dir,
        "Restorability of camera blur",
        notes="dB; differences: setting minus the first root, paired per frame, mean [95 % "
        "bootstrap interval].",
    )
    print(saved.markdown.read_text())


if __name__ == "__main__":
    main()
