"""Run the notebooks in order with papermill, headless, and log the time each takes."""

from __future__ import annotations

import contextlib
import os
import sys
import time
from collections.abc import Iterator
from pathlib import Path

from .config import (
    DEFAULT_SEED,
    HEADLESS_VARIABLE,
    default_data_root,
    project_root,
    write_rows,
)
from .errors import NotebookError

#: Figure and table files (under ``figures_dir``) that each notebook promises to write.
EXPECTED_OUTPUTS: dict[str, tuple[str, ...]] = {
    "00_synthetic_scenes": (
        "standin_scenes.png",
        "standin_scenes.pdf",
        "standin_exposure.png",
        "standin_exposure.pdf",
        "standin_trajectories.png",
        "standin_trajectories.pdf",
        "standin_pairs.png",
        "standin_pairs.pdf",
        "standin_blur_histogram.png",
        "standin_blur_histogram.pdf",
        "standin_motion_stats.md",
        "standin_motion_stats.csv",
        "standin_mean_pose_baseline.md",
        "standin_mean_pose_baseline.csv",
    ),
    "01_blur_model_and_spectrum": (
        "blur_kernels.png",
        "blur_kernels.pdf",
        "blur_spectra.png",
        "blur_spectra.pdf",
        "blur_estimation_accuracy.png",
        "blur_estimation_accuracy.pdf",
        "blur_estimation_accuracy.md",
        "blur_estimation_accuracy.csv",
        "blur_detection.png",
        "blur_detection.pdf",
        "blur_scores_photos.md",
        "blur_scores_photos.csv",
        "blur_estimation_standin.md",
        "blur_estimation_standin.csv",
        "blur_estimation_standin.png",
        "blur_estimation_standin.pdf",
        "blur_vs_camera_motion.md",
        "blur_vs_camera_motion.csv",
    ),
    "02_wiener_deconvolution": (
        "wiener_vs_inverse.png",
        "wiener_vs_inverse.pdf",
        "wiener_nsr.png",
        "wiener_nsr.pdf",
        "wiener_boundaries.png",
        "wiener_boundaries.pdf",
        "wiener_vs_skimage.png",
        "wiener_vs_skimage.pdf",
        "fig03_deblurring_process.png",
        "fig03_deblurring_process.pdf",
        "deblur_per_scene.md",
        "deblur_per_scene.csv",
        "fig06_psnr_per_scene.png",
        "fig06_psnr_per_scene.pdf",
        "fig07_ssim_per_scene.png",
        "fig07_ssim_per_scene.pdf",
        "wiener_oracles.md",
        "wiener_oracles.csv",
        "wiener_oracles.png",
        "wiener_oracles.pdf",
        "deblur_oracle_per_scene.md",
        "deblur_oracle_per_scene.csv",
    ),
    "03_video_rnn_deblurring": (
        "video_training_curves.png",
        "video_training_curves.pdf",
        "video_deblur_per_scene.md",
        "video_deblur_per_scene.csv",
        "video_ablation_intervals.md",
        "video_ablation_intervals.csv",
        "video_ablation_intervals.png",
        "video_ablation_intervals.pdf",
        "video_ablation_health.md",
        "video_ablation_health.csv",
        "video_motion_network_control.md",
        "video_motion_network_control.csv",
        "fig04_video_deblurring.png",
        "fig04_video_deblurring.pdf",
        "video_attention.png",
        "video_attention.pdf",
    ),
    "04_pose_lstm_training": (
        "pose_overview.md",
        "pose_overview.csv",
        "table1_blurred.md",
        "table1_blurred.csv",
        "table2_deblurred.md",
        "table2_deblurred.csv",
        "fig08_position_error.png",
        "fig08_position_error.pdf",
        "fig09_orientation_error.png",
        "fig09_orientation_error.pdf",
        "pose_training_curves.png",
        "pose_training_curves.pdf",
        "pose_trajectories.png",
        "pose_trajectories.pdf",
        "pose_input_blur.md",
        "pose_input_blur.csv",
        "pose_vs_mean_pose.md",
        "pose_vs_mean_pose.csv",
        "pose_paired_differences.md",
        "pose_paired_differences.csv",
        "pose_paired_differences.png",
        "pose_paired_differences.pdf",
    ),
    "05_results_figures": (
        "fig01_architecture.png",
        "fig01_architecture.pdf",
        "fig02_pipeline.png",
        "fig02_pipeline.pdf",
        "fig05_predicted_views.png",
        "fig05_predicted_views.pdf",
        "fig10_combined_error.png",
        "fig10_combined_error.pdf",
        "table3_pose_comparison.md",
        "table3_pose_comparison.csv",
        "paper_vs_reproduction.md",
        "paper_vs_reproduction.csv",
        "paper_vs_reproduction.png",
        "paper_vs_reproduction.pdf",
        "errata.md",
        "errata.csv",
    ),
    "06_blur_dose_response": (
        "pose_dose_response.md",
        "pose_dose_response.csv",
        "pose_dose_response.png",
        "pose_dose_response.pdf",
    ),
}


