"""``tests.csv`` rows as Markdown: the table and the sentence that names the tests."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["describe_tests", "tests_markdown"]


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
        "estimate [95 % CI]",
        "effect",
        "p",
        "p (Holm)",
    ]
    body = []
    for r in results:
        star = " *" if not math.isnan(r["p_holm"]) and r["p_holm"] < 0.05 else ""
        spec = ".3f" if str(r["measure"]).endswith("rate") else ".1f"  # a share, or a count
        diff = f"{_fmt(float(r.get('estimate', r['mean_diff'])), spec)}" + (
            f" [{_fmt(r['ci_low'], spec)}, {_fmt(r['ci_high'], spec)}]"
            if not math.isnan(float(r["ci_low"]))
            else ""
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
        f"('none' = unpaired, Welch); Holm's correction over each test, reading and pair "
        "of systems. "
        f"{significant} of {len(testable)} testable comparisons have Holm-adjusted p < 0.05 "
        f"(marked *); {len(results) - len(testable)} are untestable (no spread). "
        "Effect: Cohen's d_z (paired) or d (Welch); estimate of a - b with its 95 % CI: the "
        "mean for t-tests, the Hodges-Lehmann shift for Wilcoxon."
    )
