"""Is an image motion-blurred? The blur score, the detector and its calibration."""

from __future__ import annotations

import numpy as np

from .features import blur_features
from .length_model import analysis_length

#: The detector's classes, by recorded blur extent (px): frames with at least BLURRED_FROM_PX are
#: blurred; frames under SHARP_BELOW_PX (too little blur for deblurring to help) count as sharp,
#: beside the sharp renders; frames in between are left out of calibration.
BLURRED_FROM_PX = 3.0
SHARP_BELOW_PX = 1.5


def calibrate_blur_threshold(
    scores: np.ndarray, blurred: np.ndarray, sharp_groups: np.ndarray | None = None
) -> float:
    r"""The threshold on blur scores that maximises balanced accuracy on labelled examples.

    .. math::

        \hat{t} = \arg\max_t \; \tfrac{1}{2}\Bigl( \frac{|\{i \in B : s_i > t\}|}{|B|}
        + \frac{1}{G} \sum_{g=1}^{G} \frac{|\{i \in S_g : s_i \le t\}|}{|S_g|} \Bigr)

    over cuts t midway between consecutive scores, for blurred examples B and sharp groups
    :math:`S_g` (one group when ``sharp_groups`` is None); exact ties go to the lowest cut.

    Parameters
    ----------
    scores : numpy.ndarray
        (N,) blur scores (:func:`blur_score`).
    blurred : numpy.ndarray
        (N,) bool, True for blurred examples; both classes must be present.
    sharp_groups : numpy.ndarray, optional
        (N,) group of each example (read for the sharp ones only). When given, the share of sharp
        examples passed is the mean over the groups of each group's share, so that a small group
        (frames with a little blur) counts as much as a large one (sharp renders).

    Returns
    -------
    float
        The threshold, px.

    Raises
    ------
    ValueError
        If only one class is present.

    References
    ----------
    Brodersen, Ong, Stephan and Buhmann, "The balanced accuracy and its posterior distribution",
    ICPR 2010.
    Not in the paper (it deblurs every frame); the detector stands before eq. 4 in Section
    III.A.1.
    """
    scores, blurred = np.asarray(scores, float), np.asarray(blurred, bool)
    if blurred.all() or not blurred.any():
        raise ValueError("calibration needs both blurred and sharp examples")
    groups = np.zeros(len(scores), int) if sharp_groups is None else np.asarray(sharp_groups)
    sharp_sets = [scores[~blurred & (groups == g)] for g in np.unique(groups[~blurred])]
    candidates = np.sort(scores)
    cuts = (candidates[:-1] + candidates[1:]) / 2

    def share_at_or_below(values: np.ndarray) -> np.ndarray:
        return np.searchsorted(np.sort(values), cuts, side="right") / len(values)

    flagged = 1.0 - share_at_or_below(scores[blurred])
    passed = np.mean([share_at_or_below(group) for group in sharp_sets], axis=0)
    balanced = np.round(flagged + passed, 12)  # exact ties go to the lowest cut
    return float(cuts[int(np.argmax(balanced))])


def detection_rates(
    scores: np.ndarray, blurred: np.ndarray, threshold: float
) -> tuple[float, float, float]:
    r"""How a threshold on blur scores separates blurred from sharp frames.

    .. math::

        \text{flagged} = \frac{|\{i \in B : s_i > t\}|}{|B|}, \quad
        \text{passed} = \frac{|\{i \notin B : s_i \le t\}|}{N - |B|}, \quad
        \text{balanced} = \frac{\text{flagged} + \text{passed}}{2}

    Parameters
    ----------
    scores : numpy.ndarray
        (N,) blur scores (:func:`blur_score`).
    blurred : numpy.ndarray
        (N,) bool, True for frames that are blurred; both classes must be present.
    threshold : float
        Frames scoring above it are flagged as blurred.

    Returns
    -------
    flagged, passed, balanced : float
        Share of blurred frames flagged (sensitivity), share of sharp frames passed
        (specificity), and their mean (balanced accuracy).

    References
    ----------
    Brodersen, Ong, Stephan and Buhmann, "The balanced accuracy and its posterior distribution",
    ICPR 2010.
    Not in the paper (it deblurs every frame); the detector stands before eq. 4 in Section
    III.A.1.
    """
    scores, blurred = np.asarray(scores, float), np.asarray(blurred, bool)
    flagged = float((scores[blurred] > threshold).mean())
    passed = float((scores[~blurred] <= threshold).mean())
    return flagged, passed, (flagged + passed) / 2


#: Estimated length (px at the analysis scale) above which :func:`detect_blur` calls an image
#: blurred, and at or below which the estimator reports it sharp. Chosen by
#: :func:`calibrate_blur_threshold` on the stand-in's training examples at 160x120 and 640x480
#: (frames with >= BLURRED_FROM_PX of blur against sharp renders and frames under
#: SHARP_BELOW_PX, each of the two sharp groups counted equally; notebook 01 recomputes it).
BLUR_THRESHOLD = 2.47


def blur_score(image: np.ndarray) -> float:
    r"""Blur score of an image: its coarse blind blur length at the analysis scale.

    .. math::

        s(b) = \hat{L}(b)

    the length of :func:`~blurloc.blur.analysis_length` on :func:`blur_features` (without the
    sinc refinement of :func:`~blurloc.blur.estimate_motion_blur`): px of the image's copy with a
    short side of at most ANALYSIS_SIDE px, so that the score measures blur against the size of
    the whole image (a 160x120 frame is its own copy; 4 px of blur in a 640x480 frame score 2).
    It grows with blur and is about 0 for sharp frames.

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) image, uint8 or float in [0, 1]; short side >= MIN_ANALYSIS_SIDE px.

    Returns
    -------
    float
        The score, px at the analysis scale (>= 0).

    Raises
    ------
    ValueError
        If a side is under MIN_ANALYSIS_SIDE px.

    References
    ----------
    Yitzhaky and Kopeika, "Identification of blur parameters from motion blurred images", CVGIP
    1997. The paper's Section III.A.1 (is the image blurred?).
    """
    return analysis_length(blur_features(image))


def detect_blur(image: np.ndarray, threshold: float = BLUR_THRESHOLD) -> tuple[bool, float]:
    r"""Whether an image is motion-blurred, and its blur score.

    .. math::

        \text{blurred} \iff s(b) > t

    with s the estimated blur length (:func:`blur_score`) and t the threshold.

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) image, uint8 or float in [0, 1]; short side >= MIN_ANALYSIS_SIDE px.
    threshold : float
        t, px at the analysis scale (default BLUR_THRESHOLD, calibrated by
        :func:`calibrate_blur_threshold`).

    Returns
    -------
    blurred : bool
        True when the score exceeds the threshold.
    score : float
        The score, px at the analysis scale.

    References
    ----------
    The paper's Section III.A.1 and Fig. 3 (blurred frames are detected, then deblurred).
    """
    score = blur_score(image)
    return score > threshold, score
