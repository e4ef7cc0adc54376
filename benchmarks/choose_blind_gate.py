"""Choose the gate of blind Wiener deblurring on one set of frames, report it on others.

    blurloc synth --quick --seed 5 --out data/gate-fit-160 --workers 1
    blurloc synth --quick --width 640 --height 480 --seed 5 --out data/gate-fit-640 --workers 1
    blurloc synth --quick --seed 6 --out data/gate-rep-160-s6 --workers 1
    blurloc synth --quick --width 640 --height 480 --seed 6 --out data/gate-rep-640-s6 --workers 1
    blurloc synth --quick --width 640 --height 480 --seed 7 --out data/gate-rep-640-s7 --workers 1
    python benchmarks/choose_blind_gate.py --fit-standin data/gate-fit-640 data/gate-fit-160 \\
        --standin data/gate-rep-640-s6 data/gate-rep-640-s7 data/gate-rep-160-s6 [--out-dir figures]

(each 640x480 render takes about 4 minutes on one core, the 160x120 ones seconds; the script
itself about 5 minutes).

Blind deblurring (:func:`blurloc.deconv.deblur_blind`) passes a frame through unchanged where
its restoration is not expected to gain
(:func:`blurloc.deconv.blind_restoration_expected_to_gain`: sinc-fit confidence, anisotropy of
the spectrum's fall-off, blur length at the analysis scale against the noise, the sinc-refined
length against the coarse one). This script measures, for every frame of its sets, the gate's
inputs and the PSNR change that blind Wiener deconvolution would bring, by eq. 4 with its
constant NSR rule and with the gradient regulariser (:func:`blurloc.deconv.wiener_deconvolve`)
at weights WEIGHTS_PER_NOISE times the frame's noise sigma:

- fit set: scikit-image photographs (astronaut, coffee, chelsea, rocket, camera,
  immunohistochemistry, hubble_deep_field, cat) at 160x120 and 640x480, blurred the way a camera
  blurs (:func:`camera_blur`: sub-frames along a camera-shake path, extents 0-44 px at 640x480
  and half at 160x120, turned about the image centre, averaged in linear light) without noise
  (but for extent 0, the sharp frame itself) and with Gaussian noise σ 0.002, 0.01 and 0.02 on
  the encoded intensities, rounded to 8 bits, against the mid-exposure sub-frame;
- held-out photographs: the other bundled photographs (coins, moon, page, retina, gravel, brick,
  text) the same way with another seed, half along straight paths instead of shake paths;
- fit stand-ins: every ``*.color.png`` under each ``--fit-standin`` root with its
  ``*.sharp.png`` (renders in the default look), added to the fit set;
- report stand-ins: the same under each ``--standin`` root (renders of other seeds);
- real frames: the real blurred/sharp pair (:func:`blurloc.data.real.load_pairs`, scored), the
  real blurred photographs and the 80 posed TUM RGB-D frames (no reference: counted only).

It picks the restoration and the gate's thresholds on the fit sets alone, pooled (a grid; the
largest mean change over all frames, passed-through frames counting 0 dB, among rules whose
median change over restored frames is above 0 and that restore at least 5 frames; ties go to
the rule restoring fewer frames, then to the strictest), prints them beside the ones the package
ships, then reports, per set, the mean change with its 95 % bootstrap interval
(:func:`blurloc.intervals.paired_interval` over frames), the median over restored frames and the
counts, for the shipped gate, the grid's choice (where it differs) and the ungated rule (every
frame the detector calls blurred is restored; by eq. 4 and by the chosen restoration). Writes
``<out-dir>/choose_blind_gate.md`` and ``.csv``.
"""

from __future__ import annotations

import argparse
import itertools
from pathlib import Path

import cv2
import numpy as np
import skimage.data

