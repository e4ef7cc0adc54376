"""Settings of the synthetic stand-in (:class:`SynthConfig`) and the bounds they are checked
against."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .layout import SCENE_NAMES, SEQUENCE_COUNTS

#: Per-frame motion of the real 7-Scenes trajectories (30 fps, handheld Kinect), quoted from the
#: package's design notes (measured on the real poses; not measurable here without the dataset).
REAL_7SCENES_MOTION = {
    "step_median_m": 0.009,
    "step_p95_m": (0.015, 0.032),
    "rotation_median_deg": 0.55,
    "rotation_p95_deg": (1.1, 2.0),
}


#: Image sizes accepted, px per side (the intrinsics are 7-Scenes' scaled to the size).
MIN_SIZE, MAX_SIZE = 8, 4096
#: Longest exposure accepted, in frame intervals (1/3 s at 30 fps). Beyond it a frame's image
#: motion outgrows the 41 sub-exposure renders per frame (they would lie over 1 px apart), and at
#: 30 it would leave the trajectory's 1 s margin.
MAX_BLUR_STRENGTH = 10.0
#: Most rays per pixel side (64 a pixel).
MAX_SUPERSAMPLE = 8
#: What the scenes' surfaces are made of: "painted" (flat paint with a weak texture, strong edges
#: at objects, frames, doors, windows and bookshelves) or "photographs" (tiled photographs of
#: gravel, grass and brick: the stand-in's first look).
SCENE_CONTENTS = ("painted", "photographs")
#: The settings of the stand-in's first look (photographed surfaces, no camera model, Gaussian
#: noise of sigma 0.01 on the encoded intensities): the values that render it byte for byte.
PREVIOUS_LOOK = {
    "scene_content": "photographs",
    "exposure_gain": 1.0,
    "optics_blur_px": 0.0,
    "shot_noise": 0.0,
    "read_noise": 0.0,
    "jpeg_quality": 0,
    "noise_sigma": 0.01,
}


def is_integer(value: object) -> bool:
    """True for a Python or NumPy integer (``bool`` is not counted as one)."""
    return isinstance(value, int | np.integer) and not isinstance(value, bool)


@dataclass(frozen=True)
class SynthConfig:
    """Settings of the stand-in. ``blur_strength`` is the exposure time in frame intervals.

    The real Kinect exposes for at most one frame interval (1/30 s); at the stand-in's 160x120
    that would give about 1-2 px of blur. The default 2.2 stretches it so that blur at 160x120 is
    about as strong, relative to the image, as in strongly blurred real 7-Scenes frames at
    640x480: over the default trajectories the blur extent has a median of about 3 px and a
    90th percentile of about 5 px (notebook 00 measures it).

    Every field is checked on construction; a ValueError names the field and its ``blurloc
    synth`` option: width and height in [MIN_SIZE, MAX_SIZE] px, at least 2 frames per
    sequence, ``blur_strength`` in [0, MAX_BLUR_STRENGTH], ``noise_sigma`` in [0, 1],
    ``route_share`` in [0, 1], ``supersample`` an integer in [1, MAX_SUPERSAMPLE],
    ``scene_content`` one of SCENE_CONTENTS, ``exposure_gain`` in (0, 100], ``optics_blur_px``
    in [0, 10], ``shot_noise`` and ``read_noise`` in [0, 1], ``jpeg_quality`` an integer in
    [0, 100].

    The camera model (:mod:`~blurloc.data.camera_model`): the rendered linear light is
    multiplied by ``exposure_gain``, blurred by the optics (a Gaussian of sigma
    ``optics_blur_px``), given signal-dependent sensor noise of variance
    ``shot_noise * x + read_noise**2`` at linear signal x (photon shot noise and read noise),
    gamma-encoded, given ``noise_sigma`` of Gaussian noise on the encoded intensities, quantised
    and, with ``jpeg_quality`` > 0, JPEG-compressed at that quality. The sharp frame passes the
    same gain and optics, without noise or compression. The defaults: painted rooms, gain 0.9
    (the mean brightness of real Kinect frames), optics 0.3 px (with one ray per pixel it
    stands for the pixel's area, a 1 px box of sigma 0.29 px, and a sharp lens), shot noise 2e-4
    and read noise 0.006 (the noise sigma in the darker and the brighter halves of real Kinect
    frames at 160x120), no encoded noise, no JPEG (Kinect frames are stored losslessly); they
    are measured beside real frames by ``benchmarks/bench_realism.py``. :data:`PREVIOUS_LOOK`
    renders the first look.

    ``supersample`` is how many rays per pixel side every render of the exposure casts (their
    mean is the pixel, in linear light): a camera's pixel integrates the light over its area,
    where one ray samples the scene at the pixel's centre (jagged edges, a coarser texture
    level). The default, one ray, is the stand-in's; three (nine rays) take about nine times
    the ray casts to render.

    ``route_share`` is how much of each sequence's walk and gaze follows a route shared by all
    sequences of its scene (:func:`scene_route`), the rest being the sequence's own wander
    (each part keeps unit variance: ``share * route + sqrt(1 - share**2) * own``). People
    recording one room walk much the same way, so the test views of real 7-Scenes lie near
    training views (published regressors reach 0.1-0.3x the mean-pose error there); with
    independent sequences (``route_share`` 0) a test sequence wanders where no training
    sequence went. The default 0.9 brings the nearest training view to 0.08-0.27x the
    mean-pose error on every scene, while that error stays near the real one
    (:data:`~blurloc.data.scenes.REAL_MEAN_POSE_BASELINE`; notebook 00 measures both).
    """

    width: int = 160
    height: int = 120
    frames_per_sequence: int = 1000  # as 7-Scenes; stairs gets half (500)
    blur_strength: float = 2.2
    noise_sigma: float = 0.0  # Gaussian noise on [0, 1] gamma-encoded intensities
    route_share: float = 0.9  # part of each walk that follows the scene's shared route
    max_sample_spacing_px: float = 1.0  # sub-exposure renders at most this far apart
    fps: float = 30.0
    step_median_m: float = REAL_7SCENES_MOTION["step_median_m"]
    rotation_median_deg: float = REAL_7SCENES_MOTION["rotation_median_deg"]
    sequence_counts: dict[str, tuple[int, int]] = field(
        default_factory=lambda: dict(SEQUENCE_COUNTS)
    )
    supersample: int = 1  # rays per pixel side (1: one ray through each pixel's centre)
    scene_content: str = "painted"  # one of SCENE_CONTENTS
    exposure_gain: float = 0.9  # multiplies the rendered linear light
    optics_blur_px: float = 0.3  # sigma of the optics' Gaussian blur, px
    shot_noise: float = 2e-4  # variance of the sensor noise per unit linear signal
    read_noise: float = 0.006  # sigma of the signal-independent sensor noise, linear light
    jpeg_quality: int = 0  # JPEG quality of the stored frames (0: lossless PNG only)

    def __post_init__(self) -> None:
        for name, option in (("width", "--width"), ("height", "--height"),
                             ("frames_per_sequence", "--frames")):  # fmt: skip
            value = getattr(self, name)
            low, high = (2, None) if name == "frames_per_sequence" else (MIN_SIZE, MAX_SIZE)
            if not is_integer(value) or value < low or (high is not None and value > high):
                bounds = f">= {low}" if high is None else f"in [{low}, {high}]"
                raise ValueError(f"{name} ({option}) must be an integer {bounds}, got {value!r}")
        for name, option, high in (("blur_strength", "--blur-strength", MAX_BLUR_STRENGTH),
                                   ("noise_sigma", "--noise", 1.0),
                                   ("route_share", "--route-share", 1.0)):  # fmt: skip
            value = getattr(self, name)
            if not (np.isfinite(value) and 0 <= value <= high):
                raise ValueError(f"{name} ({option}) must be a finite number in [0, {high}], "
                                 f"got {value!r}")  # fmt: skip
        if not is_integer(self.supersample) or not 1 <= self.supersample <= MAX_SUPERSAMPLE:
            raise ValueError(f"supersample (--supersample) must be an integer in "
                             f"[1, {MAX_SUPERSAMPLE}], got {self.supersample!r}")  # fmt: skip
        if self.scene_content not in SCENE_CONTENTS:
            choices = ", ".join(SCENE_CONTENTS)
            raise ValueError(f"scene_content (--scene-content) must be one of {choices}, "
                             f"got {self.scene_content!r}")  # fmt: skip
        if not (np.isfinite(self.exposure_gain) and 0 < self.exposure_gain <= 100):
            raise ValueError(f"exposure_gain (--exposure-gain) must be a finite number in "
                             f"(0, 100], got {self.exposure_gain!r}")  # fmt: skip
        for name, option, high in (("optics_blur_px", "--optics-blur", 10.0),
                                   ("shot_noise", "--shot-noise", 1.0),
                                   ("read_noise", "--read-noise", 1.0)):  # fmt: skip
            value = getattr(self, name)
            if not (np.isfinite(value) and 0 <= value <= high):
                raise ValueError(f"{name} ({option}) must be a finite number in [0, {high}], "
                                 f"got {value!r}")  # fmt: skip
        if not is_integer(self.jpeg_quality) or not 0 <= self.jpeg_quality <= 100:
            raise ValueError(f"jpeg_quality (--jpeg-quality) must be an integer in [0, 100], "
                             f"got {self.jpeg_quality!r}")  # fmt: skip
        for name in ("max_sample_spacing_px", "fps", "step_median_m", "rotation_median_deg"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
        for scene, counts in self.sequence_counts.items():
            if (
                scene not in SCENE_NAMES
                or len(counts) != 2
                or not all(is_integer(n) and n >= 1 for n in counts)
            ):
                raise ValueError(f"sequence_counts[{scene!r}] must be (train, test) counts >= 1 "
                                 f"of one of {', '.join(SCENE_NAMES)}, got {counts!r}")  # fmt: skip

    @classmethod
    def quick(cls, **overrides) -> SynthConfig:
        """Tiny settings for CI: one training and one test sequence of 8 frames per scene."""
        counts = {name: (1, 1) for name in SCENE_NAMES}
        return replace(cls(frames_per_sequence=8, sequence_counts=counts), **overrides)

    @classmethod
    def previous_look(cls, **overrides) -> SynthConfig:
        """The default settings with the stand-in's first look (:data:`PREVIOUS_LOOK`)."""
        return cls(**{**PREVIOUS_LOOK, **overrides})

    def frames_for(self, scene: str) -> int:
        """Frames per sequence of ``scene`` (stairs sequences are half as long)."""
        return (
            max(2, self.frames_per_sequence // 2) if scene == "stairs" else self.frames_per_sequence
        )
