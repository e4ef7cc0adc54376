"""Motion blur: kernels (PSFs), the blur model (eq. 1), spectra, detection and blind estimation.

One module per job, imported here so that ``from blurloc.blur import name`` reaches them all:

- :mod:`~blurloc.blur.kernels`: linear and camera-shake kernels, the blur model of eq. 1;
- :mod:`~blurloc.blur.spectrum`: gray conversion, the log power spectrum, the noise level;
- :mod:`~blurloc.blur.features`: the spectral and gradient features the estimator reads;
- :mod:`~blurloc.blur.length_model`: the learnt model from features to blur extent;
- :mod:`~blurloc.blur.detection`: the blur score, the detector and its calibration;
- :mod:`~blurloc.blur.estimation`: blind estimation of the blur's length and angle;
- :mod:`~blurloc.blur.video_motion`: each frame's kernel from a video's own motion.

Conventions: images are float arrays in [0, 1] (or uint8), rows downwards. Angles are degrees in
[0, 180), counter-clockwise from the image's horizontal axis as displayed (y up); lengths are
pixels of the image given. A kernel is a 2-D array summing to 1 with its centre at
``(rows // 2, cols // 2)``.
"""

from .detection import (
    BLUR_THRESHOLD,
    BLURRED_FROM_PX,
    SHARP_BELOW_PX,
    blur_score,
    calibrate_blur_threshold,
    detect_blur,
    detection_rates,
)
from .estimation import SINC_AGREEMENT, SINC_MIN_PX, BlurEstimate, estimate_motion_blur
from .features import ANALYSIS_SIDE, MIN_ANALYSIS_SIDE, BlurFeatures, blur_features
from .kernels import (
    blur_image,
    centred_on_one_grid,
    check_kernel,
    kernel_to_otf,
    motion_kernel,
    shake_path,
    trajectory_kernel,
)
from .length_model import (
    LENGTH_MODEL_PATH,
    LengthModel,
    analysis_length,
    default_length_model,
    fit_length_model,
    length_from_features,
)
from .spectrum import estimate_noise_sigma, log_power_spectrum, to_gray
from .video_motion import (
    DEFAULT_EXPOSURE_SHARE,
    LOCAL_GRID,
    ExposureFit,
    LocalVideoMotion,
    VideoMotion,
    calibrate_exposure_share,
    exposure_paths,
    fit_exposure_share,
    frame_shifts,
    frame_warps,
    grid_points,
    local_motion_kernels,
    mid_exposure_shifts,
    video_motion_kernels,
)

__all__ = [
    "ANALYSIS_SIDE",
    "BLURRED_FROM_PX",
    "BLUR_THRESHOLD",
    "DEFAULT_EXPOSURE_SHARE",
    "LENGTH_MODEL_PATH",
    "LOCAL_GRID",
    "MIN_ANALYSIS_SIDE",
    "SHARP_BELOW_PX",
    "SINC_AGREEMENT",
    "SINC_MIN_PX",
    "BlurEstimate",
    "BlurFeatures",
    "ExposureFit",
    "LengthModel",
    "LocalVideoMotion",
    "VideoMotion",
    "analysis_length",
    "blur_features",
    "blur_image",
    "blur_score",
    "calibrate_blur_threshold",
    "calibrate_exposure_share",
    "centred_on_one_grid",
    "check_kernel",
    "default_length_model",
    "detect_blur",
    "detection_rates",
    "estimate_motion_blur",
    "estimate_noise_sigma",
    "exposure_paths",
    "fit_exposure_share",
    "fit_length_model",
    "frame_shifts",
    "frame_warps",
    "grid_points",
    "kernel_to_otf",
    "length_from_features",
    "local_motion_kernels",
    "log_power_spectrum",
    "mid_exposure_shifts",
    "motion_kernel",
    "shake_path",
    "to_gray",
    "trajectory_kernel",
    "video_motion_kernels",
]
