"""Ablations of the video network (eq. 8-11) at equal capacity and over several seeds: does
the recurrence, the auxiliary state (eq. 9) or the adaptive blending (eq. 10) earn its place?

Each ablated variant gets residual blocks back until its parameter count matches the full
network's (:func:`~blurloc.models.video_deblur.matched_blocks`), every variant is trained with
the same budget once per seed, and each is compared with the full network trained with the
same seed: the paired difference of their gains over the blurred input, with a 95 %
t-interval over the seeds.
"""

from __future__ import annotations

import functools
import os
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from tqdm.auto import tqdm

from ..inference import VideoRestorer
from ..intervals import paired_interval, verdict
from ..models.video_deblur import VideoDeblurConfig, VideoDeblurNet, matched_blocks, parameter_count
from ..train.config import VideoTrainConfig
from ..train.loop import parallel_map
from ..train.video import Video, load_video_splits, train_video_deblur
from .deblurring import per_scene_means
from .video import evaluate_video_deblurring

ABLATED_PARTS = {
    "no_aux": {"aux_state": False},
    "no_blending": {"blending": False},
    "single_frame": {"aux_state": False, "blending": False, "recurrent": False},
}
"""What each ablation switches off: eq. 9, eq. 10, or the recurrence itself (every frame alone)."""

SPIKE_FACTOR = 10.0
"""A training loss spike: an interval whose mean training loss exceeds this many times the
run's median interval loss."""

INTERVAL_COLUMNS = ("variant", "parameters", "seeds", "gain_mean", "gain_min", "gain_max",
                    "minus_reference", "ci_low", "ci_high", "verdict")  # fmt: skip
"""The columns of :func:`ablation_intervals`' rows, in table order."""


def equal_parameter_variants(base: VideoDeblurConfig | None = None) -> dict[str, VideoDeblurConfig]:
    """The full network and its ablations (:data:`ABLATED_PARTS`), each ablation with the
    number of residual blocks that brings its parameter count nearest to the full network's.

    Parameters
    ----------
    base : VideoDeblurConfig, optional
        The full network (the package's defaults when None).

    Returns
    -------
    dict
        ``full``, ``no_aux``, ``no_blending``, ``single_frame`` -> configuration.
    """
    base = base or VideoDeblurConfig()
    target = parameter_count(VideoDeblurNet(base))
    variants = {"full": base}
    for name, switches in ABLATED_PARTS.items():
        variants[name] = matched_blocks(replace(base, **switches), target)
    return variants


@dataclass(frozen=True)
class AblationRun:
    """One trained variant: its name, seed, run folder (``best.pt`` inside) and history."""

    variant: str
    seed: int
    folder: Path
    history: dict


