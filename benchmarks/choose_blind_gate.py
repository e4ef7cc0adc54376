"""Choose the gate of blind Wiener deblurring on one set of frames, report it on others.

    python benchmarks/choose_blind_gate.py --standin /tmp/standin-quick [ROOT ...] [--out figures]

Blind deblurring (:func:`blurloc.deconv.deblur_blind`) passes a frame through unchanged where
its restoration is not expected to gain (:func:`blurloc.deconv.blind_restoration_expected_to_gain`:
sinc-fit confidence, anisotropy of the spectrum's fall-off, noise σ). This script measures, for
every frame of three sets, the gate's inputs and the PSNR change that blind Wiener deconvolution
(eq. 4) would bring:

- fit set: scikit-image photographs (astronaut, coffee, chelsea, rocket, camera,
  immunohistochemistry, hubble_deep_field, cat) at 160x120 and 640x480, each blurred by
  camera-shake kernels (:func:`blurloc.blur.shake_path`, extents 0-22 px at 640x480, half at
  160x120) with Gaussian noise σ 0.002, 0.01 and 0.02, rounded to 8 bits;
- held-out photographs: other bundled photographs (coins, moon, page, retina, gravel, brick,
  text) the same way with another seed, half with line kernels instead of shake kernels;
- the stand-in: every ``*.color.png`` under each ``--standin`` root with its ``*.sharp.png``
  (``blurloc synth --quick --out DIR`` makes one; ``--width 640 --height 480`` a full-size one).

It picks the thresholds on the fit set alone (a grid; the largest mean change over all frames,
counting passed-through frames as 0 dB, among rules whose median change over restored frames is
above 0 and that restore at least 5 frames) and prints them beside the ones the package ships,
then reports, per set, the mean change and the median over restored frames of the shipped gate
and of the ungated rule (every frame the detector calls blurred is restored). Writes
``<out>/blind_wiener_gate.md`` and ``.csv``.
"""

from __future__ import annotations

import argparse
import datetime
import itertools
import sys
from pathlib import Path

import cv2
import numpy as np
import skimage.data

from blurloc.blur import (
    BLUR_THRESHOLD,
    blur_features,
    blur_image,
    estimate_motion_blur,
    estimate_noise_sigma,
    length_from_features,
    motion_kernel,
    shake_path,
    trajectory_kernel,
)
from blurloc.config import write_rows
from blurloc.deconv import GATE_MAX_NOISE, GATE_MIN_ANISOTROPY, GATE_MIN_FIT, wiener_deconvolve
from blurloc.files import atomic_path
from blurloc.metrics import psnr

FIT_PHOTOS = ("astronaut", "coffee", "chelsea", "rocket", "camera", "immunohistochemistry",
              "hubble_deep_field", "cat")  # fmt: skip
#: Not "clock": that photograph is itself motion-blurred (scikit-image's description says so),
#: so it has no sharp reference to score a restoration against.
HELD_OUT_PHOTOS = ("coins", "moon", "page", "retina", "gravel", "brick", "text")
EXTENTS_PX = (0, 2, 4, 8, 14, 22)  # at 640x480; halved at 160x120
NOISE_SIGMAS = (0.002, 0.01, 0.02)
GRID = {"fit": (0.0, 0.5, 0.6, 0.7, 0.8, 0.9), "anisotropy": (0.0, 0.25, 0.5, 0.75, 1.0),
        "noise": (0.005, 0.01, 0.02, 0.04)}  # fmt: skip


def measure(blurred: np.ndarray, sharp: np.ndarray) -> dict:
    """The gate's inputs for one uint8 frame and the PSNR change (dB) of restoring it."""
    features = blur_features(blurred)
    length = length_from_features(features)
    estimate = estimate_motion_blur(blurred, features=features)
    detected = length > BLUR_THRESHOLD
    gain = 0.0
    if detected:
        restored = wiener_deconvolve(blurred, estimate.kernel())
        gain = psnr(sharp, restored, 255.0) - psnr(sharp, blurred, 255.0)
    return {"detected": detected, "fit": estimate.fit, "anisotropy": features.anisotropy,
            "noise": estimate_noise_sigma(blurred), "gain_db": gain}  # fmt: skip


def photo_set(photos: tuple[str, ...], seed: int, lines: bool) -> list[dict]:
    """Rows of :func:`measure` for blurred photographs (see the module docstring)."""
    rng = np.random.default_rng(seed)
    rows = []
    for name in photos:
        photo = getattr(skimage.data, name)()
        photo = np.dstack([photo] * 3) if photo.ndim == 2 else photo[..., :3]
        for width, height in ((160, 120), (640, 480)):
            sharp = cv2.resize(photo, (width, height), interpolation=cv2.INTER_AREA)
            for index, (extent, noise) in enumerate(itertools.product(EXTENTS_PX, NOISE_SIGMAS)):
                extent *= width / 640 * 2 if width < 640 else 1
                if extent == 0:
                    kernel = np.ones((1, 1))
                elif lines and index % 2:
                    kernel = motion_kernel(extent, float(rng.uniform(0, 180)))
                else:
                    kernel = trajectory_kernel(shake_path(extent, rng))
                blurred = blur_image(sharp, kernel, noise, rng=rng)
                blurred = np.round(np.clip(blurred, 0, 1) * 255).astype(np.uint8)
                rows.append({"photo": name, "width": width, **measure(blurred, sharp)})
    return rows


