"""Where Wiener deconvolution loses: on camera frames, oracle runs that swap one ingredient at a
time (the kernel, the intensity space, the NSR) for the truth, the fit of the NSR rule, and the
per-scene comparison with the paper's Fig. 6-7; on photographs with true kernels, the comparison
with scikit-image's Wiener filter, with and without the best NSR per image."""

from __future__ import annotations

import json
import os
from collections.abc import Iterable
from dataclasses import fields
from pathlib import Path

import numpy as np
from scipy.optimize import minimize_scalar
from scipy.stats import linregress
from skimage.restoration import unsupervised_wiener, wiener
from tqdm.auto import tqdm

from ..blur import blur_image, estimate_noise_sigma, motion_kernel, shake_path, trajectory_kernel
from ..data.samples import split_frames
from ..data.sevenscenes import read_depth, read_image
from ..data.stats import read_blur_metadata
from ..data.synth import STANDIN_MANIFEST, SynthConfig, exposure_tracks, sequence_trajectory
from ..deconv import blind_kernel, estimate_nsr, wiener_deconvolve
from ..geometry import intrinsics
from ..images import as_float_image, linear_to_srgb, srgb_to_linear
from ..metrics import psnr, ssim
from .deblurring import paper_fig6_7
from .rows import grouped_means, matching

#: Eq. 4's constant NSR with the mean put back: each channel of the restoration shifted so that
#: its mean is the blurred frame's (a constant NSR scales it by 1 / (1 + NSR)); an oracle run
#: that separates the mean from the NSR's shape over the other frequencies.
MEAN_KEPT = "constant, mean kept"
#: The runs, each (kernel, intensity space, NSR, regulariser): one ingredient changes between
#: neighbours. The regulariser is the NSR's dependence on frequency
#: (:func:`~blurloc.deconv.wiener_deconvolve`): constant, as eq. 4 is printed, constant with the
#: mean put back (MEAN_KEPT), or the gradient's.
VARIANTS = {
    "blind": ("estimated line", "gamma", "rule", "constant"),
    "line_rule": ("recorded line", "gamma", "rule", "constant"),
    "line_best": ("recorded line", "gamma", "best", "constant"),
    "path_rule": ("true path", "gamma", "rule", "constant"),
    "path_best": ("true path", "gamma", "best", "constant"),
    "path_linear_rule": ("true path", "linear", "rule", "constant"),
    "path_linear_best": ("true path", "linear", "best", "constant"),
    "path_best_mean_kept": ("true path", "gamma", "best", MEAN_KEPT),
    "path_best_gradient": ("true path", "gamma", "best", "gradient"),
    "line_best_gradient": ("recorded line", "gamma", "best", "gradient"),
    "blind_best_gradient": ("estimated line", "gamma", "best", "gradient"),
}


def best_nsr(
    blurred: np.ndarray,
    sharp: np.ndarray,
    kernel: np.ndarray,
    linear: bool = False,
    regulariser: str = "constant",
) -> tuple[float, float]:
    """The NSR of eq. 4 that gives the best PSNR against the truth (an oracle), searched in
    log10(NSR) from -5 to 0 by bounded scalar minimisation.

    Parameters
    ----------
    blurred, sharp : np.ndarray
        (H, W) or (H, W, 3) float images in [0, 1] (gamma-encoded).
    kernel : np.ndarray
        Blur kernel (sums to 1).
    linear : bool
        Deconvolve in linear light (undo gamma 2.2, deconvolve, re-apply).
    regulariser : str
        The NSR's dependence on frequency (:func:`~blurloc.deconv.wiener_deconvolve`).

    Returns
    -------
    tuple of float
        The best NSR and its PSNR (dB, data range 1).
    """

    def loss(log_nsr: float) -> float:
        restored = _restore(blurred, kernel, 10.0**log_nsr, linear, regulariser)
        return -psnr(sharp, restored, 1.0)

    found = minimize_scalar(loss, bounds=(-5.0, 0.0), method="bounded", options={"xatol": 0.05})
    return float(10.0**found.x), float(-found.fun)


