"""robin_sim.appearance.trend: the session's gain tested per run, not read off the means."""

from __future__ import annotations

import pytest
from scipy.stats import ttest_1samp

from robin_sim.appearance.trend import trend_rows


def _tables(gains: list[list[float]]) -> list[dict[str, object]]:
    rows: list[dict[str, object]] = []
    for rep, series in enumerate(gains):
        for k, gain in enumerate(series, start=1):
            rows.append(
                {
                    "person": "p",
                    "classifier": "adapted",
                    "rep": rep,
                    "table": k,
                    "detection_rate": 0.8 + gain,
                    "shipped_detection_rate": 0.8,
                }
            )
            rows.append({**rows[-1], "classifier": "fixed", "shipped_detection_rate": ""})
    return rows


def test_slopes_per_run_are_tested_against_zero() -> None:
    gains = [[0.0, 0.02, 0.04], [0.01, 0.0, 0.05], [0.0, 0.01, 0.0], [0.02, 0.03, 0.01]]
    (row,) = trend_rows(_tables(gains))
    slopes = [(s[2] - s[0]) / 2 for s in gains]  # least squares over 3 equally spaced tables
    assert row["runs"] == 4 and row["tables"] == 3
    assert row["slope_mean"] == pytest.approx(sum(slopes) / 4, abs=1e-6)
    assert row["slope_p"] == pytest.approx(ttest_1samp(slopes, 0.0).pvalue, abs=1e-6)
    assert row["last_minus_first"] == pytest.approx(0.0175, abs=1e-6)
