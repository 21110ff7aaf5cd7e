"""Comparisons between systems as a reviewer expects them: the test that matches the design.

Where two systems ran with the same seeds (a study's repetitions share the handover order and
the detector deck), their samples are *paired* by a key such as ``rep``: the paired t-test
(``scipy.stats.ttest_rel``) and the Wilcoxon signed-rank test (``scipy.stats.wilcoxon``; counts
are not normal) are run on the differences of the complete pairs (a failed run drops its pair
only). Where the design does not pair, Welch's test (``scipy.stats.ttest_ind(equal_var=False)``)
is used and the output says so. Every result has an estimate with its own 95 % interval (the
mean difference for t-tests, the Hodges-Lehmann shift for Wilcoxon: :func:`hodges_lehmann`),
an effect size (Cohen's d_z paired, d with the pooled sd unpaired) and a Holm-adjusted p over
its declared family (:func:`pair_family`; ``statsmodels.stats.multitest.multipletests``).
Differences without spread are tested by neither test (``note`` says so). :func:`mean_ci`
gives the 95 % interval of a mean over independent seeds. Equivalence ("as costly as"):
:mod:`pil.experiments.equivalence`.

Rows are mappings of column name to value (numbers, or strings read back from a CSV).
"""

from __future__ import annotations

import math
import statistics
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from pil.experiments.hodges_lehmann import hodges_lehmann
from pil.experiments.report import ReportError, Row, check_columns, group_rows, number, sort_key
from pil.experiments.stats_text import describe_tests as describe_tests
from pil.experiments.stats_text import tests_markdown as tests_markdown

CONFIDENCE = 0.95
PAIRED_T = "paired t"
WILCOXON = "wilcoxon signed-rank"
WELCH = "welch t"
UNPAIRED = "none"
MEAN = "mean"
HODGES_LEHMANN = "hodges-lehmann"

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
    "estimator",
    "estimate",
    "note",
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
    """Mean and its t-based confidence interval (NaN bounds for fewer than two values and
    for constant values: no spread gives no interval, never a zero-width one)."""
    from scipy.stats import ttest_1samp  # imported here: scipy is slow to import

    values = [float(v) for v in values]
    if not values:
        return math.nan, math.nan, math.nan
    mean = statistics.fmean(values)
    if len(values) < 2:
        return mean, math.nan, math.nan
    if len(set(values)) == 1:
        return mean, math.nan, math.nan
    ci = ttest_1samp(values, 0.0).confidence_interval(confidence)
    return mean, float(ci.low), float(ci.high)


#: the ``note`` of a comparison whose every pair differs by the same amount: neither the
#: t-test nor the Wilcoxon test has a spread to work on, so both are left out (no p, no
#: interval) and the family does not count it; ``mean_diff`` still says how large it is
CONSTANT_NOTE = "every pair differs by the same amount: not tested"
NO_DIFFERENCE_NOTE = "no pair differs: not tested"


def paired(a: Sequence[float], b: Sequence[float]) -> list[dict[str, Any]]:
    """Paired t-test and Wilcoxon signed-rank test of ``a`` against ``b`` (same order = same
    pair). Both carry ``mean_diff`` (a - b) and Cohen's d_z; each carries its own estimate
    and interval: the mean with its t interval, the Hodges-Lehmann shift with the interval
    the signed-rank test inverts. Differences without spread (constant, or all zero) leave
    both tests out alike, with a ``note``; no zero-width interval is given as a 95 % CI."""
    from scipy.stats import ttest_rel, wilcoxon

    diffs = [x - y for x, y in zip(a, b, strict=True)]
    n = len(diffs)
    mean = statistics.fmean(diffs) if diffs else math.nan
    sd = statistics.stdev(diffs) if n > 1 else math.nan
    note = ""
    if n > 1 and not sd > 0:
        note = CONSTANT_NOTE if mean != 0 else NO_DIFFERENCE_NOTE
    elif n < 2:
        note = "fewer than two pairs: not tested"
    common = {
        "n": n,
        "mean_diff": mean,
        "effect_size": mean / sd if sd and sd > 0 else math.nan,
        "note": note,
    }
    t_row = {
        "test": PAIRED_T,
        "statistic": math.nan,
        "p": math.nan,
        "estimator": MEAN,
        "estimate": mean,
        "ci_low": math.nan,
        "ci_high": math.nan,
    }
    w_row = {**t_row, "test": WILCOXON, "estimator": HODGES_LEHMANN}
    if not note:
        with warnings.catch_warnings():  # nearly constant differences: p is still valid
            warnings.filterwarnings("ignore", "Precision loss", RuntimeWarning)
            test = ttest_rel(a, b)
        ci = test.confidence_interval(CONFIDENCE)
        t_row.update(
            statistic=float(test.statistic),
            p=float(test.pvalue),
            ci_low=float(ci.low),
            ci_high=float(ci.high),
        )
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", category=UserWarning)  # small n: exact / ties
            w_test = wilcoxon(a, b)
        estimate, low, high = hodges_lehmann(diffs, CONFIDENCE)
        w_row.update(
            statistic=float(w_test.statistic),
            p=float(w_test.pvalue),
            estimate=estimate,
            ci_low=low,
            ci_high=high,
        )
    return [{**t_row, **common}, {**w_row, **common}]


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
        "estimator": MEAN,
        "estimate": mean,
        "note": "no spread: not tested",
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
                note="",
            )
    return out