def _restore(
    blurred: np.ndarray,
    kernel: np.ndarray,
    nsr: float | None,
    linear: bool,
    regulariser: str = "constant",
) -> np.ndarray:
    """Wiener (eq. 4) in gamma-encoded or linear intensities, clipped to [0, 1]; with MEAN_KEPT,
    eq. 4 with each channel shifted to the blurred frame's mean before clipping."""
    if regulariser == MEAN_KEPT:
        source = srgb_to_linear(blurred) if linear else blurred
        restored = wiener_deconvolve(source, kernel, nsr)
        restored = np.clip(restored + source.mean(axis=(0, 1)) - restored.mean(axis=(0, 1)), 0, 1)
        return linear_to_srgb(restored) if linear else restored
    if not linear:
        return np.clip(wiener_deconvolve(blurred, kernel, nsr, regulariser), 0.0, 1.0)
    light = srgb_to_linear(blurred)
    restored = wiener_deconvolve(light, kernel, nsr, regulariser)
    return linear_to_srgb(np.clip(restored, 0.0, 1.0))


def fit_nsr_rule(
    crops: Iterable[np.ndarray],
    lengths: Iterable[float],
    noise_sigmas: Iterable[float],
    seed: int = 0,
) -> tuple[float, float, list[dict]]:
    """Fit the NSR rule NSR = a * sigma^b of :func:`blurloc.deconv.estimate_nsr` on photographs.

    Every crop is blurred by a line kernel of each length at a random angle, noise of each sigma
    is added, and the PSNR-best NSR (:func:`best_nsr`) is found; log(best NSR) is regressed on
    log(sigma estimated from the blurred crop), as the rule sees it.

    Parameters
    ----------
    crops : iterable of np.ndarray
        Gray (H, W) float crops in [0, 1].
    lengths : iterable of float
        Blur lengths, px.
    noise_sigmas : iterable of float
        Gaussian noise sigmas on [0, 1] intensities.
    seed : int
        Seed of the angles and the noise.

    Returns
    -------
    tuple
        ``a`` (NSR_COEFFICIENT), ``b`` (NSR_EXPONENT) and one row per trial (length_px,
        noise_sigma, estimated_sigma, best_nsr, best_psnr_db, rule_psnr_db).
    """
    rng = np.random.default_rng(seed)
    rows = []
    for crop in crops:
        for length in lengths:
            for sigma in noise_sigmas:
                kernel = motion_kernel(length, rng.uniform(0, 180))
                blurred = blur_image(crop, kernel, sigma, rng=rng)
                nsr, value = best_nsr(blurred, crop, kernel)
                rule = psnr(crop, _restore(blurred, kernel, None, False), 1.0)
                rows.append({"length_px": float(length), "noise_sigma": float(sigma),
                             "estimated_sigma": estimate_noise_sigma(blurred), "best_nsr": nsr,
                             "best_psnr_db": value, "rule_psnr_db": rule})  # fmt: skip
    if len({r["noise_sigma"] for r in rows}) < 2:
        raise ValueError("the fit needs at least two noise levels")
    line = linregress(np.log([r["estimated_sigma"] for r in rows]),
                      np.log([r["best_nsr"] for r in rows]))  # fmt: skip
    return float(np.exp(line.intercept)), float(line.slope), rows


#: scikit-image ``wiener`` balances swept per trial by :func:`skimage_comparison`, half a decade
#: apart; wide enough that the best one lies inside the sweep, not at its end.
SKIMAGE_BALANCES = (1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0)
#: Kernel kinds of :func:`random_kernel`: the range (px) each kind's size is drawn from (a line's
#: length; the longer side of a camera-shake path's bounding box) and a description.
KERNEL_KINDS = {
    "line": ((7.0, 27.0), "line kernels"),
    "camera shake": ((11.0, 25.0), "camera-shake kernels (Boracchi-Foi paths)"),
}


def random_kernel(kind: str, rng: np.random.Generator) -> np.ndarray:
    """A random blur kernel of ``kind`` (:data:`KERNEL_KINDS`).

    Parameters
    ----------
    kind : str
        ``"line"``: a line of uniformly drawn length at a uniformly drawn angle
        (:func:`~blurloc.blur.motion_kernel`); ``"camera shake"``: a random hand-shake path of
        uniformly drawn extent (:func:`~blurloc.blur.shake_path`).
    rng : numpy.random.Generator
        Draws the size, the angle or the path.

    Returns
    -------
    numpy.ndarray
        The kernel (k, k), summing to 1.
    """
    if kind not in KERNEL_KINDS:
        raise ValueError(f"kind must be one of {sorted(KERNEL_KINDS)}, got {kind!r}")
    low, high = KERNEL_KINDS[kind][0]
    if kind == "line":
        return motion_kernel(rng.uniform(low, high), rng.uniform(0, 180))
    return trajectory_kernel(shake_path(rng.uniform(low, high), rng))


