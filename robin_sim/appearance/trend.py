"""Does adapting gain more the longer the session runs? A test, not a reading of the means.

Per person, on the adapted runs: the gain of each table is the adapted model's detection rate
minus the shipped model's on the very same views. Per run the gain's least-squares slope over
the tables is one sample; the slopes are tested against 0 (one-sample t-test) and the last
table's gain against the first's (paired t by run). ``trend.csv`` holds one row per person.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping, Sequence
from typing import Any

TREND_COLUMNS: tuple[str, ...] = (
    "person",
    "runs",
    "tables",
    "slope_mean",
    "slope_ci_low",
    "slope_ci_high",
    "slope_p",
    "first_gain",
    "last_gain",
    "last_minus_first",
    "last_minus_first_p",
)


def _slope(points: Sequence[tuple[float, float]]) -> float:
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in points) / sxx if sxx else math.nan


def trend_rows(tables: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """One row per person (:data:`TREND_COLUMNS`) from ``appearance_tables.csv`` rows."""
    from scipy.stats import ttest_1samp, ttest_rel

    runs: dict[str, dict[str, list[tuple[float, float]]]] = {}
    for t in tables:
        shipped = str(t.get("shipped_detection_rate", ""))
        if str(t["classifier"]) != "adapted" or shipped in ("", "None", "nan"):
            continue
        gain = float(t["detection_rate"]) - float(shipped)
        runs.setdefault(str(t["person"]), {}).setdefault(str(t["rep"]), []).append(
            (float(t["table"]), gain)
        )
    out = []
    for person, by_rep in runs.items():
        series = [sorted(points) for points in by_rep.values() if len(points) > 1]
        slopes = [_slope(s) for s in series]
        first = [s[0][1] for s in series]
        last = [s[-1][1] for s in series]
        row: dict[str, Any] = {
            "person": person,
            "runs": len(series),
            "tables": max((len(s) for s in series), default=0),
            "slope_mean": statistics.fmean(slopes) if slopes else math.nan,
            "first_gain": statistics.fmean(first) if first else math.nan,
            "last_gain": statistics.fmean(last) if last else math.nan,
        }
        row["last_minus_first"] = row["last_gain"] - row["first_gain"]
        low = high = p = p_last = math.nan
        if len(slopes) > 1 and statistics.stdev(slopes) > 0:
            test = ttest_1samp(slopes, 0.0)
            ci = test.confidence_interval(0.95)
            low, high, p = float(ci.low), float(ci.high), float(test.pvalue)
        if len(first) > 1 and statistics.stdev([b - a for a, b in zip(first, last, strict=True)]):
            p_last = float(ttest_rel(last, first).pvalue)
        row.update(slope_ci_low=low, slope_ci_high=high, slope_p=p, last_minus_first_p=p_last)
        out.append({k: round(v, 6) if isinstance(v, float) else v for k, v in row.items()})
    return out