from blurloc.blur import (
    BLUR_THRESHOLD,
    analysis_length,
    blur_features,
    estimate_motion_blur,
    estimate_noise_sigma,
    shake_path,
)
from blurloc.data.real import load_pairs, load_photographs, posed_root
from blurloc.deconv import (
    BLIND_REGULARISER,
    GATE_MAX_AGREEMENT,
    GATE_MAX_LENGTH,
    GATE_MIN_ANISOTROPY,
    GATE_MIN_FIT,
    GATE_MIN_LENGTH,
    GATE_NOISE_EXPONENT,
    GATE_REFERENCE_NOISE,
    GRADIENT_WEIGHT_PER_NOISE,
    wiener_deconvolve,
)
from blurloc.images import srgb_to_linear, to_uint8
from blurloc.intervals import paired_interval
from blurloc.metrics import psnr
from blurloc.tables import add_out_dir_argument, save_benchmark_tables

FIT_PHOTOS = ("astronaut", "coffee", "chelsea", "rocket", "camera", "immunohistochemistry",
              "hubble_deep_field", "cat")  # fmt: skip
#: Not "clock": that photograph is itself motion-blurred (scikit-image's description says so),
#: so it has no sharp reference to score a restoration against.
HELD_OUT_PHOTOS = ("coins", "moon", "page", "retina", "gravel", "brick", "text")
EXTENTS_PX = (0, 2, 4, 8, 14, 22, 32, 44)  # at 640x480; halved at 160x120
NOISE_SIGMAS = (0.0, 0.002, 0.01, 0.02)
#: Largest turn of the camera about its axis over the exposure, as a share of the extent: the
#: image corners move by up to half the extent more (or less) than the centre.
ROLL_SHARE = 0.5
GRID = {"fit": (0.0, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95),
        "anisotropy": (0.0, 0.25, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0),
        "min_length": (0.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 10.0, 12.0),
        "noise_exponent": (0.0, 0.25, 0.5, 0.75, 1.0),
        "max_length": (10.0, 12.0, 15.0, 20.0, np.inf),
        "max_agreement": (1.1, 1.2, 1.3, 1.4, 1.5, 1.7, np.inf)}  # fmt: skip
UNGATED = (-np.inf, -np.inf, 0.0, 0.0, np.inf, np.inf)


