"""Proactive vs reactive PIL: gestures saved and actions wasted per rate, t-tests, a figure.

Both systems learn from scratch on the same handover order and detector deck (common random
numbers), so repetition ``r`` of ``pil`` and of ``proactive`` differ only by the anticipations.
Per repetition: *gestures saved* = pil's gestures - proactive's gestures (the anticipations the
person let happen save one each, and a changed course of learning may save or cost more);
*actions wasted* = anticipations the person stopped. The p-values are the study's paired
t-tests (by repetition, Holm-adjusted; :mod:`pil.experiments.study_tests`) of the two systems'
gestures and actions on the test tables.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.experiments.paper import BASELINE
from pil.experiments.report import Row, group_rows, markdown_table, mean_sd, number
from pil.experiments.stats import PAIRED_T
from pil.experiments.study_tests import TEST_TABLES, study_tests

PROACTIVE = "proactive"


def _by_rep(rows: Sequence[Row], system: str) -> dict[str, Row]:
    return {str(r["rep"]): r for r in rows if str(r["system"]) == system}


def proactive_figures(
    rows: Sequence[Row], tests: Sequence[Mapping[str, Any]] | None = None
) -> list[dict[str, float]]:
    """Per rate (both systems present): means and sds of the comparison, with the
    Holm-adjusted paired p-values of ``tests`` (:func:`study_tests` rows; by default those
    of ``rows``)."""
    tests = study_tests(rows) if tests is None else tests
    rows = [r for r in rows if str(r["system"]) in (BASELINE, PROACTIVE)]
    if not rows or {str(r["system"]) for r in rows} != {BASELINE, PROACTIVE}:
        return []
    p_of = {
        (str(t["rate"]), t["measure"]): float(t["p_holm"])
        for t in tests
        if t["system_b"] == PROACTIVE and t["reading"] == TEST_TABLES and t["test"] == PAIRED_T
    }
    out = []
    for (rate,), members in group_rows(rows, ["rate"]).items():
        base, pro = _by_rep(members, BASELINE), _by_rep(members, PROACTIVE)
        reps = sorted(set(base) & set(pro), key=int)

        def col(side: dict[str, Row], name: str, reps: list[str] = reps) -> list[float]:
            return [number(side[k][name], name) for k in reps]

        saved = [b - p for b, p in zip(col(base, "gestures"), col(pro, "gestures"), strict=True)]
        wasted = [
            a - k for a, k in zip(col(pro, "anticipated"), col(pro, "anticipated_ok"), strict=True)
        ]
        entry: dict[str, float] = {"rate": number(rate, "rate"), "n": float(len(reps))}
        for name, values in (
            ("pil_gestures", col(base, "gestures")),
            ("gestures", col(pro, "gestures")),
            ("saved", saved),
            ("anticipated", col(pro, "anticipated")),
            ("let_happen", col(pro, "anticipated_ok")),
            ("wasted", wasted),
            ("pil_actions", col(base, "actions")),
            ("actions", col(pro, "actions")),
        ):
            entry[f"{name}_mean"], entry[f"{name}_sd"] = mean_sd(values)
        entry["p_gestures"] = p_of.get((rate, "gestures"), math.nan)
        entry["p_actions"] = p_of.get((rate, "actions"), math.nan)
        out.append(entry)
    return out


def _p(p: float) -> str:
    return "n/a" if math.isnan(p) else f"{p:.3g}{' *' if p < 0.05 else ''}"


def proactive_markdown(figures: Sequence[dict[str, float]]) -> str:
    """The summary's table of :func:`proactive_figures` (mean ± sd; p < 0.05 marked *)."""

    def ms(entry: dict[str, float], name: str) -> str:
        return f"{entry[f'{name}_mean']:.1f} ± {entry[f'{name}_sd']:.1f}"

    header = [
        "rate",
        "n",
        "gestures pil",
        "gestures proactive",
        "gestures saved",
        "anticipated",
        "let happen",
        "actions wasted",
        "actions pil",
        "actions proactive",
        "p gestures",
        "p actions",
    ]
    names = (
        "pil_gestures",
        "gestures",
        "saved",
        "anticipated",
        "let_happen",
        "wasted",
        "pil_actions",
        "actions",
    )
    body = [
        [
            f"{e['rate']:g}",
            int(e["n"]),
            *(ms(e, n) for n in names),
            _p(e["p_gestures"]),
            _p(e["p_actions"]),
        ]
        for e in figures
    ]
    return markdown_table(header, body)


def plot_proactive(figures: Sequence[dict[str, float]], path: str | Path) -> Path:
    """Bars per rate: gestures saved and actions wasted (mean ± sd over repetitions)."""
    from pil.experiments.plotting import finish_figure, pyplot

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4))
    x = list(range(len(figures)))
    width = 0.38
    bars = (
        (-width / 2, "saved", "gestures saved (pil - proactive)"),
        (width / 2, "wasted", "actions wasted (stopped anticipations)"),
    )
    for shift, name, label in bars:
        ax.bar(
            [i + shift for i in x],
            [e[f"{name}_mean"] for e in figures],
            width,
            yerr=[e[f"{name}_sd"] for e in figures],
            capsize=3,
            label=label,
        )
    ax.set_xticks(x, [f"{e['rate'] * 100:.0f} %" for e in figures])
    ax.set_xlabel("detection rate")
    ax.set_ylabel("per run (test tables)")
    ax.axhline(0.0, color="black", linewidth=0.6)
    ax.set_title("Proactive vs reactive PIL (mean ± sd)")
    ax.legend()
    return finish_figure(plt, fig, None, path)