def standin_set(root: Path) -> list[dict]:
    """Rows of :func:`measure` for every stand-in frame with a sharp render."""
    rows = []
    for path in sorted(root.glob("*/seq-*/frame-*.color.png")):
        sharp = cv2.imread(str(path).replace(".color.png", ".sharp.png"))
        if sharp is not None:
            rows.append(measure(cv2.imread(str(path)), sharp))  # BGR both: PSNR is the same
    if not rows:
        raise SystemExit(f"{root}: no stand-in frames with sharp renders")
    return rows


def outcome(rows: list[dict], fit: float, anisotropy: float, noise: float) -> dict:
    """Mean change over all frames (passed-through frames: 0 dB), restored count, median
    change over restored frames, under a gate with these thresholds."""
    touched = np.array([r["detected"] and r["fit"] >= fit and r["anisotropy"] >= anisotropy
                        and r["noise"] <= noise for r in rows])  # fmt: skip
    gains = np.array([r["gain_db"] for r in rows])
    return {"frames": len(rows), "restored": int(touched.sum()),
            "mean_change_db": round(float(np.where(touched, gains, 0.0).mean()), 3),
            "median_restored_db": round(float(np.median(gains[touched])), 3)
            if touched.any() else float("nan"),
            "restored_with_gain": int((gains[touched] > 0).sum())}  # fmt: skip


def choose(rows: list[dict]) -> tuple[float, float, float]:
    """The grid's thresholds with the largest mean change on ``rows`` (median over restored
    frames above 0, at least 5 restored)."""
    best, best_mean = None, -np.inf
    for thresholds in itertools.product(GRID["fit"], GRID["anisotropy"], GRID["noise"]):
        result = outcome(rows, *thresholds)
        if result["restored"] >= 5 and result["median_restored_db"] > 0:
            if result["mean_change_db"] > best_mean:
                best, best_mean = thresholds, result["mean_change_db"]
    if best is None:
        raise SystemExit("no rule of the grid restores frames with a median gain")
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--standin", type=Path, nargs="+", required=True)
    parser.add_argument("--out", default="figures")
    args = parser.parse_args()
    sets = {"fit: photographs, shake kernels": photo_set(FIT_PHOTOS, 1, lines=False),
            "held-out photographs, shake and line kernels": photo_set(HELD_OUT_PHOTOS, 2, True),
            **{f"stand-in ({root})": standin_set(root) for root in args.standin}}  # fmt: skip
    chosen = choose(next(iter(sets.values())))
    shipped = (GATE_MIN_FIT, GATE_MIN_ANISOTROPY, GATE_MAX_NOISE)
    print(f"chosen on the fit set: fit >= {chosen[0]}, anisotropy >= {chosen[1]}, noise <= "
          f"{chosen[2]}; shipped: {shipped}")  # fmt: skip
    rows = []
    for name, frames in sets.items():
        for rule, thresholds in (("gated (shipped)", shipped), ("ungated", (-1.0, -1.0, 1.0))):
            rows.append({"set": name, "rule": rule, **outcome(frames, *thresholds)})
            print(rows[-1])
    command = "python " + " ".join([Path(sys.argv[0]).as_posix(), *sys.argv[1:]])
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = Path(args.out)
    write_rows([{**row, "command": command, "date": date} for row in rows],
               out / "blind_wiener_gate.csv")  # fmt: skip
    columns = ("set", "rule", "frames", "restored", "mean_change_db", "median_restored_db",
               "restored_with_gain")  # fmt: skip
    lines = [
        "# Blind Wiener deblurring with and without its gate: PSNR change against the blurred "
        "frame",
        "",
        f"Command: `{command}` ({date}). Gate chosen on the first set only: sinc fit >= "
        f"{shipped[0]}, anisotropy >= {shipped[1]}, noise sigma <= {shipped[2]} (the grid's "
        f"choice: {chosen}). Mean change over all frames, passed-through frames counting 0 dB; "
        "median over the frames restored.",
        "",
        "| " + " | ".join(columns) + " |",
        "| " + " | ".join("---" for _ in columns) + " |",
        *("| " + " | ".join(str(row[c]) for c in columns) + " |" for row in rows),
        "",
    ]
    with atomic_path(out / "blind_wiener_gate.md") as temporary:
        temporary.write_text("\n".join(lines))


if __name__ == "__main__":
    main()