def camera_blur(
    sharp: np.ndarray, path: np.ndarray, roll_rad: float, noise: float, rng: np.random.Generator
) -> np.ndarray:
    """A photograph blurred as a camera blurs it: the mean, in linear light, of sub-frames
    shifted along ``path`` and turned by up to ``roll_rad`` about the centre, then encoded with
    noise on the encoded intensities and rounded to 8 bits. The middle sub-frame is ``sharp``."""
    linear = srgb_to_linear(sharp.astype(np.float32) / 255.0)
    extent = float(np.ptp(path, axis=0).max())
    steps = 2 * int(np.ceil(extent)) + 1  # odd, so that the middle sub-frame is unmoved
    points = path[np.linspace(0, len(path) - 1, steps).round().astype(int)]
    height, width = sharp.shape[:2]
    total = np.zeros_like(linear)
    for step, point in enumerate(points):
        turn = roll_rad * (step / max(steps - 1, 1) - 0.5)
        matrix = cv2.getRotationMatrix2D((width / 2, height / 2), float(np.degrees(turn)), 1.0)
        matrix[:, 2] += point - points[steps // 2]
        total += cv2.warpAffine(linear, matrix, (width, height), flags=cv2.INTER_LINEAR,
                                borderMode=cv2.BORDER_REFLECT)  # fmt: skip
    return to_uint8(total / steps, rng.normal(0.0, noise, linear.shape))


def regulariser_label(weight_per_noise: float | None) -> str:
    """Name of a restoration rule: eq. 4's constant NSR (None) or the gradient regulariser with
    weight ``weight_per_noise`` * sigma."""
    if weight_per_noise is None:
        return "constant NSR (eq. 4)"
    return f"gradient, weight {weight_per_noise:g} sigma"


#: The restorations measured on every frame: eq. 4 with its NSR rule, and Wiener with the
#: gradient regulariser at weights WEIGHTS_PER_NOISE * the frame's noise sigma.
WEIGHTS_PER_NOISE = (1.0, 2.0, 5.0, 10.0, 20.0, 40.0)
REGULARISER_RULES = (None, *WEIGHTS_PER_NOISE)


def restore(blurred: np.ndarray, kernel: np.ndarray, weight_per_noise: float | None,
            noise: float) -> np.ndarray:  # fmt: skip
    """Wiener deconvolution of a uint8 frame by one of REGULARISER_RULES."""
    if weight_per_noise is None:
        return wiener_deconvolve(blurred, kernel)
    return wiener_deconvolve(blurred, kernel, max(weight_per_noise * noise, 1e-6), "gradient")


def measure(blurred: np.ndarray, sharp: np.ndarray | None) -> dict:
    """The gate's inputs for one uint8 frame and the PSNR change (dB) of restoring it by each of
    REGULARISER_RULES (``gains``: NaN without a sharp reference; 0 where the detector calls the
    frame sharp). ``agreement``: the estimate's length over the coarse length, both in the
    frame's pixels."""
    features = blur_features(blurred)
    length = analysis_length(features)
    estimate = estimate_motion_blur(blurred, features=features)
    noise = estimate_noise_sigma(blurred)
    detected = length > BLUR_THRESHOLD
    gains = {}
    for weight in REGULARISER_RULES:
        gain = 0.0 if sharp is not None else float("nan")
        if detected and sharp is not None:
            restored = restore(blurred, estimate.kernel(), weight, noise)
            gain = psnr(sharp, restored, 255.0) - psnr(sharp, blurred, 255.0)
        gains[weight] = gain
    agreement = estimate.length_px / max(length * features.scale, 1e-9)
    return {"detected": detected, "length": length, "fit": estimate.fit,
            "anisotropy": features.anisotropy, "noise": noise,
            "agreement": agreement, "gains": gains}  # fmt: skip


def photo_set(photos: tuple[str, ...], seed: int, lines: bool) -> list[dict]:
    """Rows of :func:`measure` for photographs blurred by :func:`camera_blur` (see the module
    docstring)."""
    rng = np.random.default_rng(seed)
    rows = []
    for name in photos:
        photo = getattr(skimage.data, name)()
        photo = np.dstack([photo] * 3) if photo.ndim == 2 else photo[..., :3]
        for width, height in ((160, 120), (640, 480)):
            sharp = cv2.resize(photo, (width, height), interpolation=cv2.INTER_AREA)
            for index, (extent, noise) in enumerate(itertools.product(EXTENTS_PX, NOISE_SIGMAS)):
                extent *= 0.5 if width < 640 else 1.0
                if extent == 0 and noise == 0:  # the sharp frame itself: no finite PSNR
                    continue
                if extent == 0:
                    path = np.zeros((1, 2))
                elif lines and index % 2:
                    angle = rng.uniform(0, np.pi)
                    path = np.outer(np.linspace(0, extent, 100), [np.cos(angle), np.sin(angle)])
                else:
                    path = shake_path(extent, rng)
                roll = rng.uniform(-ROLL_SHARE, ROLL_SHARE) * extent / (np.hypot(width, height) / 2)
                blurred = camera_blur(sharp, path, roll, noise, rng)
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


def real_sets() -> dict[str, list[dict]]:
    """Rows of :func:`measure` for the real frames: the blurred/sharp pairs (scored), the real
    blurred photographs and the posed TUM RGB-D frames (no reference)."""
    posed = sorted(posed_root().glob("*/seq-*/frame-*.color.png"))
    return {
        "real blurred/sharp pair (GoPro)": [measure(b, s) for _, b, s in load_pairs()],
        "real blurred photographs (no reference)":
            [measure(image, None) for image in load_photographs("blurred").values()],
        "real TUM RGB-D frames, fr1_rpy (no reference)":
            [measure(cv2.imread(str(path)), None) for path in posed],
    }  # fmt: skip


def touched(rows: list[dict], thresholds: tuple[float, ...]) -> np.ndarray:
    """Which frames a gate with ``thresholds`` (fit, anisotropy, min_length, noise_exponent,
    max_length, max_agreement) restores: the rule of
    :func:`blurloc.deconv.blind_restoration_expected_to_gain`."""
    fit, anisotropy, min_length, exponent, max_length, max_agreement = thresholds
    keys = ("detected", "fit", "anisotropy", "noise", "length", "agreement")
    column = {key: np.array([r[key] for r in rows], float) for key in keys}
    shortest = min_length * (column["noise"] / GATE_REFERENCE_NOISE) ** exponent
    return (
        (column["detected"] > 0) & (column["fit"] >= fit) & (column["anisotropy"] >= anisotropy)
        & (shortest <= column["length"]) & (column["length"] <= max_length)
        & (column["agreement"] <= max_agreement)
    )  # fmt: skip


#: Columns of the table: a set, a gate, a restoration and :func:`outcome`'s measures (empty
#: where it has none).
COLUMNS = ("set", "rule", "restoration", "frames", "restored", "mean_change_db",
           "interval_95_db", "median_restored_db", "restored_with_gain")  # fmt: skip


def outcome(rows: list[dict], thresholds: tuple[float, ...], weight: float | None,
            interval: bool = False) -> dict:  # fmt: skip
    """Counts, mean change over all frames (passed-through frames: 0 dB; with ``interval`` its
    95 % bootstrap interval) and median change over restored frames, under a gate, for the
    restoration ``weight`` (a key of REGULARISER_RULES)."""
    restored = touched(rows, thresholds)
    gains = np.array([r["gains"][weight] for r in rows])
    result = {"frames": len(rows), "restored": int(restored.sum())}
    if np.isnan(gains).any():  # no reference: the counts are all there is
        return result
    changes = np.where(restored, gains, 0.0)
    result["mean_change_db"] = round(float(changes.mean()), 3)
    if interval:
        if restored.any() and len(rows) > 1:
            bounds = paired_interval(changes)
            result["interval_95_db"] = f"[{bounds.low:+.3f}, {bounds.high:+.3f}]"
        else:
            result["interval_95_db"] = "none restored" if not restored.any() else ""
    if restored.any():
        result["median_restored_db"] = round(float(np.median(gains[restored])), 3)
        result["restored_with_gain"] = int((gains[restored] > 0).sum())
    return result


def choose(rows: list[dict]) -> tuple[float | None, tuple[float, ...]]:
    """The restoration (a key of REGULARISER_RULES) and the grid's thresholds with the largest
    mean change on ``rows`` (median over restored frames above 0, at least 5 restored); of rules
    within 0.001 dB of it, the one that restores the fewest frames, and of those the strictest
    (largest lower thresholds, then smallest maximum length): the fit set cannot tell them
    apart, and the stricter rule risks less on frames unlike it. Between restorations, ties go
    to eq. 4's constant NSR, then to the smaller weight."""
    gains = {weight: np.array([r["gains"][weight] for r in rows]) for weight in REGULARISER_RULES}
    candidates = []
    for thresholds in itertools.product(*GRID.values()):
        restored = touched(rows, thresholds)
        if restored.sum() < 5:
            continue
        strictness = (*thresholds[:4], -thresholds[4], -thresholds[5])
        for order, (weight, gain) in enumerate(gains.items()):
            if np.median(gain[restored]) > 0:
                mean = float(np.where(restored, gain, 0.0).mean())
                candidates.append((round(mean, 3), -int(restored.sum()), strictness, -order,
                                   weight, thresholds))  # fmt: skip
    if not candidates:
        raise SystemExit("no rule of the grid restores frames with a median gain")
    best = max(candidates, key=lambda candidate: candidate[:4])
    return best[4], best[5]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--standin",
        type=Path,
        nargs="+",
        required=True,
        help="stand-in renders to report on (never chosen on)",
    )
    parser.add_argument("--fit-standin", type=Path, nargs="*", default=[],
                        help="stand-in renders added to the fit set")  # fmt: skip
    add_out_dir_argument(parser)
    args = parser.parse_args()
    fit_sets = {
        "fit: photographs, shake paths": photo_set(FIT_PHOTOS, 1, lines=False),
        **{f"fit: stand-in {root.name}": standin_set(root) for root in args.fit_standin},
    }
    sets = {**fit_sets,
            "held-out photographs, shake and straight paths": photo_set(HELD_OUT_PHOTOS, 2, True),
            **{f"stand-in {root.name}": standin_set(root) for root in args.standin},
            **real_sets()}  # fmt: skip
    chosen_weight, chosen = choose([row for frames in fit_sets.values() for row in frames])
    shipped = (GATE_MIN_FIT, GATE_MIN_ANISOTROPY, GATE_MIN_LENGTH, GATE_NOISE_EXPONENT,
               GATE_MAX_LENGTH, GATE_MAX_AGREEMENT)  # fmt: skip
    shipped_weight = None if BLIND_REGULARISER == "constant" else GRADIENT_WEIGHT_PER_NOISE
    print(f"chosen on the fit sets (fit, anisotropy, min length, noise exponent, max length, "
          f"max agreement): {chosen}, {regulariser_label(chosen_weight)}; shipped: {shipped}, "
          f"{regulariser_label(shipped_weight)}")  # fmt: skip
    rules = [("gated (shipped)", shipped, shipped_weight),
             ("gated (chosen on the fit sets)", chosen, chosen_weight),
             ("ungated", UNGATED, None), ("ungated", UNGATED, chosen_weight)]  # fmt: skip
    rules = [rule for index, rule in enumerate(rules)  # each gate and restoration once
             if rule[1:] not in [earlier[1:] for earlier in rules[:index]]]  # fmt: skip
    rows = []
    for name, frames in sets.items():
        for rule, thresholds, weight in rules:
            found = {"set": name, "rule": rule, "restoration": regulariser_label(weight),
                     **outcome(frames, thresholds, weight, True)}  # fmt: skip
            rows.append({column: found.get(column, "") for column in COLUMNS})
            print(rows[-1])
    notes = (
        "PSNR change of blind Wiener deblurring against the sharp frame (dB), with and without "
        f"its gate. Gate and restoration chosen on the sets marked fit only ({len(fit_sets)} of "
        f"them). Shipped: sinc fit >= {shipped[0]}, anisotropy >= "
        f"{shipped[1]}, {shipped[2]} * (noise sigma / {GATE_REFERENCE_NOISE}) ** {shipped[3]} <= "
        f"blur length at the analysis scale <= {shipped[4]} px, sinc-refined length <= "
        f"{shipped[5]} * the coarse length, restoration {regulariser_label(shipped_weight)} "
        f"(the grid's choice: {chosen}, {regulariser_label(chosen_weight)}). Restorations: eq. 4 "
        "with its constant NSR rule, or Wiener with the gradient regulariser (NSR(f) = weight "
        "|D(f)|^2, weight = a multiple of the frame's noise sigma). "
        "Mean change over all frames, passed-through frames counting 0 dB, with its 95 % "
        "bootstrap interval over frames; median over the frames restored. Real frames without a "
        "reference: counts only."
    )
    save_benchmark_tables(
        "choose_blind_gate",
        {"outcomes": rows},
        args.out_dir,
        "Blind Wiener deblurring with and without its gate",
        notes=notes,
    )


if __name__ == "__main__":
    main()