def holm(pvalues: Sequence[float], size: int | None = None) -> list[float]:
    """Holm-adjusted p-values; NaN entries (untestable comparisons) stay NaN. Without
    ``size`` they do not count towards the family's size. ``size``: the family's declared
    size, Holm's multiplier: every declared comparison without a p (NaN here, or not among
    ``pvalues`` at all) counts as p = 1, so no adjusted p shrinks because less ran or less
    could be tested.

    The step-down of ``statsmodels.stats.multitest.multipletests(method="holm")`` (a test
    checks they agree), computed here: statsmodels runs a full garbage collection on every
    call, which costs seconds over a table's hundreds of small families."""
    present = sorted((p, i) for i, p in enumerate(pvalues) if not math.isnan(p))
    adjusted = [math.nan] * len(pvalues)
    m = max(len(present), size or 0)
    running = 0.0
    for rank, (p, i) in enumerate(present):
        running = max(running, min(1.0, (m - rank) * p))
        adjusted[i] = running
    return adjusted


def _pairs(a_rows: Sequence[Row], b_rows: Sequence[Row], pair_by: Sequence[str]):
    """The two groups' rows matched one-to-one by ``pair_by`` (only the keys both have: a
    failed run drops its pair, never the pairing), or None where nothing pairs them (no key
    columns, a key that repeats within a group, or no key in common)."""
    if not pair_by or any(c not in r for r in (*a_rows, *b_rows) for c in pair_by):
        return None
    keyed_a = {tuple(str(r[c]) for c in pair_by): r for r in a_rows}
    keyed_b = {tuple(str(r[c]) for c in pair_by): r for r in b_rows}
    if len(keyed_a) != len(a_rows) or len(keyed_b) != len(b_rows):
        return None
    common = keyed_a.keys() & keyed_b.keys()
    if not common:
        return None
    keys = sorted(common, key=lambda k: [sort_key(v) for v in k])
    return [(keyed_a[k], keyed_b[k]) for k in keys]


def pair_family(result: Mapping[str, Any]) -> tuple[Any, ...]:
    """The default family: one test and reading of one pair of systems (every ``within``
    group and measure of it). Declared by the pair, not built from what else ran, so a
    comparison's Holm p is the same whichever other systems ran."""
    return (result["test"], result["reading"], result["system_a"], result["system_b"])


def compare(
    rows: Sequence[Row],
    baseline: str,
    *,
    compare_by: str = "system",
    within: Sequence[str] = ("rate",),
    metrics: Sequence[str | Measure] = ("total_gestures", "total_actions"),
    pair_by: Sequence[str] = ("rep",),
    family: Callable[[Mapping[str, Any]], Any] | None = None,
    family_sizes: Mapping[Any, int] | None = None,
) -> list[dict[str, Any]]:
    """``baseline`` against every other value of ``compare_by``, for each ``within`` group
    and each metric: paired t and Wilcoxon where the rows pair by ``pair_by`` (inside the
    ``within`` group; a run missing from one side drops that pair only), Welch where the
    design does not pair. Holm's correction runs over each family: by default
    :func:`pair_family` (one test and reading of one pair of systems), so what else ran
    never changes a comparison's p; ``family_sizes`` declares a family's size where some of
    its comparisons may be missing (:func:`holm`'s ``size``).

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
                    dropped = len(base_rows) + len(other_rows) - 2 * len(pairs)
                    if dropped:
                        why = f"{dropped} run(s) without a partner left out"
                        found = [
                            {**f, "note": "; ".join(x for x in (f["note"], why) if x)}
                            for f in found
                        ]
                else:
                    a = [number(r[m.column], m.column) for r in base_rows]
                    b = [number(r[m.column], m.column) for r in other_rows]
                    pairing = UNPAIRED
                    found = [welch(a, b)]
                results += [{**head, **f, "pairing": pairing} for f in found]
    family = family or pair_family
    families: dict[Any, list[int]] = {}
    for i, r in enumerate(results):
        families.setdefault(family(r), []).append(i)
    for name, indices in families.items():
        size = (family_sizes or {}).get(name)
        found_p = holm([results[i]["p"] for i in indices], size)
        for i, adjusted in zip(indices, found_p, strict=True):
            results[i]["p_holm"] = adjusted
    columns = [*LEADING_COLUMNS, *within, *TRAILING_COLUMNS]
    return [{c: r[c] for c in columns} for r in results]


def csv_columns(within: Sequence[str] = ("rate",)) -> list[str]:
    """The column order of ``tests.csv`` for results compared within ``within``."""
    return [*LEADING_COLUMNS, *within, *TRAILING_COLUMNS]
