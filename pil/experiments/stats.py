"""Comparisons between systems as a reviewer expects them: the test that matches the design.

Where two systems ran with the same seeds (a study's repetitions share the handover order and
the detector deck), their samples are *paired* by a key such as ``rep``: the paired t-test
(``scipy.stats.ttest_rel``) and the Wilcoxon signed-rank test (``scipy.stats.wilcoxon``; counts
are not normal) are run on the differences. Where nothing pairs the samples, Welch's test
(``scipy.stats.ttest_ind(equal_var=False)``) is used and the output says so. Every result has
an effect size (mean difference with its 95 % confidence interval; Cohen's d_z for paired
samples, Cohen's d with the pooled sd for unpaired ones) and a Holm-adjusted p over its family
of comparisons (``statsmodels.stats.multitest.multipletests``). :func:`mean_ci` gives the 95 %
interval of a mean over independent seeds.

Rows are mappings of column name to value (numbers, or strings read back from a CSV).
"""

from __future__ import annotations

import math
import statistics
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from pil.experiments.report import ReportError, Row, check_columns, group_rows, number, sort_key

CONFIDENCE = 0.95
PAIRED_T = "paired t"
WILCOXON = "wilcoxon signed-rank"
WELCH = "welch t"
UNPAIRED = "none"

#: The columns of ``tests.csv``, in order; ``within`` columns (``rate`` for a study) sit
#: between ``reading`` and ``system_a``.
LEADING_COLUMNS = ("measure", "reading")
TRAILING_COLUMNS = (
    "system_a",
    "system_b",
    "test",
    "n",
    "pairing",
    "statistic",
    "p",
    "p_holm",
    "mean_diff",
    "ci_low",
    "ci_high",
    "effect_size",
)


@dataclass(frozen=True)
class Measure:
    """A results column to compare, with the name and reading it is reported under."""

    column: str
    measure: str
    reading: str = ""


def measures(
    columns: Sequence[str], readings: Mapping[str, tuple[str, str]] | None = None
) -> list[Measure]:
    """:class:`Measure` objects; ``readings`` maps a column to its (measure, reading)."""
    readings = readings or {}
    return [Measure(c, *readings.get(c, (c, ""))) for c in columns]


def mean_ci(values: Sequence[float], confidence: float = CONFIDENCE) -> tuple[float, float, float]:
    """Mean and its t-based confidence interval (NaN bounds for fewer than two values, the
    mean itself for constant values)."""
    from scipy.stats import ttest_1samp  # imported here: scipy is slow to import

    values = [float(v) for v in values]
    if not values:
        return math.nan, math.nan, math.nan
    mean = statistics.fmean(values)
    if len(values) < 2:
        return mean, math.nan, math.nan
    if len(set(values)) == 1:
        return mean, mean, mean
    ci = ttest_1samp(values, 0.0).confidence_interval(confidence)
    return mean, float(ci.low), float(ci.high)


def paired(a: Sequence[float], b: Sequence[float]) -> list[dict[str, Any]]:
    """Paired t-test and Wilcoxon signed-rank test of ``a`` against ``b`` (same order = same
    pair); both results carry the mean difference a - b, its CI and Cohen's d_z."""
    from scipy.stats import ttest_rel, wilcoxon

    diffs = [x - y for x, y in zip(a, b, strict=True)]
    n = len(diffs)
    mean = statistics.fmean(diffs) if diffs else math.nan
    sd = statistics.stdev(diffs) if n > 1 else math.nan
    effect = {
        "n": n,
        "mean_diff": mean,
        "ci_low": math.nan,
        "ci_high": math.nan,
        "effect_size": mean / sd if sd and sd > 0 else math.nan,
    }
    t_stat = t_p = w_stat = w_p = math.nan
    if n > 1 and sd > 0:
        with warnings.catch_warnings():  # nearly constant differences: p is still valid
            warnings.filterwarnings("ignore", "Precision loss", RuntimeWarning)
            test = ttest_rel(a, b)
        t_stat, t_p = float(test.statistic), float(test.pvalue)
        ci = test.confidence_interval(CONFIDENCE)
        effect["ci_low"], effect["ci_high"] = float(ci.low), float(ci.high)
    elif n > 1:  # every pair differs by the same amount: no spread, the interval is the point
        effect["ci_low"] = effect["ci_high"] = mean
    if any(d != 0 for d in diffs):
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", category=UserWarning)  # small n: exact / ties
            test = wilcoxon(a, b)
        w_stat, w_p = float(test.statistic), float(test.pvalue)
    return [
        {"test": PAIRED_T, "statistic": t_stat, "p": t_p, **effect},
        {"test": WILCOXON, "statistic": w_stat, "p": w_p, **effect},
    ]


