"""Figures, one function per figure, by topic; every one is drawn in the style of
:mod:`blurloc.plots.style` (applied per figure, never globally) and saved as PNG + PDF."""

from .blur import (
    plot_detection,
    plot_estimation_accuracy,
    plot_kernels,
    plot_motion_agreement,
    plot_spectra,
    plot_standin_estimation,
)
from .deconv import (
    plot_deblurring_process,
    plot_nsr_curve,
    plot_oracle_gains,
    plot_restorations,
    plot_skimage_comparison,
)
from .explore import (
    blur_spectrum_explorer,
    plot_blur_spectrum,
    plot_wiener_restoration,
    wiener_explorer,
)
from .pose import (
    plot_dose_response,
    plot_error_distributions,
    plot_pipeline,
    plot_pose_training_curves,
    plot_predicted_paths,
    plot_predicted_views,
)
from .results import (
    plot_architecture,
    plot_paired_differences,
    plot_per_scene_metric,
    plot_ratios,
)
from .standin import (
    plot_blur_histogram,
    plot_blur_pairs,
    plot_exposure,
    plot_realism,
    plot_scene_gallery,
    plot_trajectories,
)
from .style import SavedFigure, describe_figure, figure_style, save_figure, show_figure
from .video import (
    largest_difference_window,
    plot_ablation_intervals,
    plot_attention,
    plot_training_curves,
    plot_video_network,
)

__all__ = [
    "SavedFigure",
    "blur_spectrum_explorer",
    "describe_figure",
    "figure_style",
    "largest_difference_window",
    "plot_ablation_intervals",
    "plot_architecture",
    "plot_attention",
    "plot_blur_histogram",
    "plot_blur_pairs",
    "plot_blur_spectrum",
    "plot_deblurring_process",
    "plot_detection",
    "plot_dose_response",
    "plot_error_distributions",
    "plot_estimation_accuracy",
    "plot_exposure",
    "plot_kernels",
    "plot_motion_agreement",
    "plot_nsr_curve",
    "plot_oracle_gains",
    "plot_paired_differences",
    "plot_per_scene_metric",
    "plot_pipeline",
    "plot_pose_training_curves",
    "plot_predicted_paths",
    "plot_predicted_views",
    "plot_ratios",
    "plot_realism",
    "plot_restorations",
    "plot_scene_gallery",
    "plot_skimage_comparison",
    "plot_spectra",
    "plot_standin_estimation",
    "plot_training_curves",
    "plot_trajectories",
    "plot_video_network",
    "plot_wiener_restoration",
    "save_figure",
    "show_figure",
    "wiener_explorer",
]