def notebook_names() -> list[str]:
    """Names of the notebooks in run order.

    Returns
    -------
    list of str
        Stems (without .ipynb) of the project's ``notebooks/NN_*.ipynb``
        (:func:`blurloc.config.project_root`), sorted.
    """
    notebooks = project_root() / "notebooks"
    return sorted(path.stem for path in notebooks.glob("[0-9][0-9]_*.ipynb"))


@contextlib.contextmanager
def _headless() -> Iterator[None]:
    previous = os.environ.get(HEADLESS_VARIABLE)
    os.environ[HEADLESS_VARIABLE] = "1"
    try:
        yield
    finally:
        if previous is None:
            os.environ.pop(HEADLESS_VARIABLE, None)
        else:
            os.environ[HEADLESS_VARIABLE] = previous


def default_parameters(quick: bool) -> dict:
    """The parameters ``make reproduce`` passes to every notebook.

    Parameters
    ----------
    quick : bool
        Quick runs use the tiny stand-in and write under ``build/quick`` (never into
        ``figures/`` or ``results/``).

    Returns
    -------
    dict
        quick, seed, data_root, results_dir, figures_dir, device; the folders in the project
        (:func:`blurloc.config.project_root`).
    """
    root = project_root()
    if quick:
        return {
            "quick": True,
            "seed": DEFAULT_SEED,
            "data_root": str(default_data_root(quick=True)),
            "results_dir": str(root / "build" / "quick" / "results"),
            "figures_dir": str(root / "build" / "quick" / "figures"),
            "device": "auto",
        }
    return {
        "quick": False,
        "seed": DEFAULT_SEED,
        "data_root": str(default_data_root(quick=False)),
        "results_dir": str(root / "results"),
        "figures_dir": str(root / "figures"),
        "device": "auto",
    }


def run_notebooks(
    quick: bool = False,
    names: list[str] | None = None,
    parameters: dict | None = None,
    output_dir: str | os.PathLike | None = None,
    cell_timeout_s: int | None = None,
    log_output: bool = False,
) -> list[tuple]:
    """Execute notebooks in order with papermill (kernel ``python3``).

    Parameters
    ----------
    quick : bool
        Tiny sizes (as in the tests); results and figures go under ``build/quick``.
    names : list of str, optional
        Notebook names without ``.ipynb`` (default: all, in order).
    parameters : dict, optional
        Overrides of :func:`default_parameters`.
    output_dir : str or os.PathLike, optional
        Where the executed copies and ``timings.csv`` go (default ``build/`` or
        ``build/quick``).
    cell_timeout_s : int, optional
        Seconds a cell may run (default: no limit).
    log_output : bool
        Echo the cells' output.

    Returns
    -------
    list of tuple
        (name, seconds) per notebook; the times are also printed and written to
        ``timings.csv``.

    Raises
    ------
    NotebookError
        Naming the notebook, the failing cell and the exception (the executed copy keeps the
        whole traceback).
    ValueError
        On an unknown notebook name.
    """
    import papermill

    available = notebook_names()
    names = names or available
    unknown = sorted(set(names) - set(available))
    if unknown:
        raise ValueError(f"unknown notebook(s) {unknown}; available: {available}")
    params = {**default_parameters(quick), **(parameters or {})}
    notebooks, build = project_root() / "notebooks", project_root() / "build"
    output_dir = Path(output_dir or (build / "quick" if quick else build))
    output_dir.mkdir(parents=True, exist_ok=True)
    # The python3 kernel must be this interpreter (the one with blurloc installed).
    os.environ["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), os.environ["PATH"]])
    timings = []
    with _headless():  # the kernels inherit it: no progress bars in the executed copies
        for name in names:
            start = time.perf_counter()
            executed = output_dir / f"{name}.ipynb"
            try:
                papermill.execute_notebook(
                    str(notebooks / f"{name}.ipynb"),
                    str(executed),
                    parameters=params,
                    kernel_name="python3",
                    cwd=str(notebooks),
                    execution_timeout=cell_timeout_s,
                    log_output=log_output,
                    progress_bar=False,
                    # the kernel's own log (a warning that it talks to papermill over local TCP, an
                    # interrupt it recovers from) is not the notebook's; cell errors still raise
                    extra_arguments=["--log-level=CRITICAL"],
                )
            except papermill.PapermillExecutionError as error:
                line = ((error.source or "").strip().splitlines() or [""])[0]
                line = line if len(line) <= 60 else f"{line[:57]}..."
                raise NotebookError(
                    f"{notebooks / name}.ipynb: cell In [{error.exec_count}] "
                    f"({line!r}) failed with {error.ename}: {error.evalue} "
                    f"(full traceback in {executed}, cell {error.cell_index})"
                ) from None
            seconds = time.perf_counter() - start
            timings.append((name, round(seconds, 1)))
            print(f"{name}: {seconds:.1f} s", flush=True)
    write_rows([{"notebook": n, "seconds": s} for n, s in timings], output_dir / "timings.csv",
               ["notebook", "seconds"])  # fmt: skip
    return timings
