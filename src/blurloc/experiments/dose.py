"""The dose-response of the paper's claim: pose error against blur strength, with and without
deblurring.

The same scenes and trajectories (same seed) are rendered with several exposure lengths, from
none to longer than the default; at each, the pose regressor is trained on the blurred frames
and on the same frames deblurred, with the same seeds, so that the two can be paired. The
paper shows one blur level (7-Scenes' own); this shows when deblurring starts to matter.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np
from tqdm.auto import tqdm

from ..data.synth import SynthConfig, synthesize
from ..train.config import PoseTrainConfig
from .comparisons import comparison_table
from .pose import blur_at_input, run_pose_matrix
from .video import write_deblurred_root


def blur_dose_response(
    out_dir: str | os.PathLike,
    scenes: list[str],
    strengths: tuple[float, ...],
    synth_config: SynthConfig,
    config: PoseTrainConfig,
    deblur: Callable[[np.ndarray], np.ndarray],
    seeds: tuple[int, ...],
    seed: int = 0,
    progress: bool = False,
    workers: int = 1,
) -> list[dict]:
    """Train and test the pose regressor on blurred and deblurred frames at each blur strength.

    Parameters
    ----------
    out_dir : str or os.PathLike
        Stand-ins, deblurred copies and models go to ``out_dir/blur-<strength>[-deblurred,
        -models]``.
    scenes : list of str
        Scenes rendered and trained on.
    strengths : tuple of float
        Exposure lengths in frame intervals (:class:`~blurloc.data.synth.SynthConfig`'s
        ``blur_strength``; 0: no blur, only noise).
    synth_config : SynthConfig
        Every other setting of the renders.
    config : PoseTrainConfig
        The regressor's training settings.
    deblur : callable
        Function of a whole uint8 (T, H, W, 3) sequence returning it deblurred (e.g. the
        recurrent network, eq. 8-11).
    seeds : tuple of int
        Training seeds, the same for both inputs at every strength.
    seed : int
        Seed of the renders (trajectories and noise), the same at every strength.
    progress : bool
        Show a progress bar over the strengths.
    workers : int
        Processes for deblurring and training (see
        :func:`~blurloc.experiments.pose.run_pose_matrix`); with more than 1, ``deblur`` must be
        picklable (e.g. :class:`~blurloc.inference.VideoRestorer`).

    Returns
    -------
    list of dict
        One row per strength, input (``condition`` ``blurred`` or ``rnn``), scene and seed:
        ``blur_strength``, ``frame_median_blur_px`` and ``input_median_blur_px`` (recorded blur
        in the frames and at the network's input, :func:`~blurloc.experiments.pose.blur_at_input`)
        and the row of :func:`~blurloc.experiments.pose.run_pose_matrix`.
    """
    out_dir = Path(out_dir)
    rows = []
    for strength in tqdm(strengths, disable=not progress, desc="blur strengths"):
        name = f"blur-{strength:g}"
        root = synthesize(out_dir / name, scenes=scenes, seed=seed, progress=False,
                          config=replace(synth_config, blur_strength=strength))  # fmt: skip
        deblurred = write_deblurred_root(
            root, out_dir / f"{name}-deblurred", deblur, workers=workers
        )
        blur = blur_at_input(root, config)
        summaries, _ = run_pose_matrix({"blurred": root, "rnn": deblurred}, scenes,
                                       [("blurred", "lstm"), ("rnn", "lstm")], config,
                                       out_dir / f"{name}-models", seeds,
                                       workers=workers)  # fmt: skip
        rows += [{"blur_strength": strength, "frame_median_blur_px": blur["frame_median_px"],
                  "input_median_blur_px": blur["input_median_px"], **row}
                 for row in summaries]  # fmt: skip
    return rows


def dose_response_table(rows: list[dict]) -> list[dict]:
    """Per strength: the errors with blurred and deblurred input, and their paired difference.

    With a few pairs per strength (one scene, five seeds) a percentile bootstrap understates
    the uncertainty, so the intervals are Student t-intervals.

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`blur_dose_response`.

    Returns
    -------
    list of dict
        Per strength: ``blur_strength``, ``frame_median_blur_px``, ``input_median_blur_px``,
        ``pairs``, the mean over scenes and seeds of the median position error (m, eq. 12) for
        ``blurred`` and ``deblurred`` input, their mean paired difference (deblurred -
        blurred) with its 95 % t-interval over scene x seed pairs, the same for the
        median orientation error (degrees, eq. 13), and the verdict on the position difference.
    """
    table = []
    for strength in dict.fromkeys(r["blur_strength"] for r in rows):
        level = [r for r in rows if r["blur_strength"] == strength]
        paired = comparison_table(
            level, [("blurred", "rnn")], ("position_m_median", "orientation_deg_median"), method="t"
        )
        position, orientation = paired
        table.append({
            "blur_strength": strength, "frame_median_blur_px": level[0]["frame_median_blur_px"],
            "input_median_blur_px": level[0]["input_median_blur_px"], "pairs": position["pairs"],
            "blurred_position_m": position["baseline_mean"],
            "deblurred_position_m": position["other_mean"],
            "position_difference_m": position["mean_difference"],
            "position_ci_low": position["ci_low"], "position_ci_high": position["ci_high"],
            "blurred_orientation_deg": orientation["baseline_mean"],
            "deblurred_orientation_deg": orientation["other_mean"],
            "orientation_difference_deg": orientation["mean_difference"],
            "orientation_ci_low": orientation["ci_low"],
            "orientation_ci_high": orientation["ci_high"],
            "position_verdict": position["verdict"],
        })  # fmt: skip
    return table