def train_ablations(
    root: str | os.PathLike,
    variants: dict[str, VideoDeblurConfig],
    seeds: list[int],
    budget: VideoTrainConfig,
    out_dir: str | os.PathLike,
    frames_per_sequence: int | None = None,
    workers: int = 1,
    progress: bool = False,
    validation_per_scene: int | None = None,
) -> list[AblationRun]:
    """Train every variant once per seed with the same budget (finished runs are reused).

    With ``workers > 1`` the trainings are spread over that many processes
    (:func:`~blurloc.train.loop.parallel_map`), each decoding the frames once and training with
    ``budget.threads // workers`` threads (at least 1).

    Parameters
    ----------
    root : str or os.PathLike
        A stand-in root (it needs the sharp frames).
    variants : dict
        Name -> network configuration, e.g. :func:`equal_parameter_variants`.
    seeds : list of int
        The seeds; every variant is trained with each.
    budget : VideoTrainConfig
        Steps, batch, crop and the rest, shared by all runs (its ``model``, ``seed`` and, with
        several workers, ``threads`` are replaced).
    out_dir : str or os.PathLike
        Runs go to ``out_dir/<variant>-seed<seed>/``.
    frames_per_sequence : int, optional
        Train on the first that many frames of every sequence
        (:func:`~blurloc.train.video.load_video_splits`; all when None).
    workers : int
        Processes that train at once (1: in this process).
    progress : bool
        Show a progress bar over the trainings.
    validation_per_scene : int, optional
        Validate on the ends of the first that many training sequences of each scene (all
        when None; :func:`~blurloc.train.video.load_video_splits`).

    Returns
    -------
    list of AblationRun
        Variant by variant, seed by seed.

    Raises
    ------
    ValueError
        If ``workers`` is not positive.
    """
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    threads = budget.threads if workers == 1 else max(1, budget.threads // workers)
    jobs = [(str(root), frames_per_sequence, validation_per_scene, name, seed,
             replace(budget, model=model, seed=seed, threads=threads),
             Path(out_dir) / f"{name}-seed{seed}")
            for name, model in variants.items() for seed in seeds]  # fmt: skip
    done = parallel_map(_train_one, jobs, workers)
    runs = list(tqdm(done, total=len(jobs), disable=not progress, desc="video ablations"))
    training_videos.cache_clear()  # the frames held in this process (workers > 1: in none)
    return runs


@functools.cache
def training_videos(
    root: str, frames_per_sequence: int | None, validation_per_scene: int | None
) -> dict[str, list[Video]]:
    """The training and validation videos of a stand-in root, read once per process.

    :func:`~blurloc.train.video.load_video_splits` without the test split, cached, so that the
    trainings one process makes on a root share its frames.

    Parameters
    ----------
    root : str
        A stand-in root (it needs the sharp frames).
    frames_per_sequence : int or None
        Train on the first that many frames of every training sequence (all when None).
    validation_per_scene : int or None
        Validate on the ends of that many training sequences per scene (all when None).

    Returns
    -------
    dict
        ``train``, ``validation`` and an empty ``test`` list of (blurred, sharp) uint8 videos.
    """
    return load_video_splits(root, frames_per_sequence=frames_per_sequence, with_test=False,
                             validation_per_scene=validation_per_scene)  # fmt: skip


def _train_one(job: tuple) -> AblationRun:
    """Train (or reuse) one run of :func:`train_ablations`."""
    root, frames_per_sequence, validation_per_scene, name, seed, config, folder = job
    splits = training_videos(root, frames_per_sequence, validation_per_scene)
    history = train_video_deblur(splits, folder, config, progress=False)
    return AblationRun(name, seed, folder, history)


def ablation_gains(
    root: str | os.PathLike,
    runs: list[AblationRun],
    device: str = "cpu",
    frames_per_sequence: int | None = None,
    progress: bool = False,
    workers: int = 1,
) -> tuple[dict[str, dict[int, float]], list[dict]]:
    """Score every run on the test sequences: its PSNR gain over the blurred input.

    With ``workers > 1`` the networks are shared out over that many one-thread processes
    (:func:`~blurloc.train.loop.parallel_map`); each process reads the test frames once.

    Parameters
    ----------
    root : str or os.PathLike
        A stand-in root (it needs the sharp frames).
    runs : list of AblationRun
        From :func:`train_ablations`.
    device : str
        Where the networks run.
    frames_per_sequence : int, optional
        Score only the first that many frames of every test sequence (all when None).
    progress : bool
        Show a progress bar.
    workers : int
        Processes that score at once (1: in this process).

    Returns
    -------
    gains : dict
        Variant -> {seed: mean of the per-scene mean PSNR of the restored frames minus that
        of the blurred frames (dB)}.
    rows : list of dict
        The per-frame PSNR (:func:`~blurloc.experiments.video.evaluate_video_deblurring`
        without SSIM; methods ``blurred`` and ``<variant>-seed<seed>``).
    """
    methods = {"blurred": np.asarray}  # the input itself
    for run in runs:
        methods[f"{run.variant}-seed{run.seed}"] = VideoRestorer(run.folder / "best.pt", device)
    names = list(methods)
    jobs = [(str(root), {name: methods[name] for name in names[k::workers]}, frames_per_sequence,
             progress) for k in range(min(workers, len(names)))]  # fmt: skip
    rows = [row for group_rows in parallel_map(_score_group, jobs, workers) for row in group_rows]
    means = per_scene_means(rows, "psnr_db")
    gains: dict[str, dict[int, float]] = {}
    for run in runs:
        restored = means[f"{run.variant}-seed{run.seed}"]["mean"]
        gains.setdefault(run.variant, {})[run.seed] = restored - means["blurred"]["mean"]
    return gains, rows


def _score_group(job: tuple) -> list[dict]:
    """The per-frame PSNR rows of a group of the methods of :func:`ablation_gains`."""
    root, methods, frames_per_sequence, progress = job
    return evaluate_video_deblurring(root, methods, "test", progress=progress,
                                     frames_per_sequence=frames_per_sequence,
                                     with_ssim=False)  # fmt: skip


def ablation_intervals(
    gains: dict[str, dict[int, float]],
    parameters: dict[str, int],
    reference: str = "full",
    unit: str = "dB",
    below: str = "the part helps",
    above: str = "the part hurts",
) -> list[dict]:
    """Each variant's gain over the blurred input across seeds, and its paired difference to
    ``reference`` (same seeds) with a 95 % Student t-interval.

    Parameters
    ----------
    gains : dict
        Variant -> {seed: gain over the blurred input} (e.g. PSNR in dB, the mean of the
        per-scene means of the restored frames minus that of the blurred ones).
    parameters : dict
        Variant -> parameter count.
    reference : str
        The variant the others are compared with.
    unit : str
        Unit of the gains, used in the verdict.
    below, above : str
        The verdict when the whole interval lies below zero (the variant gains less than the
        reference: for an ablation, the removed part helps) or above it.

    Returns
    -------
    list of dict
        One row per variant: ``variant``, ``parameters``, ``seeds``, ``gain_mean``,
        ``gain_min``, ``gain_max`` and, except for ``reference``, ``minus_reference``,
        ``ci_low``, ``ci_high`` and ``verdict`` (``below`` when the whole interval lies below
        zero, ``above`` when above, otherwise "too small to resolve at this power (±x)").

    Raises
    ------
    ValueError
        If ``reference`` is missing, or a variant was not run with the reference's seeds (at
        least two).
    """
    if reference not in gains:
        raise ValueError(f"reference variant {reference!r} not among {sorted(gains)}")
    seeds = sorted(gains[reference])
    rows = []
    for name, by_seed in gains.items():
        if sorted(by_seed) != seeds:
            raise ValueError(f"variant {name!r} has seeds {sorted(by_seed)}, but {reference!r} "
                             f"has {seeds}: the comparison must be paired")  # fmt: skip
        values = np.array([by_seed[seed] for seed in seeds])
        row = {"variant": name, "parameters": parameters[name], "seeds": len(seeds),
               "gain_mean": float(values.mean()), "gain_min": float(values.min()),
               "gain_max": float(values.max())}  # fmt: skip
        if name != reference:
            differences = values - np.array([gains[reference][seed] for seed in seeds])
            interval = paired_interval(differences, method="t")
            worded = {"reproduced": below, "contradicted": above}  # a claim that it is lower
            unresolved = f"too small to resolve at this power (±{interval.half_width:.2g} {unit})"
            row.update(
                minus_reference=interval.mean,
                ci_low=interval.low,
                ci_high=interval.high,
                verdict=worded.get(verdict(interval, claimed_sign=-1), unresolved),
            )
        rows.append(row)
    return rows


def training_health(runs: list[AblationRun]) -> list[dict]:
    """How each training went, read from its history: where the scored network came from and
    whether the training collapsed on the way.

    A recurrent network can leave training with an expansive recurrence after a loss spike;
    its validation on whole sequences then falls and stays low, and the network scored
    (``best.pt``, the best validation) is an early one. This table shows that without running
    any network. It cannot show a state that drifts only beyond the length of the validation
    sequences: such a network validates well and falls apart on a long test video, so the
    test scores remain the check.

    Parameters
    ----------
    runs : list of AblationRun
        From :func:`train_ablations`.

    Returns
    -------
    list of dict
        One row per run: ``variant``, ``seed``, ``steps`` (the last step trained),
        ``best_step`` (the step of the scored network), ``peak_loss_ratio`` (the largest
        interval mean training loss over the median one), ``spike`` (that ratio above
        :data:`SPIKE_FACTOR`), and ``best_val_db`` and ``last_val_db`` (validation PSNR of the
        scored and of the last network; NaN where the network returned NaN).
    """
    rows = []
    for run in runs:
        history = run.history
        losses = np.asarray(history["train_loss"], dtype=float)
        psnr = np.asarray(history["val_psnr"], dtype=float)
        best = int(np.nanargmax(psnr))
        ratio = float(np.nanmax(losses) / np.nanmedian(losses))
        rows.append({"variant": run.variant, "seed": run.seed, "steps": int(history["step"][-1]),
                     "best_step": int(history["step"][best]), "peak_loss_ratio": ratio,
                     "spike": bool(ratio > SPIKE_FACTOR), "best_val_db": float(psnr[best]),
                     "last_val_db": float(psnr[-1])})  # fmt: skip
    return rows
