"""Equivalence by two one-sided tests (TOST) on paired samples: "no worse than" needs one.

:func:`tost_paired` tests whether the mean paired difference a - b lies inside
(-margin, +margin) (``statsmodels.stats.weightstats.ttost_paired``): its p is the larger of
the two one-sided p-values, so p < alpha supports equivalence within the margin. A
non-significant difference test is never read as equivalence. ``noninferior_p`` is the
one-sided test of a - b < +margin alone (a is no worse than b by more than the margin, for a
lower-is-better measure). :func:`noninferior_paired` is that one-sided test on its own, with
the one-sided upper bound of the mean difference (``statsmodels`` ``DescrStatsW``).
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from typing import Any


def tost_paired(a: Sequence[float], b: Sequence[float], margin: float) -> dict[str, Any]:
    """TOST of the paired a - b against the margin; NaN where it cannot be computed."""
    from statsmodels.stats.weightstats import ttost_paired

    diffs = [x - y for x, y in zip(a, b, strict=True)]
    out = {"n": len(diffs), "margin": margin, "tost_p": math.nan, "noninferior_p": math.nan}
    if len(diffs) < 2 or statistics.stdev(diffs) == 0:
        if len(diffs) >= 2:  # a constant difference: inside or outside for certain
            inside = abs(diffs[0]) < margin
            out.update(
                tost_p=0.0 if inside else 1.0, noninferior_p=0.0 if diffs[0] < margin else 1.0
            )
        return out
    import numpy as np

    p, _lower, upper = ttost_paired(np.asarray(a, float), np.asarray(b, float), -margin, margin)
    out.update(tost_p=float(p), noninferior_p=float(upper[1]))
    return out


def noninferior_paired(
    a: Sequence[float], b: Sequence[float], margin: float, alpha: float = 0.05
) -> dict[str, Any]:
    """One-sided paired t-test of H0: mean(a - b) >= ``margin`` against H1: < ``margin`` (a is
    no worse than b by more than the margin, lower being better): the mean difference, its
    one-sided (1 - alpha) upper bound, t and p; NaN where it cannot be computed, and a
    constant difference is inside or outside for certain (p 0 or 1, no bound)."""
    from statsmodels.stats.weightstats import DescrStatsW

    diffs = [x - y for x, y in zip(a, b, strict=True)]
    out: dict[str, Any] = {
        "n": len(diffs),
        "margin": margin,
        "mean_diff": statistics.fmean(diffs) if diffs else math.nan,
        "upper": math.nan,
        "statistic": math.nan,
        "p": math.nan,
        "note": "",
    }
    if len(diffs) < 2:
        out["note"] = "fewer than two pairs: not tested"
        return out
    if statistics.stdev(diffs) == 0:
        out.update(p=0.0 if diffs[0] < margin else 1.0, note="every pair differs by the same")
        return out
    import numpy as np

    described = DescrStatsW(np.asarray(diffs, dtype=float))
    t, p, _df = described.ttest_mean(margin, alternative="smaller")
    _low, upper = described.tconfint_mean(alpha, alternative="smaller")
    out.update(upper=float(upper), statistic=float(t), p=float(p))
    return out