def welch(a: Sequence[float], b: Sequence[float]) -> dict[str, Any]:
    """Welch's t-test of ``a`` against ``b`` with the mean difference a - b, its CI and
    Cohen's d (pooled sd)."""
    from scipy.stats import ttest_ind

    n_a, n_b = len(a), len(b)
    mean = statistics.fmean(a) - statistics.fmean(b) if a and b else math.nan
    out = {
        "test": WELCH,
        "n": n_a + n_b,
        "statistic": math.nan,
        "p": math.nan,
        "mean_diff": mean,
        "ci_low": math.nan,
        "ci_high": math.nan,
        "effect_size": math.nan,
    }
    if n_a > 1 and n_b > 1:
        pooled = math.sqrt(
            ((n_a - 1) * statistics.variance(a) + (n_b - 1) * statistics.variance(b))
            / (n_a + n_b - 2)
        )
        if pooled > 0:
            with warnings.catch_warnings():
                warnings.filterwarnings("ignore", "Precision loss", RuntimeWarning)
                test = ttest_ind(a, b, equal_var=False)
            ci = test.confidence_interval(CONFIDENCE)
            out.update(
                statistic=float(test.statistic),
                p=float(test.pvalue),
                ci_low=float(ci.low),
                ci_high=float(ci.high),
                effect_size=mean / pooled,
            )
    return out


def holm(pvalues: Sequence[float]) -> list[float]:
    """Holm-adjusted p-values; NaN entries (untestable comparisons) stay NaN and do not
    count towards the family's size."""
    from statsmodels.stats.multitest import multipletests

    present = [i for i, p in enumerate(pvalues) if not math.isnan(p)]
    adjusted = [math.nan] * len(pvalues)
    if present:
        _reject, corrected, _s, _b = multipletests([pvalues[i] for i in present], method="holm")
        for i, value in zip(present, corrected, strict=True):
            adjusted[i] = float(value)
    return adjusted


def _pairs(a_rows: Sequence[Row], b_rows: Sequence[Row], pair_by: Sequence[str]):
    """The two groups' rows matched one-to-one by ``pair_by``, or None if they do not match."""
    if not pair_by or any(c not in r for r in (*a_rows, *b_rows) for c in pair_by):
        return None
    keyed_a = {tuple(str(r[c]) for c in pair_by): r for r in a_rows}
    keyed_b = {tuple(str(r[c]) for c in pair_by): r for r in b_rows}
    if (
        len(keyed_a) != len(a_rows)
        or len(keyed_b) != len(b_rows)
        or keyed_a.keys() != keyed_b.keys()
    ):
        return None
    keys = sorted(keyed_a, key=lambda k: [sort_key(v) for v in k])
    return [(keyed_a[k], keyed_b[k]) for k in keys]


