"""Equivalence by two one-sided tests (TOST): what "as costly as" has to rest on.

A non-significant difference is not evidence of no difference. Two systems are called
*equivalent* within a margin ±m only when both one-sided tests reject: the mean paired
difference is above −m and below +m (``statsmodels.stats.weightstats.ttost_paired``). The
matching interval is the 90 % confidence interval of the mean difference (1 − 2α): it lies
inside ±m exactly when TOST rejects at α = 0.05.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass

ALPHA = 0.05
#: the margin of "as costly as" for robot actions per run (about 2 % of a 10-table run)
ACTION_MARGIN = 5.0


@dataclass(frozen=True)
class Equivalence:
    """A TOST result: ``p`` is the larger of the two one-sided p-values."""

    n: int
    margin: float
    mean_diff: float
    ci_low: float  # the (1 - 2 alpha) interval of the mean difference
    ci_high: float
    p: float

    @property
    def equivalent(self) -> bool:
        """Both one-sided tests reject at :data:`ALPHA` (NaN p: no)."""
        return not math.isnan(self.p) and self.p < ALPHA

    def verdict(self) -> str:
        """``equivalent``, ``not shown equivalent`` or ``untestable``."""
        if math.isnan(self.p):
            return "untestable"
        return "equivalent" if self.equivalent else "not shown equivalent"


def tost_paired(
    a: Sequence[float], b: Sequence[float], margin: float, alpha: float = ALPHA
) -> Equivalence:
    """TOST of the paired difference a − b against ±``margin`` (same order = same pair).

    Fewer than two pairs, or no spread in the differences, gives NaN p (untestable)."""
    from scipy.stats import t as t_dist
    from statsmodels.stats.weightstats import ttost_paired

    if not margin > 0:
        raise ValueError(f"margin must be a positive number, got {margin!r}")
    diffs = [float(x) - float(y) for x, y in zip(a, b, strict=True)]
    n = len(diffs)
    mean = statistics.fmean(diffs) if diffs else math.nan
    sd = statistics.stdev(diffs) if n > 1 else math.nan
    if n < 2 or not sd > 0:
        return Equivalence(n, margin, mean, math.nan, math.nan, math.nan)
    import numpy as np

    x, y = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    p, _low, _high = ttost_paired(x, y, -margin, margin)
    half = float(t_dist.ppf(1 - alpha, n - 1)) * sd / math.sqrt(n)
    return Equivalence(n, margin, mean, mean - half, mean + half, float(p))