def _best_skimage(observed: np.ndarray, truth: np.ndarray, kernel: np.ndarray, pad: int) -> tuple:
    """PSNR (dB) and balance of scikit-image's ``wiener`` at its best balance; with ``pad`` > 0
    the image is mirror-padded by that many pixels first and cropped back (as this package's
    Wiener does), otherwise transformed as it is (periodic, scikit-image's own way)."""
    padded = np.pad(observed, pad, mode="reflect") if pad else observed
    inside = (slice(pad, pad + observed.shape[0]), slice(pad, pad + observed.shape[1]))
    scores = [psnr(truth, np.clip(wiener(padded, kernel, b, clip=False)[inside], 0, 1), 1.0)
              for b in SKIMAGE_BALANCES]  # fmt: skip
    best = int(np.argmax(scores))
    return scores[best], SKIMAGE_BALANCES[best]


def skimage_comparison(
    images: Iterable[np.ndarray],
    kinds: Iterable[str],
    kernels_per_image: int,
    rng: np.random.Generator,
    noise_sigma: float = 0.01,
    unsupervised: bool = False,
    oracle_nsr: bool = False,
) -> list[dict]:
    """This package's Wiener filter (eq. 4, NSR estimated from the image) against scikit-image's
    ``wiener`` at its best ``balance`` per trial (an oracle sweep over SKIMAGE_BALANCES), with
    the true kernel; scikit-image's filter both as it is (periodic DFT) and given the same
    mirror padding as this package's, so that the two differ in their regulariser only.

    Parameters
    ----------
    images : iterable of numpy.ndarray
        Sharp gray images, float in [0, 1].
    kinds : iterable of str
        Kernel kinds (:data:`KERNEL_KINDS`).
    kernels_per_image : int
        Random kernels of each kind per image (:func:`random_kernel`).
    rng : numpy.random.Generator
        Draws the kernels and the noise.
    noise_sigma : float
        Gaussian noise added after blurring ([0, 1] scale).
    unsupervised : bool
        Also score scikit-image's ``unsupervised_wiener`` (slower).
    oracle_nsr : bool
        Also score this package's Wiener at the PSNR-best constant NSR of each trial
        (:func:`best_nsr`, an oracle): whether the NSR rule or the constant NSR of eq. 4 costs.

    Returns
    -------
    list of dict
        One row per trial: ``image`` (index), ``kernel`` (kind), ``noise_sigma``, PSNR (dB, data
        range 1, restorations clipped to [0, 1]) of the blurred image, this package's Wiener and
        scikit-image's at its best balance, unpadded and mirror-padded (``blurred_db``,
        ``ours_db``, ``skimage_best_balance_db``, ``skimage_padded_db``), and the two best
        balances (``skimage_balance``, ``skimage_padded_balance``); with ``unsupervised`` also
        ``unsupervised_db``, with ``oracle_nsr`` also ``best_nsr_db`` and ``best_nsr``.
    """
    kinds = list(kinds)
    rows = []
    for index, image in enumerate(images):
        for kind in kinds:
            for _ in range(kernels_per_image):
                kernel = random_kernel(kind, rng)
                observed = blur_image(image, kernel, noise_sigma, rng=rng)
                periodic, balance = _best_skimage(observed, image, kernel, 0)
                padded, padded_balance = _best_skimage(observed, image, kernel,
                                                       max(kernel.shape) + 8)  # fmt: skip
                row = {
                    "image": index, "kernel": kind, "noise_sigma": noise_sigma,
                    "blurred_db": psnr(image, np.clip(observed, 0, 1), 1.0),
                    "ours_db": psnr(image, np.clip(wiener_deconvolve(observed, kernel), 0, 1), 1.0),
                    "skimage_best_balance_db": periodic, "skimage_padded_db": padded,
                    "skimage_balance": balance, "skimage_padded_balance": padded_balance,
                }  # fmt: skip
                if unsupervised:
                    restored = unsupervised_wiener(observed, kernel, clip=False,
                                                   rng=np.random.default_rng(0))[0]  # fmt: skip
                    row["unsupervised_db"] = psnr(image, np.clip(restored, 0, 1), 1.0)
                if oracle_nsr:
                    row["best_nsr"], row["best_nsr_db"] = best_nsr(observed, image, kernel)
                rows.append(row)
    return rows


