"""The study's comparisons: PIL against every other system, paired by repetition, and the
paper's claim read from those same corrected tests.

Every system and rate of one repetition runs with the repetition's seed (same handover order,
same detector deck), so the rows pair by ``rep`` and ``seed``: :func:`study_tests` runs the
paired t-test and the Wilcoxon signed-rank test (:mod:`pil.experiments.stats`) on the totals
(*training included*, as the paper's Figs. 3 and 4) and on the test tables alone, with Holm's
correction over each test and reading. :func:`claim_markdown` reads the paper's claim (at 40
and 60 % PIL needs more gestures and actions than conditions 1 and 2) from those rows.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from pil.experiments.paper import BASELINE, LOW_RATES
from pil.experiments.report import Row, markdown_table, number
from pil.experiments.stats import PAIRED_T, WILCOXON, Measure, compare, measures

CLAIM_SYSTEMS: tuple[str, ...] = ("c1", "c2")
PAIR_BY: tuple[str, ...] = ("rep", "seed")  # the compared runs of one repetition share its seed
TRAINING_INCLUDED = "training included"
TEST_TABLES = "test tables only"
#: results column -> (measure, reading) in ``tests.csv``
READINGS: dict[str, tuple[str, str]] = {
    "total_gestures": ("gestures", TRAINING_INCLUDED),
    "total_actions": ("actions", TRAINING_INCLUDED),
    "gestures": ("gestures", TEST_TABLES),
    "actions": ("actions", TEST_TABLES),
}
#: the ``--discarded`` choices: the project's (the person repeats a discarded gesture) and the
#: paper's section I (a low-confidence gesture makes an invalid state that is corrected)
DISCARD_READINGS: dict[bool, str] = {True: "repeated", False: "corrected"}


def discard_reading(repeat_discarded: Any) -> str:
    """``repeated`` or ``corrected`` for a ``repeat_discarded`` value (bool or CSV text)."""
    return DISCARD_READINGS[str(repeat_discarded) == "True"]


def study_measures(suffix: str = "") -> list[Measure]:
    """The four compared columns with their readings (``suffix`` appended to each reading)."""
    return [
        Measure(m.column, m.measure, m.reading + suffix)
        for m in measures(tuple(READINGS), READINGS)
    ]


def study_tests(rows: Sequence[Row], suffix: str = "") -> list[dict[str, Any]]:
    """PIL against every other system per rate, paired by repetition (``tests.csv`` rows);
    none without a ``pil`` row beside another system."""
    systems = {str(r["system"]) for r in rows}
    if BASELINE not in systems or len(systems) < 2:
        return []
    return compare(
        rows,
        BASELINE,
        compare_by="system",
        within=("rate",),
        metrics=study_measures(suffix),
        pair_by=PAIR_BY,
    )


def claim_rows(tests: Sequence[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    """The tests the claim rests on: PIL vs c1 and c2 at the low rates."""
    return [
        t
        for t in tests
        if t["system_a"] == BASELINE
        and t["system_b"] in CLAIM_SYSTEMS
        and number(t["rate"], "rate") in LOW_RATES
    ]


def _costlier(test: Mapping[str, Any]) -> bool:
    """PIL needs more, with Holm-adjusted p < 0.05."""
    p = float(test["p_holm"])
    return float(test["mean_diff"]) > 0 and not math.isnan(p) and p < 0.05


def claim_verdicts(tests: Sequence[Mapping[str, Any]]) -> dict[str, tuple[int, int]]:
    """Per reading: (comparisons where PIL is costlier under both the paired t-test and the
    Wilcoxon test, Holm-adjusted p < 0.05; comparisons)."""
    out: dict[str, tuple[int, int]] = {}
    by_key: dict[tuple[str, str, str, str], dict[str, Mapping[str, Any]]] = {}
    for t in claim_rows(tests):
        key = (str(t["reading"]), str(t["rate"]), str(t["measure"]), str(t["system_b"]))
        by_key.setdefault(key, {})[str(t["test"])] = t
    for (reading, *_), found in by_key.items():
        held, tried = out.get(reading, (0, 0))
        both = all(name in found and _costlier(found[name]) for name in (PAIRED_T, WILCOXON))
        out[reading] = (held + both, tried + 1)
    return out


def claim_markdown(tests: Sequence[Mapping[str, Any]], discarded: str = "") -> str:
    """The claim's comparisons (paired t and Wilcoxon, Holm-adjusted) and one verdict per
    reading; ``tests`` are :func:`study_tests` rows (the same numbers as ``tests.csv``);
    ``discarded`` names the discard reading of the rows whose reading does not."""
    chosen = [
        {**t, "reading": f"{t['reading']}; discarded {discarded}"}
        if discarded and ";" not in str(t["reading"])
        else t
        for t in claim_rows(tests)
    ]
    if not chosen:
        return "(needs pil, c1 and c2 at 40 % or 60 %)"
    pairs: dict[tuple[str, str, str, str], dict[str, Mapping[str, Any]]] = {}
    for t in chosen:
        key = (str(t["reading"]), str(t["rate"]), str(t["measure"]), str(t["system_b"]))
        pairs.setdefault(key, {})[str(t["test"])] = t
    body = []
    for (reading, rate, measure, other), found in pairs.items():
        paired_t, wil = found.get(PAIRED_T), found.get(WILCOXON)
        ref = paired_t if paired_t is not None else wil
        assert ref is not None
        yes = paired_t is not None and wil is not None and _costlier(paired_t) and _costlier(wil)
        body.append(
            [
                reading,
                f"{number(rate) * 100:.0f} %",
                measure,
                other,
                f"{float(ref['mean_diff']):+.1f} [{float(ref['ci_low']):+.1f}, "
                f"{float(ref['ci_high']):+.1f}]",
                _p(paired_t),
                _p(wil),
                "yes" if yes else "no",
            ]
        )
    table = markdown_table(
        [
            "reading",
            "rate",
            "measure",
            "vs",
            "PIL − condition [95 % CI]",
            "p paired t (Holm)",
            "p Wilcoxon (Holm)",
            "PIL costlier",
        ],
        body,
    )
    verdicts = [
        f"- {reading}: PIL costlier (both tests, Holm-adjusted p < 0.05) in {held} of {tried} "
        f"comparisons; the claim {'holds' if held == tried else 'does not hold in full'}."
        for reading, (held, tried) in claim_verdicts(chosen).items()
    ]
    return table + "\n\n" + "\n".join(verdicts)


def _p(test: Mapping[str, Any] | None) -> str:
    if test is None or math.isnan(float(test["p_holm"])):
        return "n/a"
    return f"{float(test['p_holm']):.2g}"
