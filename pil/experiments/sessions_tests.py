"""The live sessions' tests: each pair of conditions on each measure, within one scenario and
protocol, with the mean difference, its 95 % CI, an effect size and Holm's correction.

Within-subject designs (some participant did more than one condition) get paired t-tests over
the participants who did both conditions of a pair (effect size Cohen's d_z); between-subject
designs get Welch's t-test (Cohen's d, pooled sd). The family Holm corrects over is declared by
the design, not by what came out testable: every pair of the group's conditions on every
measure of :data:`MEASURES`, one family per scenario and protocol; an untestable comparison
(too few participants, no spread) has no p-value and leaves the family smaller. The tests
themselves come from :mod:`pil.experiments.stats` (scipy and statsmodels).
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping, Sequence
from itertools import combinations
from typing import Any

from pil.experiments.sessions_load import MEASURES

SESSION_TEST_COLUMNS = [
    "scenario",
    "protocol",
    "test",
    "measure",
    "a",
    "b",
    "n",
    "mean_a",
    "mean_b",
    "mean_diff",
    "ci_low",
    "ci_high",
    "effect_size",
    "t",
    "p",
    "p_holm",
]


def conditions_of(rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """The conditions in registry order (pil, c1, ..., proactive), unknown ones after, by name."""
    from pil.task.systems import SYSTEM_SPECS

    known = list(SYSTEM_SPECS)
    names = {str(r["condition"]) for r in rows}
    return sorted(names, key=lambda n: (known.index(n) if n in known else len(known), n))


def participant_means(
    rows: Sequence[Mapping[str, Any]], measure: str
) -> dict[str, dict[str, float]]:
    """condition -> participant -> the mean of their counted sessions' ``measure`` values."""
    values: dict[str, dict[str, list[float]]] = {}
    for row in rows:
        if row["counted"] and row[measure] is not None and not math.isnan(row[measure]):
            by = values.setdefault(row["condition"], {})
            by.setdefault(row["participant"], []).append(float(row[measure]))
    return {c: {p: statistics.fmean(v) for p, v in by.items()} for c, by in values.items()}


def is_within(rows: Sequence[Mapping[str, Any]]) -> bool:
    """True when some participant has counted sessions in more than one condition."""
    seen: dict[str, set[str]] = {}
    for row in rows:
        if row["counted"]:
            seen.setdefault(row["participant"], set()).add(row["condition"])
    return any(len(c) > 1 for c in seen.values())


def group_tests(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """The tests of one scenario and protocol's rows, Holm-corrected as one family."""
    from pil.experiments.stats import holm, paired, welch

    within = is_within(rows)
    results = []
    for a, b in combinations(conditions_of([r for r in rows if r["counted"]]), 2):
        for measure in MEASURES:
            means = participant_means(rows, measure)
            in_a, in_b = means.get(a, {}), means.get(b, {})
            if within:
                both = sorted(set(in_a) & set(in_b))
                xs, ys = [in_a[p] for p in both], [in_b[p] for p in both]
                n: Any = len(both)
                test = paired(xs, ys)[0]
            else:
                xs, ys = list(in_a.values()), list(in_b.values())
                n = f"{len(xs)}/{len(ys)}"
                test = welch(xs, ys)
            testable = not math.isnan(test["p"])
            results.append(
                {
                    "test": "paired" if within else "welch",
                    "measure": measure,
                    "a": a,
                    "b": b,
                    "n": n,
                    "mean_a": statistics.fmean(xs) if xs else math.nan,
                    "mean_b": statistics.fmean(ys) if ys else math.nan,
                    "mean_diff": test["mean_diff"],
                    "ci_low": test["ci_low"] if testable else math.nan,
                    "ci_high": test["ci_high"] if testable else math.nan,
                    "effect_size": test["effect_size"] if testable else math.nan,
                    "t": test["statistic"],
                    "p": test["p"],
                }
            )
    for result, adjusted in zip(results, holm([r["p"] for r in results]), strict=True):
        result["p_holm"] = adjusted
    return results
