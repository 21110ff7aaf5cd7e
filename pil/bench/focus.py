"""The suite's declared focus comparisons and non-inferiority test, applied to journal rows.

:func:`focus_comparisons`: the focus entrant (``analysis.focus``, the robust rule) against
each declared opponent in each declared (track, condition): paired t and Wilcoxon
(:func:`pil.experiments.stats.paired`: mean difference and Hodges-Lehmann shift, each with its
95 % interval, and Cohen's d_z), entrant - opponent in actions. One Holm family per test whose
size is the declared number of comparisons (:attr:`pil.bench.declared.Focus.size`): what did
not run counts as p = 1, so a comparison's Holm p never shrinks because less ran.

:func:`noninferiority`: the entrant against its anchor per declared condition, one-sided
(:func:`pil.bench.equivalence.noninferior_paired`), and the claim over all conditions
(intersection-union: it holds when every condition's test does, so its p is the largest).

In both a failed run counts at the cap (:func:`capped`: the track's cap x the run's scripted
gestures, in actions) instead of dropping its pair; ``at_cap`` says how many runs did.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from pil.bench.equivalence import noninferior_paired
from pil.bench.suite import Suite
from pil.experiments.stats import PAIRED_T, WILCOXON, holm, paired

FOCUS = "focus"  # the ``family`` of focus rows in tests.csv (the anchors' rows: ``anchors``)
NONINFERIORITY_COLUMNS = (
    "track",
    "entrant",
    "anchor",
    "condition",
    "n",
    "at_cap",
    "margin",
    "mean_diff",
    "upper",
    "statistic",
    "p",
    "noninferior",
    "note",
)


def capped(suite: Suite, row: Mapping[str, Any]) -> tuple[float, bool]:
    """A run's primary metric, or the cap (the track's cap x its scripted gestures) for a
    failed run; and whether it was capped."""
    value = float(row[suite.primary])
    if row.get("failed") or math.isnan(value):
        return suite.cap_of(str(row["track"])) * float(row["scripted"]), True
    return value, False


def _capped_pairs(
    suite: Suite, rows: Sequence[Mapping[str, Any]], a: str, b: str, track: str, condition: str
) -> tuple[list[float], list[float], int]:
    """a's and b's values on their common seeds (seed order), failed runs at the cap, and how
    many runs were counted at the cap."""
    by: dict[str, dict[int, tuple[float, bool]]] = {a: {}, b: {}}
    for r in rows:
        if r["track"] == track and r["condition"] == condition and r["agent"] in by:
            by[str(r["agent"])][int(r["seed"])] = capped(suite, r)
    seeds = sorted(set(by[a]) & set(by[b]))
    at_cap = sum(by[a][s][1] + by[b][s][1] for s in seeds)
    return [by[a][s][0] for s in seeds], [by[b][s][0] for s in seeds], at_cap


def focus_comparisons(suite: Suite, rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """The declared focus family (module docstring); [] when the suite declares none or its
    entrant did not run."""
    focus = suite.focus
    if focus is None or not any(r["agent"] == focus.entrant for r in rows):
        return []
    out: list[dict[str, Any]] = []
    ran = {(str(r["agent"]), str(r["track"]), str(r["condition"])) for r in rows}
    for opponent in focus.against:
        for track, condition in focus.cells:
            if {(focus.entrant, track, condition), (opponent, track, condition)} - ran:
                continue  # did not run: counts as p = 1 through the declared size
            a, b, at_cap = _capped_pairs(suite, rows, focus.entrant, opponent, track, condition)
            for result in paired(a, b):
                if at_cap:
                    why = f"{at_cap} failed run(s) counted at the cap"
                    result["note"] = "; ".join(x for x in (result["note"], why) if x)
                out.append(
                    {
                        "track": track,
                        "entrant": focus.entrant,
                        "anchor": opponent,
                        "condition": condition,
                        "measure": suite.primary,
                        "family": FOCUS,
                        "dropped": 0,
                        "at_cap": at_cap,
                        **result,
                    }
                )
    for test in (PAIRED_T, WILCOXON):
        members = [r for r in out if r["test"] == test]
        adjusted = holm([r["p"] for r in members], size=focus.size)
        for r, p in zip(members, adjusted, strict=True):
            r["p_holm"] = p
            r["family_size"] = focus.size
    return out


def noninferiority(suite: Suite, rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """The declared non-inferiority test per condition and over all of them (module
    docstring); [] when the suite declares none or its entrant did not run."""
    test = suite.noninferiority
    if test is None or not any(r["agent"] == test.entrant for r in rows):
        return []
    head = {"track": test.track, "entrant": test.entrant, "anchor": test.anchor}
    out = []
    for condition in test.conditions:
        a, b, at_cap = _capped_pairs(suite, rows, test.entrant, test.anchor, test.track, condition)
        if not a:
            continue
        found = noninferior_paired(a, b, test.margin, suite.alpha)
        if at_cap:
            why = f"{at_cap} failed run(s) counted at the cap"
            found["note"] = "; ".join(x for x in (found["note"], why) if x)
        out.append(
            {
                **head,
                "condition": condition,
                "at_cap": at_cap,
                **found,
                "noninferior": "yes" if found["p"] < suite.alpha else "no",
            }
        )
    if out:
        done = [r["condition"] for r in out]
        ps = [r["p"] for r in out]
        worst = math.nan if any(math.isnan(p) for p in ps) else max(ps)
        complete = len(done) == len(test.conditions) and not math.isnan(worst)
        out.append(
            {
                **head,
                "condition": "all",
                "n": sum(r["n"] for r in out),
                "at_cap": sum(r["at_cap"] for r in out),
                "margin": test.margin,
                "p": worst,
                "noninferior": "yes" if complete and worst < suite.alpha else "no",
                "note": "intersection-union: the largest p of the conditions"
                + ("" if complete else "; not every condition ran"),
            }
        )
    return out