def standin_settings(root: str | os.PathLike) -> tuple[SynthConfig, int]:
    """The settings and seed a stand-in root was rendered with (from its manifest)."""
    path = Path(root) / STANDIN_MANIFEST
    if not path.is_file():
        raise ValueError(f"{path}: missing; the oracle runs need a rendered stand-in")
    manifest = json.loads(path.read_text())
    if "config" not in manifest:
        raise ValueError(f"{path}: the stand-in is incomplete")
    settings = {k: v for k, v in manifest["config"].items()
                if k in {f.name for f in fields(SynthConfig)}}  # fmt: skip
    settings["sequence_counts"] = {k: tuple(v) for k, v in settings["sequence_counts"].items()}
    return SynthConfig(**settings), int(manifest["seed"])


def exposure_kernel(tracks: np.ndarray) -> np.ndarray:
    """The frame's true blur kernel, averaged over the image: the mean over points of each
    point's path kernel, centred on its mid-exposure position (so the mid-exposure sharp frame
    maps to the blurred one without a shift).

    Parameters
    ----------
    tracks : np.ndarray
        (samples, points, 2) image positions (px, x right, y down) of scene points over the
        exposure, e.g. :func:`blurloc.data.synth.exposure_tracks`; ``samples`` odd.

    Returns
    -------
    np.ndarray
        The kernel (odd square, sums to 1).
    """
    middle = tracks[tracks.shape[0] // 2]
    reach = np.abs(tracks - middle[None]).max()
    size = 2 * int(np.ceil(reach + 1)) + 1
    kernels = [trajectory_kernel(tracks[:, p], size, origin=middle[p])
               for p in range(tracks.shape[1])]  # fmt: skip
    return np.mean(kernels, axis=0)


def oracle_rows(
    root: str | os.PathLike,
    split: str = "test",
    budget: int | None = None,
    progress: bool = False,
) -> list[dict]:
    """Wiener deconvolution of a stand-in split's frames in each of VARIANTS, scored against the
    sharp mid-exposure render.

    Parameters
    ----------
    root : str or os.PathLike
        The stand-in root (with its manifest, ``blur.csv``, sharp renders and depth).
    split : str
        Split to measure on.
    budget : int or None
        About how many frames of the split to read, spread evenly
        (:func:`~blurloc.data.samples.split_frames`); None reads every frame.
    progress : bool
        Show a progress bar.

    Returns
    -------
    list of dict
        One row per frame and variant (plus ``blurred``): scene, sequence, frame, extent_px,
        variant, kernel, space, nsr_source, regulariser, nsr, psnr_db, ssim.
    """
    config, seed = standin_settings(root)
    records = {(r["scene"], r["sequence"], r["frame"]): r for r in read_blur_metadata(root)}
    camera = intrinsics(config.width, config.height)
    jobs = split_frames(root, split, budget)
    rows, paths = [], {}
    for scene, sequence, frame in tqdm(jobs, disable=not progress, desc=f"oracles {split}"):
        if (scene, sequence.number) not in paths:
            paths[(scene, sequence.number)] = sequence_trajectory(scene, sequence.number,
                                                                  config, seed)  # fmt: skip
        world, trajectory = paths[(scene, sequence.number)]
        record = records[(scene, sequence.number, frame)]
        blurred = as_float_image(read_image(sequence.path(frame, "color")))
        sharp = as_float_image(read_image(sequence.path(frame, "sharp")))
        tracks = exposure_tracks(world, trajectory, frame / config.fps, config, camera,
                                 read_depth(sequence.path(frame, "depth")), samples=17)  # fmt: skip
        kernels = {"estimated line": blind_kernel(blurred),
                   "recorded line": motion_kernel(max(record["mean_px"], 0.1),
                                                  record["angle_deg"]),
                   "true path": exposure_kernel(tracks)}  # fmt: skip
        base = {"scene": scene, "sequence": sequence.number, "frame": frame,
                "extent_px": record["mean_px"]}  # fmt: skip
        rows.append({**base, "variant": "blurred", "kernel": "none", "space": "gamma",
                     "nsr_source": "none", "regulariser": "none", "nsr": 0.0,
                     "psnr_db": psnr(sharp, blurred, 1.0),
                     "ssim": ssim(sharp, blurred, 1.0)})  # fmt: skip
        for name, (kernel_name, space, source, regulariser) in VARIANTS.items():
            kernel, linear = kernels[kernel_name], space == "linear"
            if kernel is None:  # judged sharp: passed through
                nsr, restored = 0.0, blurred
            elif source == "best":
                nsr = best_nsr(blurred, sharp, kernel, linear, regulariser)[0]
                restored = _restore(blurred, kernel, nsr, linear, regulariser)
            else:
                nsr = estimate_nsr(srgb_to_linear(blurred) if linear else blurred)
                restored = _restore(blurred, kernel, nsr, linear)
            rows.append({**base, "variant": name, "kernel": kernel_name, "space": space,
                         "nsr_source": source, "regulariser": regulariser, "nsr": nsr,
                         "psnr_db": psnr(sharp, restored, 1.0),
                         "ssim": ssim(sharp, restored, 1.0)})  # fmt: skip
    return rows


def oracle_summary(rows: list[dict]) -> list[dict]:
    """Per variant of :func:`oracle_rows`: frames, mean PSNR and SSIM, and the mean paired
    PSNR change (dB) against the blurred input, with its 95 % interval (t, over frames)."""
    from scipy.stats import t as student

    table = []
    for variant in ["blurred", *VARIANTS]:
        subset = matching(rows, {"variant": variant})
        gains = frame_gains(rows, variant)[1]
        half = (student.ppf(0.975, len(gains) - 1) * gains.std(ddof=1) / np.sqrt(len(gains))
                if len(gains) > 1 else float("nan"))  # fmt: skip
        first = subset[0]
        table.append({"variant": variant, "kernel": first["kernel"], "space": first["space"],
                      "nsr": first["nsr_source"], "regulariser": first["regulariser"],
                      "frames": len(subset),
                      "psnr_db": round(float(np.mean([r["psnr_db"] for r in subset])), 2),
                      "ssim": round(float(np.mean([r["ssim"] for r in subset])), 4),
                      "gain_db": round(float(gains.mean()), 2),
                      "gain_ci95_db": round(float(half), 2)})  # fmt: skip
    return table


def frame_gains(rows: list[dict], variant: str) -> tuple[np.ndarray, np.ndarray]:
    """Per frame of :func:`oracle_rows`: the recorded blur extent and the PSNR change of one
    variant against the blurred input (paired on scene, sequence and frame).

    Parameters
    ----------
    rows : list of dict
        :func:`oracle_rows`, with the ``blurred`` rows.
    variant : str
        A key of VARIANTS.

    Returns
    -------
    extent_px : numpy.ndarray
        (N,) the mean blur extent recorded in blur.csv, pixels.
    gain_db : numpy.ndarray
        (N,) PSNR (eq. 6) of the variant minus that of the blurred input, dB.
    """
    blurred = {(r["scene"], r["sequence"], r["frame"]): r["psnr_db"] for r in rows
               if r["variant"] == "blurred"}  # fmt: skip
    subset = [r for r in rows if r["variant"] == variant]
    extent = np.array([r["extent_px"] for r in subset], float)
    gain = np.array([r["psnr_db"] - blurred[(r["scene"], r["sequence"], r["frame"])]
                     for r in subset], float)  # fmt: skip
    return extent, gain


def gain_by_extent(
    rows: list[dict], variant: str = "path_linear_best", threshold_px: float = 4.0
) -> tuple[float, float]:
    """Mean PSNR change of one variant against the blurred input, on frames with large and with
    small recorded blur.

    Parameters
    ----------
    rows : list of dict
        :func:`oracle_rows`, with the ``blurred`` rows.
    variant : str
        A key of VARIANTS (default: every ingredient true).
    threshold_px : float
        Frames with a recorded extent >= this (pixels) are large, the others small.

    Returns
    -------
    large, small : float
        Mean PSNR changes, dB (nan where no frame falls on that side).
    """
    extent, gain = frame_gains(rows, variant)
    large = extent >= threshold_px
    return (float(gain[large].mean()) if large.any() else float("nan"),
            float(gain[~large].mean()) if (~large).any() else float("nan"))  # fmt: skip


def oracle_scene_table(rows: list[dict]) -> list[dict]:
    """Per scene (and their mean): PSNR and SSIM of the blurred input, blind Wiener and the
    oracle-kernel Wiener (true path, linear light, best NSR), beside the paper's Fig. 6-7
    values (labelled ``paper_``; printed numbers, not measured here)."""
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    table = []
    for scene in [*scenes, "mean"]:
        row = {"scene": scene}
        for variant, label in (("blurred", "blurred"), ("blind", "blind_wiener"),
                               ("path_linear_best", "oracle_wiener")):  # fmt: skip
            for metric in ("psnr_db", "ssim"):
                means = grouped_means(rows, "scene", metric, {"variant": variant})
                per_scene = [means[s] for s in (scenes if scene == "mean" else [scene])]
                row[f"{label}_{metric}"] = round(float(np.mean(per_scene)), 4)
        table.append({**row, **paper_fig6_7(scene)})
    return table
