"""pil.experiments.equivalence: TOST behind any "as costly as"."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import ttest_rel
from statsmodels.stats.weightstats import ttost_paired

from pil.experiments.equivalence import tost_paired


def test_tost_p_is_statsmodels_and_the_90_interval_decides():
    rng = np.random.default_rng(0)
    base = rng.normal(300, 20, 20)
    near = base + rng.normal(0.5, 2.0, 20)
    found = tost_paired(near, base, margin=5.0)
    assert found.p == pytest.approx(ttost_paired(near, base, -5.0, 5.0)[0])
    assert found.equivalent and -5 < found.ci_low < found.ci_high < 5
    spread = np.array([-12.0, 6.0, -9.0, 3.0, -3.0, 4.0, -10.0, 2.0, -8.0, -3.0])  # mean -3
    far = base[:10] + spread  # not significantly different (p 0.15), nor shown equivalent
    assert ttest_rel(far, base[:10]).pvalue > 0.1
    off = tost_paired(far, base[:10], margin=5.0)
    assert not off.equivalent and off.ci_low < -5 and off.verdict() == "not shown equivalent"


def test_no_spread_is_untestable_and_a_margin_must_be_positive():
    assert math.isnan(tost_paired([1.0, 2.0], [1.0, 2.0], 5.0).p)
    with pytest.raises(ValueError, match="margin"):
        tost_paired([1.0, 2.0], [1.0, 3.0], 0.0)
