"""Which baseline is *as costly as* PIL: TOST on the baseline table's total actions.

Each baseline variant against each PIL variant, per rate and averaged over the rates (each
repetition's mean over the rates: one paired sample per repetition), with the margin
:data:`pil.experiments.equivalence.ACTION_MARGIN`. Only a row whose verdict is
``equivalent`` may be worded "as costly as"; a non-significant t-test is not enough.
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence
from typing import Any

from pil.experiments.equivalence import ACTION_MARGIN, tost_paired
from pil.experiments.report import markdown_table

EQUIVALENCE_COLUMNS: tuple[str, ...] = (
    "system_a",
    "system_b",
    "rate",
    "n",
    "margin",
    "mean_diff",
    "ci90_low",
    "ci90_high",
    "p_tost",
    "verdict",
)
ALL_RATES = "all"
MEASURE = "total_actions"


def _by_rep(rows: Sequence[Mapping[str, Any]], variant: str) -> dict[str, dict[str, float]]:
    out: dict[str, dict[str, float]] = {}
    for r in rows:
        if r["variant"] == variant:
            out.setdefault(str(r["rate"]), {})[str(r["rep"])] = float(r[MEASURE])
    return out


def equivalence_rows(
    rows: Sequence[Mapping[str, Any]], margin: float = ACTION_MARGIN
) -> list[dict[str, Any]]:
    """TOST rows (:data:`EQUIVALENCE_COLUMNS`) of every baseline variant against every PIL
    variant."""
    variants = list(dict.fromkeys(str(r["variant"]) for r in rows))
    pil = [v for v in variants if v.startswith("pil:")]
    out: list[dict[str, Any]] = []
    for a in (v for v in variants if v not in pil):
        mine = _by_rep(rows, a)
        for b in pil:
            theirs = _by_rep(rows, b)
            rates = [r for r in mine if r in theirs]
            samples = {
                rate: sorted(mine[rate].keys() & theirs[rate].keys(), key=int) for rate in rates
            }
            for rate in rates:
                keys = samples[rate]
                found = tost_paired(
                    [mine[rate][k] for k in keys], [theirs[rate][k] for k in keys], margin
                )
                out.append(_row(a, b, rate, found))
            common = (
                sorted(set.intersection(*(set(samples[r]) for r in rates)), key=int)
                if rates
                else []
            )
            if len(rates) > 1 and common:
                x = [statistics.fmean(mine[r][k] for r in rates) for k in common]
                y = [statistics.fmean(theirs[r][k] for r in rates) for k in common]
                out.append(_row(a, b, ALL_RATES, tost_paired(x, y, margin)))
    return out


def _row(a: str, b: str, rate: str, found: Any) -> dict[str, Any]:
    return {
        "system_a": a,
        "system_b": b,
        "rate": rate,
        "n": found.n,
        "margin": found.margin,
        "mean_diff": found.mean_diff,
        "ci90_low": found.ci_low,
        "ci90_high": found.ci_high,
        "p_tost": found.p,
        "verdict": found.verdict(),
    }


def equivalence_markdown(found: Sequence[Mapping[str, Any]]) -> str:
    """The TOST rows as a Markdown table."""
    body = [
        [
            r["system_a"],
            r["system_b"],
            r["rate"],
            f"{r['mean_diff']:+.1f} [{r['ci90_low']:+.1f}, {r['ci90_high']:+.1f}]",
            f"±{r['margin']:g}",
            f"{r['p_tost']:.2g}",
            r["verdict"],
        ]
        for r in found
    ]
    header = ["a", "b", "rate", "a − b [90 % CI]", "margin", "TOST p", "verdict"]
    return markdown_table(header, body)
