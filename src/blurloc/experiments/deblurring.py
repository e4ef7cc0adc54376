"""Single-image deblurring methods compared on a stand-in split (notebook 02): the methods, their
per-frame PSNR/SSIM, the balance of scikit-image's Wiener filter and per-scene means."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable

import numpy as np
from skimage.restoration import richardson_lucy, unsupervised_wiener, wiener
from tqdm.auto import tqdm

from ..data.samples import split_frames
from ..data.sevenscenes import read_image
from ..deconv import blind_kernel, wiener_deconvolve
from ..images import as_float_image
from ..metrics import psnr, ssim
from ..paper import paper_values


def _per_channel(restore: Callable[[np.ndarray], np.ndarray], image: np.ndarray) -> np.ndarray:
    return np.dstack([restore(image[..., c]) for c in range(image.shape[2])])


def deblurring_methods(
    skimage_balance: float, rl_iterations: int = 10, seed: int = 0
) -> dict[str, Callable[[np.ndarray, np.ndarray | None], np.ndarray]]:
    """The single-image methods compared in notebook 02.

    ``blind_wiener`` is this package's eq. 4 with the NSR estimated from the noise;
    scikit-image's ``wiener``, ``unsupervised_wiener`` and ``richardson_lucy`` are fed the same
    estimated kernel; ``blurred`` returns its input.

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
    methods = list(dict.fromkeys(r["method"] for r in rows))
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    table = {}
    for method in methods:
        values = {scene: float(np.mean([r[metric] for r in rows
                                        if r["method"] == method and r["scene"] == scene]))
                  for scene in scenes}  # fmt: skip
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
