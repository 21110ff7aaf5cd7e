"""The Hodges-Lehmann shift of paired differences and the interval the signed-rank test
inverts (Hollander & Wolfe): what a Wilcoxon row of ``tests.csv`` reports as its estimate."""

from __future__ import annotations

import math
from collections.abc import Sequence


def hodges_lehmann(diffs: Sequence[float], confidence: float = 0.95) -> tuple[float, float, float]:
    """The Hodges-Lehmann estimate of the paired shift (the median of the Walsh averages) and
    its distribution-free confidence interval, the one the Wilcoxon signed-rank test inverts:
    the k-th smallest and largest Walsh averages, k from the test's exact null distribution.
    NaN bounds where no interval of that confidence exists (fewer than 6 pairs at 95 %)."""
    import numpy as np

    d = np.asarray([float(x) for x in diffs], dtype=float)
    n = len(d)
    if n == 0:
        return math.nan, math.nan, math.nan
    i, j = np.triu_indices(n)
    walsh = np.sort((d[i] + d[j]) / 2.0)
    estimate = float(np.median(walsh))
    # null distribution of the signed-rank statistic: P(T = s) over the 2^n sign patterns
    dist = np.zeros(n * (n + 1) // 2 + 1)
    dist[0] = 1.0
    for rank in range(1, n + 1):
        shifted = np.zeros_like(dist)
        shifted[rank:] = dist[:-rank]
        dist = (dist + shifted) / 2.0
    below = np.cumsum(dist)  # P(T <= s)
    tail = (1.0 - confidence) / 2.0
    k = int(np.searchsorted(below, tail + 1e-12, side="right"))  # P(T <= k - 1) <= tail
    if k == 0:
        return estimate, math.nan, math.nan
    return estimate, float(walsh[k - 1]), float(walsh[len(walsh) - k])