def compare(
    rows: Sequence[Row],
    baseline: str,
    *,
    compare_by: str = "system",
    within: Sequence[str] = ("rate",),
    metrics: Sequence[str | Measure] = ("total_gestures", "total_actions"),
    pair_by: Sequence[str] = ("rep",),
    family: Callable[[Mapping[str, Any]], Any] | None = None,
) -> list[dict[str, Any]]:
    """``baseline`` against every other value of ``compare_by``, for each ``within`` group
    and each metric: paired t and Wilcoxon where the rows pair by ``pair_by`` (inside the
    ``within`` group), Welch otherwise. Holm's correction runs over each family: by default
    the results sharing a test and a reading (one family of comparisons per question).

    Each result is a row of ``tests.csv`` (:data:`LEADING_COLUMNS`, the ``within`` columns,
    :data:`TRAILING_COLUMNS`); ``pairing`` names the key (``rep``) or says ``none``.
    """
    wanted = [m if isinstance(m, Measure) else Measure(m, m) for m in metrics]
    check_columns(rows, [compare_by, *within, *(m.column for m in wanted)])
    values = {str(r[compare_by]) for r in rows}
    if baseline not in values:
        raise ReportError(
            f"baseline {baseline!r} not found in column {compare_by!r}; valid choices: "
            + ", ".join(sorted(values, key=sort_key))
        )
    results: list[dict[str, Any]] = []
    for key, members in group_rows(rows, within).items():
        by_value = group_rows(members, [compare_by])
        base_rows = by_value.get((baseline,), [])
        for (other,), other_rows in by_value.items():
            if other == baseline or not base_rows:
                continue
            pairs = _pairs(base_rows, other_rows, pair_by)
            for m in wanted:
                head = {
                    "measure": m.measure,
                    "reading": m.reading,
                    **dict(zip(within, key, strict=True)),
                    "system_a": baseline,
                    "system_b": other,
                }
                if pairs is not None:
                    a = [number(x[m.column], m.column) for x, _ in pairs]
                    b = [number(y[m.column], m.column) for _, y in pairs]
                    pairing = "+".join(pair_by)
                    found = paired(a, b)
                else:
                    a = [number(r[m.column], m.column) for r in base_rows]
                    b = [number(r[m.column], m.column) for r in other_rows]
                    pairing = UNPAIRED
                    found = [welch(a, b)]
                results += [{**head, **f, "pairing": pairing} for f in found]
    family = family or (lambda r: (r["test"], r["reading"]))
    families: dict[Any, list[int]] = {}
    for i, r in enumerate(results):
        families.setdefault(family(r), []).append(i)
    for indices in families.values():
        for i, adjusted in zip(indices, holm([results[i]["p"] for i in indices]), strict=True):
            results[i]["p_holm"] = adjusted
    columns = [*LEADING_COLUMNS, *within, *TRAILING_COLUMNS]
    return [{c: r[c] for c in columns} for r in results]


def csv_columns(within: Sequence[str] = ("rate",)) -> list[str]:
    """The column order of ``tests.csv`` for results compared within ``within``."""
    return [*LEADING_COLUMNS, *within, *TRAILING_COLUMNS]


def _fmt(value: float, spec: str) -> str:
    return "n/a" if math.isnan(value) else format(value, spec)


def tests_markdown(results: Sequence[Mapping[str, Any]], within: Sequence[str] = ("rate",)) -> str:
    """A Markdown table of :func:`compare` results; Holm-adjusted p < 0.05 marked with *."""
    from pil.experiments.report import markdown_table

    header = [
        "measure",
        "reading",
        *within,
        "a",
        "b",
        "test",
        "n",
        "pairing",
        "mean diff [95 % CI]",
        "effect",
        "p",
        "p (Holm)",
    ]
    body = []
    for r in results:
        star = " *" if not math.isnan(r["p_holm"]) and r["p_holm"] < 0.05 else ""
        spec = ".3f" if str(r["measure"]).endswith("rate") else ".1f"  # a share, or a count
        diff = (
            f"{_fmt(r['mean_diff'], spec)} [{_fmt(r['ci_low'], spec)}, {_fmt(r['ci_high'], spec)}]"
        )
        body.append(
            [
                r["measure"],
                r["reading"] or "-",
                *(r[c] for c in within),
                r["system_a"],
                r["system_b"],
                r["test"],
                r["n"],
                r["pairing"],
                diff,
                _fmt(r["effect_size"], ".2f"),
                _fmt(r["p"], ".3g"),
                _fmt(r["p_holm"], ".3g") + star,
            ]
        )
    return markdown_table(header, body)


def describe_tests(results: Sequence[Mapping[str, Any]]) -> str:
    """One sentence naming the tests used, the pairing and the correction, with counts."""
    tests = sorted({r["test"] for r in results})
    pairings = sorted({r["pairing"] for r in results})
    testable = [r for r in results if not math.isnan(r["p_holm"])]
    significant = sum(1 for r in testable if r["p_holm"] < 0.05)
    return (
        f"Tests: {', '.join(tests)}; samples paired by {', '.join(pairings)} "
        f"('none' = unpaired, Welch); Holm's correction over each test and reading. "
        f"{significant} of {len(testable)} testable comparisons have Holm-adjusted p < 0.05 "
        f"(marked *); {len(results) - len(testable)} are untestable (no spread). "
        "Effect: Cohen's d_z (paired) or d (Welch); mean diff = a - b with its 95 % CI."
    )
