"""The leaderboard's parts for suite 1.2: dose-response tables, the focus family, the
non-inferiority test, and the marks of failed and stalled runs.

* :func:`dose_levels` / :func:`dose_tables`: a track whose conditions are named
  ``<component>-<percent>`` (``silence-5``) with one other condition as its 0 % level (``d80``)
  is shown as one table per component, its levels as columns.
* :func:`focus_section`: the suite's focus entrant against each opponent in each declared
  cell (Holm over the declared family), and its non-inferiority test.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from pil.bench.suite import Suite
from pil.experiments.report import markdown_table
from pil.experiments.stats import PAIRED_T

DOSE_NAME = re.compile(r"^([a-z]+)-(\d+)$")  # silence-5: component silence at 5 %


def number_text(value: float | None, spec: str = ".1f") -> str:
    """A number for a cell ("–" for none)."""
    return "–" if value is None or math.isnan(value) else format(value, spec)


def p_text(value: float) -> str:
    """A p-value for a cell, starred below 0.05."""
    if math.isnan(value):
        return "–"
    star = " *" if value < 0.05 else ""
    return (f"{value:.2g}" if value >= 0.001 else "<0.001") + star


def marks(summary: Mapping[str, Any]) -> str:
    """`` (k✗ j⏸)``: the failed and stalled runs of a summary row ("" when none)."""
    found = []
    for key, sign in (("failed", "✗"), ("stalled", "⏸")):
        value = summary.get(key)
        if value is not None and not (isinstance(value, float) and math.isnan(value)) and value:
            found.append(f"{int(value)}{sign}")
    return f" ({' '.join(found)})" if found else ""


def dose_levels(conditions: Sequence[str]) -> dict[str, list[tuple[int, str]]]:
    """Per component, its (percent, condition) levels from 0 % up, when ``conditions`` are a
    dose-response ({} otherwise: fewer than two dosed names or not exactly one base)."""
    dosed = {c: DOSE_NAME.match(c) for c in conditions}
    base = [c for c, m in dosed.items() if m is None]
    if len(base) != 1 or len(dosed) - 1 < 2:
        return {}
    out: dict[str, list[tuple[int, str]]] = {}
    for c, m in dosed.items():
        if m is not None:
            out.setdefault(m.group(1), [(0, base[0])]).append((int(m.group(2)), c))
    return {k: sorted(v) for k, v in out.items()}


def dose_tables(
    dose: Mapping[str, list[tuple[int, str]]],
    agents: Sequence[str],
    cell: Callable[[str, str], str],
) -> list[str]:
    """One table per component: agents as rows, its levels (0 %: the base) as columns."""
    out: list[str] = []
    for component, levels in dose.items():
        header = [
            "agent",
            *(f"{pct} %" + (f" ({name})" if not pct else "") for pct, name in levels),
        ]
        rows = [[a, *(cell(a, name) for _pct, name in levels)] for a in agents]
        named = ", ".join(f"`{name}`" for pct, name in levels if pct)
        out += ["", f"**{component}** alone ({named}):", "", markdown_table(header, rows)]
    return out[1:]


def focus_section(suite: Suite, found: Mapping[str, list[dict]]) -> list[str]:
    """The focus family and the non-inferiority test ([] when the focus entrant did not run)."""
    focus = suite.focus
    tests = [t for t in found["tests"] if t.get("family") == "focus" and t["test"] == PAIRED_T]
    if focus is None or not tests:
        return []
    by = {(t["anchor"], t["track"], t["condition"]): t for t in tests}
    cells = [c for c in focus.cells if any((o, *c) in by for o in focus.against)]
    body = []
    for track, condition in cells:
        row = [f"{condition} ({track})"]
        for opponent in focus.against:
            t = by.get((opponent, track, condition))
            row.append("" if t is None else _difference(t))
        body.append(row)
    wins = sum(t["p_holm"] < suite.alpha and t["mean_diff"] < 0 for t in tests)
    losses = sum(t["p_holm"] < suite.alpha and t["mean_diff"] > 0 for t in tests)
    out = [
        "",
        f"## {focus.entrant} against every reference under noisy thumbs",
        "",
        f"Declared in advance (`analysis.focus`): {focus.entrant} − opponent in actions, paired "
        "by seed, a failed run counted at the cap (its track's cap x its scripted gestures) "
        "instead of dropping its pair; mean difference [95 % CI] and Holm-adjusted paired-t p "
        f"over the declared family of {focus.size} comparisons per test (* < {suite.alpha:g}). "
        f"Of the {len(tests)} that ran, {focus.entrant} needs fewer actions in {wins} and more "
        f"in {losses} (Holm p < {suite.alpha:g}). Wilcoxon rows, d_z and the runs counted at "
        "the cap: `tests.csv` (family focus).",
        "",
        markdown_table(["condition", *focus.against], body),
    ]
    return out + _noninferiority_part(suite, found)


def _difference(t: Mapping[str, Any]) -> str:
    low, high = number_text(t["ci_low"], "+.1f"), number_text(t["ci_high"], "+.1f")
    return f"{number_text(t['mean_diff'], '+.1f')} [{low}, {high}] {p_text(t['p_holm'])}"


def _noninferiority_part(suite: Suite, found: Mapping[str, list[dict]]) -> list[str]:
    test, rows = suite.noninferiority, found.get("noninferiority") or []
    if test is None or not rows:
        return []
    body = [
        [
            r["condition"],
            number_text(r["n"], ".0f"),
            number_text(r["at_cap"], ".0f"),
            number_text(r["mean_diff"], "+.1f"),
            number_text(r["upper"], "+.1f"),
            p_text(r["p"]),
            str(r["noninferior"]),
        ]
        for r in rows
    ]
    return [
        "",
        f"Non-inferiority with right thumbs (`analysis.noninferiority`): is {test.entrant} no "
        f"worse than {test.anchor} by more than {test.margin:g} actions on {test.track}? "
        f"One-sided paired t of H0: mean({test.entrant} − {test.anchor}) ≥ {test.margin:g} "
        "(statsmodels), failed runs at the cap; the upper bound is one-sided 95 %; `all` "
        "holds when every condition does (its p is the largest).",
        "",
        markdown_table(
            ["condition", "pairs", "at cap", "mean diff", "upper bound", "p", "no worse"], body
        ),
    ]
