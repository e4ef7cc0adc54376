"""Paired comparisons with their uncertainty: the interval of a mean paired difference, and
the verdict it supports.

Two configurations (e.g. a pose regressor fed blurred vs deblurred frames) are run on the same
units (scene x seed pairs); their per-unit differences are what is compared, so that what the
two runs share (the scene's difficulty, the seed's luck) cancels.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats


@dataclass(frozen=True)
class Interval:
    """A mean paired difference and its confidence interval.

    Attributes
    ----------
    mean : float
        Mean of the paired differences (b - a).
    low, high : float
        Bounds of the confidence interval of the mean.
    pairs : int
        Number of paired differences.
    level : float
        Confidence level, e.g. 0.95.
    method : str
        ``"t"`` (Student t-interval) or ``"bootstrap"`` (percentile bootstrap over pairs).
    """

    mean: float
    low: float
    high: float
    pairs: int
    level: float
    method: str

    @property
    def half_width(self) -> float:
        """Half the interval's width: the resolution of the comparison."""
        return 0.5 * (self.high - self.low)


def paired_interval(
    differences: np.ndarray,
    level: float = 0.95,
    method: str = "bootstrap",
    resamples: int = 10_000,
    seed: int = 0,
) -> Interval:
    """Confidence interval of the mean of paired differences.

    Parameters
    ----------
    differences : numpy.ndarray
        Per-pair differences (N,), e.g. error with deblurred input minus error with blurred
        input for each scene x seed pair. NaNs are not allowed.
    level : float
        Confidence level in (0, 1).
    method : {"bootstrap", "t"}
        ``"bootstrap"``: percentile bootstrap (:func:`scipy.stats.bootstrap`), resampling
        the pairs with replacement ``resamples`` times from a seeded generator and taking
        the ``(1 - level) / 2`` and ``(1 + level) / 2`` quantiles of the resampled means;
        ``"t"``: Student t-interval of the mean
        (:meth:`scipy.stats.ttest_1samp` ``.confidence_interval``),

        .. math:: \\bar d \\pm t_{(1 + \\text{level}) / 2,\\, N - 1} \\, s / \\sqrt{N}.
    resamples : int
        Bootstrap resamples.
    seed : int
        Seed of the bootstrap's generator (the same seed gives the same interval).

    Returns
    -------
    Interval

    Raises
    ------
    ValueError
        If fewer than two differences are given, any is not finite, or ``method``/``level``
        is unknown or out of range.
    """
    values = np.asarray(differences, float).ravel()
    if values.size < 2 or not np.all(np.isfinite(values)):
        raise ValueError(f"need at least two finite paired differences, got {values.tolist()}")
    if not 0.0 < level < 1.0:
        raise ValueError(f"level must lie in (0, 1), got {level}")
    if method == "t":
        bounds = stats.ttest_1samp(values, 0.0).confidence_interval(level)
    elif method == "bootstrap":
        bounds = stats.bootstrap(
            (values,),
            np.mean,
            n_resamples=resamples,
            confidence_level=level,
            method="percentile",
            rng=np.random.default_rng(seed),
        ).confidence_interval
    else:
        raise ValueError(f"method must be 'bootstrap' or 't', got {method!r}")
    low, high = bounds.low, bounds.high
    mean = float(values.mean())
    return Interval(mean, float(low), float(high), int(values.size), level, method)


def verdict(interval: Interval, claimed_sign: int = -1) -> str:
    """The verdict an interval supports on a claimed direction of the difference.

    Parameters
    ----------
    interval : Interval
        The interval of the mean paired difference (b - a).
    claimed_sign : {-1, 1}
        The direction the claim predicts: -1 when b should be lower than a (e.g. "deblurring
        lowers the pose error"), +1 when higher.

    Returns
    -------
    str
        ``"reproduced"`` when the whole interval lies on the claimed side of zero,
        ``"contradicted"`` when it lies wholly on the other side, otherwise
        ``"too small to resolve at this power (±x)"`` with the interval's half width.
    """
    if claimed_sign not in (-1, 1):
        raise ValueError(f"claimed_sign must be -1 or 1, got {claimed_sign}")
    low, high = claimed_sign * interval.low, claimed_sign * interval.high
    if min(low, high) > 0:
        return "reproduced"
    if max(low, high) < 0:
        return "contradicted"
    return f"too small to resolve at this power (±{interval.half_width:.3g})"
