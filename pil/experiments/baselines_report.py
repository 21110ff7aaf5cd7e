"""The baseline table's files: ``baselines.csv``, ``tuning.csv``, ``tests.csv``,
``equivalence.csv`` and ``summary.md`` (:func:`write_outputs`) from a
:class:`pil.experiments.baselines.BaselineResult`."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.experiments.baseline_equivalence import EQUIVALENCE_COLUMNS as EQ_COLUMNS
from pil.experiments.baseline_equivalence import equivalence_markdown, equivalence_rows
from pil.experiments.baseline_grid import CRITERION, at_edge, grid
from pil.experiments.baselines import (
    RUN_COLUMNS,
    TUNING_COLUMNS,
    BaselineConfig,
    BaselineResult,
    baseline_tests,
)
from pil.experiments.equivalence import ACTION_MARGIN
from pil.experiments.report import csv_text, markdown_table, summary_markdown
from pil.experiments.stats import csv_columns, describe_tests


def tuning_rows(result: BaselineResult) -> list[dict[str, Any]]:
    """One row per tuning setting: its means and whether it was chosen."""
    out = []
    for learner, found in result.scores.items():
        for s in found:
            out.append(
                {
                    "learner": learner,
                    "setting": s.setting.name,
                    "params": s.setting.describe(),
                    "runs": s.runs,
                    "stuck": s.stuck,
                    "mean_total_actions": round(s.actions, 3),
                    "sd_total_actions": round(s.actions_sd, 3),
                    "mean_total_gestures": round(s.gestures, 3),
                    "chosen": s is result.best[learner],
                }
            )
    return out


def _cell(r: Mapping[str, Any]) -> str:
    if math.isnan(r["p_holm"]):
        return f"{r['mean_diff']:+.1f} (no spread)"
    star = " *" if r["p_holm"] < 0.05 else ""
    return (
        f"{r['mean_diff']:+.1f} [{r['ci_low']:+.1f}, {r['ci_high']:+.1f}] p={r['p_holm']:.2g}{star}"
    )


def _matrix(tests: Sequence[Mapping[str, Any]], measure: str, rates: Sequence[float]) -> str:
    cells: dict[tuple[str, str], dict[float, str]] = {}
    for r in tests:
        if r["measure"] == measure and r["test"] == "paired t":
            cells.setdefault((r["system_a"], r["system_b"]), {})[float(r["rate"])] = _cell(r)
    body = [[a, b, *(row.get(rate, "") for rate in rates)] for (a, b), row in cells.items()]
    return markdown_table(["a", "b", *(f"{rate:g}" for rate in rates)], body)


def summary_text(result: BaselineResult, config: BaselineConfig, tests: Sequence[Any]) -> str:
    """``summary.md``: tuning, the table's means, and the paired tests against PIL."""
    rates = sorted({float(r["rate"]) for r in result.rows})
    tuning_body = [
        [
            r["learner"],
            r["setting"] + (" (chosen)" if r["chosen"] else ""),
            r["runs"],
            r["stuck"],
            f"{r['mean_total_actions']:.1f} ± {r['sd_total_actions']:.1f}",
            f"{r['mean_total_gestures']:.1f}",
        ]
        for r in tuning_rows(result)
    ]
    chosen = ", ".join(f"{k}: {v.setting.name}" for k, v in result.best.items())
    parts = [
        "# Baselines: tuned on held-out seeds, paired against PIL under every exploration rule",
        "",
        f"Rates {', '.join(f'{r:g}' for r in config.rates)}; master seed {config.seed}; "
        f"parameters {dict(config.params or {}) or 'the defaults'}. Tuning: every setting on "
        f"{config.tuning_reps} held-out repetitions (seed branch disjoint from the evaluation "
        f"seeds, checked); evaluation: {config.reps} repetitions, the seeds of "
        f"`robin-pil study --seed {config.seed}`. Best setting per learner = fewest mean "
        f"`{CRITERION}` over all tuning runs (ties: fewer gestures). Chosen: {chosen}.",
        "",
        "`+memory`: the within-step memory on (`step_memory=on`, `pil.step_memory`: a refused "
        "action is not tried again in the step until all five were refused). `default`: the "
        "registry's defaults (PIL memory off, the baselines' on).",
        "",
        "## Tuning (held-out seeds), mean ± sd over rates and repetitions",
        "",
        "`stuck`: runs with a step that found no approved action within "
        "`max_actions_per_gesture` actions (without the memory a greedy learner can keep "
        "choosing refused actions); each counts in the mean at the cap (every scripted "
        "gesture × `max_actions_per_gesture`): the means are over every run. " + _edges(result),
        "",
        markdown_table(
            ["learner", "setting", "runs", "stuck", "total actions", "total gestures"], tuning_body
        ),
        "",
        "## Evaluation seeds: mean ± sd per variant and rate",
        "",
        summary_markdown(result.rows, ("rate", "variant"), ("total_actions", "total_gestures")),
        "",
        "## Paired tests against PIL",
        "",
        describe_tests(tests)
        + " (In this table Holm's family is one test and measure of one pair over the "
        "rates, declared, so what else ran never changes it.) Cells: a − b (baseline − PIL, "
        "negative: the baseline needs "
        "fewer; the last rows: with − without the memory, tuned − default), 95 % CI, "
        "Holm-adjusted paired-t p; Wilcoxon in `tests.csv`.",
        "",
        "### Total actions",
        "",
        _matrix(tests, "total_actions", rates),
        "",
        "### Total gestures",
        "",
        _matrix(tests, "total_gestures", rates),
        "",
        f"## Equivalence (TOST, ±{ACTION_MARGIN:g} total actions)",
        "",
        "A non-significant difference is not equivalence. Two one-sided paired t-tests "
        "(`statsmodels` `ttost_paired`) per rate and averaged over the rates (each "
        "repetition's mean); `equivalent` when both reject at 0.05 (the 90 % CI inside the "
        'margin). Only those rows may be read as "as costly as" (`equivalence.csv`).',
        "",
        equivalence_markdown(equivalence_rows(result.rows)),
    ]
    return "\n".join(parts) + "\n"


def _edges(result: BaselineResult) -> str:
    """A sentence naming any chosen value at the edge of its grid."""
    notes = []
    for learner, best in result.best.items():
        edge = at_edge(best.setting, grid(learner))
        if edge:
            notes.append(f"{learner} ({', '.join(edge)})")
    if not notes:
        return "Every chosen value lies inside its grid."
    return (
        "Chosen values at the edge of their grid: "
        + "; ".join(notes)
        + " (epsilon = 0 and step size 1 are the ends of the valid ranges)."
    )


def write_outputs(result: BaselineResult, config: BaselineConfig, out: str | Path) -> list[Path]:
    """Write ``baselines.csv``, ``tuning.csv``, ``tests.csv`` and ``summary.md`` to ``out``."""
    out = Path(out)
    tests = baseline_tests(result.rows)
    return [
        write_text_atomic(out / "baselines.csv", csv_text(result.rows, RUN_COLUMNS)),
        write_text_atomic(out / "tuning.csv", csv_text(tuning_rows(result), TUNING_COLUMNS)),
        write_text_atomic(out / "tests.csv", csv_text(tests, csv_columns(("rate",)))),
        write_text_atomic(
            out / "equivalence.csv", csv_text(equivalence_rows(result.rows), EQ_COLUMNS)
        ),
        write_text_atomic(out / "summary.md", summary_text(result, config, tests)),
    ]
