"""Single-image deblurring methods compared (notebook 02): the inverse filter against Wiener, the
NSR trade-off and the boundaries on one photograph; on a stand-in split, the methods, their
per-frame PSNR/SSIM, the balance of scikit-image's Wiener filter and per-scene means."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable

import numpy as np
from skimage.restoration import richardson_lucy, unsupervised_wiener, wiener
from tqdm.auto import tqdm

from ..blur import blur_image, kernel_to_otf
from ..data.samples import split_frames
from ..data.sevenscenes import read_image
from ..deconv import (
    blind_kernel,
    blind_nsr,
    deblur_blind,
    estimate_nsr,
    inverse_filter,
    wiener_deconvolve,
)
from ..images import as_float_image
from ..intervals import paired_interval
from ..metrics import psnr, ssim
from ..paper import paper_values
from .rows import grouped_means


def _interior_psnr(sharp: np.ndarray, image: np.ndarray, border: int) -> float:
    """PSNR (eq. 6, data range 1) of ``image`` clipped to [0, 1] against ``sharp``, leaving out
    ``border`` pixels on each side (0: the whole image)."""
    inside = (slice(border, sharp.shape[0] - border), slice(border, sharp.shape[1] - border))
    return psnr(sharp[inside], np.clip(image, 0.0, 1.0)[inside], 1.0)


def filter_comparison(
    sharp: np.ndarray,
    kernel: np.ndarray,
    noise_levels: Iterable[float],
    rng: np.random.Generator,
    border: int = 24,
) -> list[dict]:
    """Blur ``sharp`` at each noise level and restore it with the inverse filter and Wiener.

    Without noise Wiener gets NSR = 1e-6 (almost the inverse filter); with noise the NSR is
    estimated from the image (:func:`~blurloc.deconv.estimate_nsr`).

    Parameters
    ----------
    sharp : numpy.ndarray
        Gray image (H, W), float in [0, 1].
    kernel : numpy.ndarray
        Blur kernel (k, k), summing to 1.
    noise_levels : iterable of float
        Noise sigmas (images in [0, 1]) of eq. 1.
    rng : numpy.random.Generator
        Source of the noise.
    border : int
        Pixels left out on each side when scoring (the interior, away from the image border).

    Returns
    -------
    list of dict
        Per noise level, in order ``blurred``, ``inverse filter (eq. 3)``, ``Wiener (eq. 4)``:
        noise_sigma, method, image (H, W) float, unclipped, psnr_db (dB over the interior,
        rounded to 0.01).

    References
    ----------
    Eq. 1 (blur model), eq. 3 (inverse filter), eq. 4 (Wiener) and eq. 5-6 (PSNR) of the paper.
    """
    rows = []
    for sigma in noise_levels:
        blurred = blur_image(sharp, kernel, sigma, rng=rng)
        images = {"blurred": blurred,
                  "inverse filter (eq. 3)": inverse_filter(blurred, kernel),
                  "Wiener (eq. 4)": wiener_deconvolve(blurred, kernel,
                                                      1e-6 if sigma == 0 else None)}  # fmt: skip
        rows += [{"noise_sigma": sigma, "method": name, "image": image,
                  "psnr_db": round(_interior_psnr(sharp, image, border), 2)}
                 for name, image in images.items()]  # fmt: skip
    return rows


def nsr_curve(
    sharp: np.ndarray,
    blurred: np.ndarray,
    kernel: np.ndarray,
    nsr_values: np.ndarray,
    border: int = 24,
) -> dict:
    """PSNR of the Wiener restoration against a constant NSR, beside the estimated NSR.

    Parameters
    ----------
    sharp, blurred : numpy.ndarray
        Gray images (H, W), float in [0, 1]: the truth and its blurred, noisy copy.
    kernel : numpy.ndarray
        The true blur kernel (k, k).
    nsr_values : numpy.ndarray
        NSR = 1/SNR values (M,), > 0.
    border : int
        Pixels left out on each side when scoring.

    Returns
    -------
    dict
        ``nsr`` (M,), ``psnr_db`` (M,) dB of each restoration clipped to [0, 1],
        ``estimated_nsr`` (:func:`~blurloc.deconv.estimate_nsr` of ``blurred``) and
        ``blurred_psnr_db`` (dB of the input), all over the interior.

    References
    ----------
    Eq. 4 (Wiener) and eq. 5-6 (PSNR) of the paper.
    """
    scores = [_interior_psnr(sharp, wiener_deconvolve(blurred, kernel, n), border)
              for n in nsr_values]  # fmt: skip
    return {"nsr": np.asarray(nsr_values, float), "psnr_db": np.array(scores),
            "estimated_nsr": estimate_nsr(blurred),
            "blurred_psnr_db": _interior_psnr(sharp, blurred, border)}  # fmt: skip


def periodic_wiener(image: np.ndarray, kernel: np.ndarray, nsr: float) -> np.ndarray:
    """Wiener deconvolution (eq. 4) by a bare DFT of the image, which treats it as periodic
    (no mirror padding, unlike :func:`~blurloc.deconv.wiener_deconvolve`).

    Parameters
    ----------
    image : numpy.ndarray
        Gray image (H, W), float.
    kernel : numpy.ndarray
        Blur kernel (k, k), k <= H, W.
    nsr : float
        Constant NSR = 1/SNR, > 0.

    Returns
    -------
    numpy.ndarray
        The restoration (H, W), float64, unclipped.

    References
    ----------
    Eq. 4 of the paper.
    """
    otf = kernel_to_otf(kernel, image.shape)
    spectrum = np.fft.rfft2(image) * np.conj(otf) / (np.abs(otf) ** 2 + nsr)
    return np.fft.irfft2(spectrum, s=image.shape)


def boundary_comparison(sharp: np.ndarray, blurred: np.ndarray, kernel: np.ndarray) -> list[dict]:
    """The blurred image and its Wiener restorations with periodic and mirror boundaries.

    Parameters
    ----------
    sharp, blurred : numpy.ndarray
        Gray images (H, W), float in [0, 1]: the truth and its blurred, noisy copy.
    kernel : numpy.ndarray
        The true blur kernel (k, k).

    Returns
    -------
    list of dict
        ``blurred``, ``Wiener, periodic DFT`` and ``Wiener, mirror padding`` (both with the NSR
        estimated from ``blurred``): method, image (H, W), psnr_db (dB over the whole image,
        clipped to [0, 1]).

    References
    ----------
    Eq. 4 (Wiener) and eq. 5-6 (PSNR) of the paper.
    """
    nsr = estimate_nsr(blurred)
    images = {"blurred": blurred,
              "Wiener, periodic DFT": periodic_wiener(blurred, kernel, nsr),
              "Wiener, mirror padding": wiener_deconvolve(blurred, kernel, nsr)}  # fmt: skip
    return [{"method": name, "image": image, "psnr_db": _interior_psnr(sharp, image, 0)}
            for name, image in images.items()]  # fmt: skip


def _per_channel(restore: Callable[[np.ndarray], np.ndarray], image: np.ndarray) -> np.ndarray:
    return np.dstack([restore(image[..., c]) for c in range(image.shape[2])])


def deblurring_methods(
    skimage_balance: float, rl_iterations: int = 10, seed: int = 0
) -> dict[str, Callable[[np.ndarray, np.ndarray | None], np.ndarray]]:
    """The single-image methods compared in notebook 02.

    ``blind_wiener`` is this package's eq. 4 with the NSR estimated from the noise;
    ``blind_wiener_gradient`` the same with the gradient regulariser at blind deblurring's
    weight (:func:`~blurloc.deconv.blind_nsr`);
    ``blind_deblurring`` the package's blind deblurring as shipped
    (:func:`~blurloc.deconv.deblur_blind`: its regulariser, and its gate, which passes through
    frames whose restoration is not expected to gain); scikit-image's ``wiener``,
    ``unsupervised_wiener`` and ``richardson_lucy`` are fed the same estimated kernel;
    ``blurred`` returns its input.

    Parameters
    ----------
    skimage_balance : float
        ``balance`` of scikit-image's ``wiener`` (:func:`choose_skimage_balance`).
    rl_iterations : int
        Richardson-Lucy iterations.
    seed : int
        Seed of ``unsupervised_wiener``'s sampler.

    Returns
    -------
    dict
        ``{name: method}``; ``method(image, kernel)`` maps an RGB float [0, 1] image (H, W, 3)
        and the blind kernel (None when the detector found no blur: the input is returned) to a
        restored image of the same shape, clipped to [0, 1].

    References
    ----------
    Eq. 4 of the paper (Wiener deconvolution).
    """
    rng = np.random.default_rng(seed)

    def skip_if_sharp(method):
        def run(image: np.ndarray, kernel: np.ndarray | None) -> np.ndarray:
            return image if kernel is None else np.clip(method(image, kernel), 0.0, 1.0)

        return run

    return {
        "blurred": lambda image, kernel: image,
        "blind_wiener": skip_if_sharp(lambda im, k: wiener_deconvolve(im, k)),
        "blind_wiener_gradient": skip_if_sharp(
            lambda im, k: wiener_deconvolve(im, k, blind_nsr(im, "gradient"), "gradient")
        ),
        "blind_deblurring": skip_if_sharp(lambda im, k: deblur_blind(im)),
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
    budget: int | None = None,
    progress: bool = False,
) -> list[dict]:
    """PSNR and SSIM of each method's output against the stand-in's sharp mid-exposure render.

    Parameters
    ----------
    root : str or os.PathLike
        The stand-in root (stored ``color`` frames and ``sharp`` renders).
    split : str
        ``"train"`` or ``"test"``.
    methods : dict
        ``{name: method}`` (:func:`deblurring_methods`).
    budget : int or None
        About how many frames of the split to read, spread evenly
        (:func:`~blurloc.data.samples.split_frames`); None reads every frame.
    progress : bool
        Show a progress bar.

    Returns
    -------
    list of dict
        One row per frame and method: scene, sequence, frame, method, psnr_db (dB, data range
        1), ssim, blurred (the detector's verdict).

    References
    ----------
    Eq. 5-7 of the paper (PSNR, SSIM).
    """
    frames = split_frames(root, split, budget)
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
    root: str | os.PathLike, candidates: Iterable[float], budget: int | None = None
) -> tuple[float, int]:
    """The ``balance`` of scikit-image's ``wiener`` with the best mean PSNR on training frames.

    Only frames that blind deblurring would touch count, each fed the same estimated kernel;
    the test split is never used.

    Parameters
    ----------
    root : str or os.PathLike
        The stand-in root.
    candidates : iterable of float
        Balances to try.
    budget : int or None
        About how many frames of the training split to read, spread evenly
        (:func:`~blurloc.data.samples.split_frames`); None reads every frame.

    Returns
    -------
    balance : float
        The best candidate.
    frames : int
        Number of frames it was chosen on.
    """
    candidates = list(candidates)
    scores: dict[float, list[float]] = {b: [] for b in candidates}
    for _, sequence, frame in split_frames(root, "train", budget):
        observed = as_float_image(read_image(sequence.path(frame, "color")))
        kernel = blind_kernel(observed)
        if kernel is None:
            continue
        truth = as_float_image(read_image(sequence.path(frame, "sharp")))
        for balance in candidates:
            restored = _per_channel(lambda c, b=balance, k=kernel: wiener(c, k, b), observed)
            scores[balance].append(psnr(truth, np.clip(restored, 0, 1), 1.0))
    used = len(scores[candidates[0]])
    if not used:
        raise ValueError(f"{root}: no blurred training frames to choose the balance on")
    return max(candidates, key=lambda b: float(np.mean(scores[b]))), used


def per_scene_means(rows: list[dict], metric: str) -> dict[str, dict[str, float]]:
    """Per-scene means of a metric, per method.

    Parameters
    ----------
    rows : list of dict
        Per-frame rows with ``method``, ``scene`` and ``metric`` keys.
    metric : str
        The key to average (e.g. ``psnr_db``).

    Returns
    -------
    dict
        ``{method: {scene: mean, ..., "mean": mean of the per-scene means}}``, scenes in
        first-seen order.
    """
    table = {}
    for method in dict.fromkeys(r["method"] for r in rows):
        values = grouped_means(rows, "scene", metric, {"method": method})
        table[method] = {**values, "mean": float(np.mean(list(values.values())))}
    return table


def paper_fig6_7(scene: str) -> dict[str, float | None]:
    """The PSNR and SSIM the paper printed after Wiener deblurring for one scene.

    Parameters
    ----------
    scene : str
        A 7-Scenes scene name, or ``"mean"`` for the mean over the printed scenes.

    Returns
    -------
    dict
        ``paper_psnr_db`` and ``paper_ssim`` (printed numbers, not measured here; None for a
        scene the paper did not print).

    References
    ----------
    Fig. 6 (PSNR) and Fig. 7 (SSIM) of the paper.
    """
    row = {}
    for metric, item in (("psnr_db", "fig6"), ("ssim", "fig7")):
        printed = paper_values(item, metric)
        value = np.mean(list(printed.values())) if scene == "mean" else printed.get(scene)
        row[f"paper_{metric}"] = None if value is None else round(float(value), 4)
    return row


def frame_changes(rows: list[dict]) -> list[dict]:
    r"""Per method of :func:`evaluate_deblurring`: how its PSNR changes frame by frame against
    the blurred input, over all frames and over the frames it changed.

    .. math::

        \Delta_i = \mathrm{PSNR}(x_i, \tilde{x}_i) - \mathrm{PSNR}(x_i, b_i)

    Parameters
    ----------
    rows : list of dict
        Per-frame rows of :func:`evaluate_deblurring` (``method``, ``scene``, ``sequence``,
        ``frame``, ``psnr_db``), with the ``blurred`` method's rows.

    Returns
    -------
    list of dict
        One row per method other than ``blurred``: ``frames``; ``restored``, the frames whose
        PSNR it changed (a frame passed through changes by 0 dB); ``mean_change_db`` over all
        frames with its 95 % bootstrap interval (``ci_low_db``, ``ci_high_db``;
        :func:`~blurloc.intervals.paired_interval` over frames); ``median_restored_db`` and
        ``restored_with_gain`` over the frames it changed (empty where it changed none).

    Raises
    ------
    ValueError
        If a method's frame has no ``blurred`` row.

    References
    ----------
    Eq. 6 of the paper (PSNR).
    """

    def key(row: dict) -> tuple:
        return row["scene"], row["sequence"], row["frame"]

    blurred = {key(r): float(r["psnr_db"]) for r in rows if r["method"] == "blurred"}
    table = []
    for method in dict.fromkeys(r["method"] for r in rows if r["method"] != "blurred"):
        subset = [r for r in rows if r["method"] == method]
        missing = [key(r) for r in subset if key(r) not in blurred]
        if missing:
            raise ValueError(f"{method}: frame {missing[0]} has no blurred row")
        change = np.array([float(r["psnr_db"]) - blurred[key(r)] for r in subset])
        restored = change[change != 0.0]
        bounds = paired_interval(change) if len(change) > 1 and change.any() else None
        table.append({
            "method": method, "frames": len(change), "restored": len(restored),
            "mean_change_db": round(float(change.mean()), 3),
            "ci_low_db": round(bounds.low, 3) if bounds else "",
            "ci_high_db": round(bounds.high, 3) if bounds else "",
            "median_restored_db": round(float(np.median(restored)), 3) if len(restored) else "",
            "restored_with_gain": int((restored > 0).sum()) if len(restored) else "",
        })  # fmt: skip
    return table


def per_scene_table(rows: list[dict]) -> list[dict]:
    """Per scene (and the mean of the per-scene means): every method's PSNR and SSIM, beside
    the paper's Fig. 6-7 values.

    Parameters
    ----------
    rows : list of dict
        Per-frame rows of :func:`evaluate_deblurring` (``method``, ``scene``, ``psnr_db``,
        ``ssim``; the ``blurred`` method counts the frames).

    Returns
    -------
    list of dict
        One row per scene and a ``mean`` row: ``frames``, ``<method>_psnr_db`` (2 decimals),
        ``<method>_ssim`` (4 decimals), ``paper_psnr_db`` and ``paper_ssim``.
    """
    measured = {metric: per_scene_means(rows, metric) for metric in ("psnr_db", "ssim")}
    scenes = [s for s in measured["psnr_db"]["blurred"] if s != "mean"]
    table = []
    for scene in [*scenes, "mean"]:
        row = {"scene": scene, "frames": sum(1 for r in rows if r["method"] == "blurred"
                                             and scene in ("mean", r["scene"]))}  # fmt: skip
        paper = paper_fig6_7(scene)
        for metric in ("psnr_db", "ssim"):
            for method, values in measured[metric].items():
                row[f"{method}_{metric}"] = round(values[scene], 4 if metric == "ssim" else 2)
            row[f"paper_{metric}"] = paper[f"paper_{metric}"]
        table.append(row)
    return table
