"""A study's report (``robin-pil report STUDY_DIR``): what was analysed and the analysis.

Which data count: participants who declined or were withdrawn are left out (the registry says
who); practice blocks never count; a block's measures count when the block is ``finished``
(every leg handed over), as in the sessions report; every answered questionnaire counts. The
outcomes are the blocks' measures (:data:`pil.experiments.sessions_load.MEASURES`) and every
questionnaire score, each analysed by :func:`pil.experiments.study_analysis.analyse` with the
design of the study. ``study.md`` says it in words and tables; ``study_tests.csv``,
``study_models.csv`` and ``study_order.csv`` hold the numbers. Paths are relative to the study
folder. Pure Python: no MuJoCo.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.experiments.answers_file import read_answers
from pil.experiments.report import markdown_table
from pil.experiments.sessions_load import COUNTED_STATUS, MEASURES
from pil.experiments.study_analysis import analyse
from pil.experiments.study_export import EXCLUDED, study_blocks
from pil.file_names import QUESTIONNAIRES_NAME

STUDY_TEST_COLUMNS = (
    "instrument",
    "outcome",
    "a",
    "b",
    "design",
    "test",
    "n",
    "mean_a",
    "mean_b",
    "mean_diff",
    "ci_low",
    "ci_high",
    "effect",
    "effect_size",
    "statistic",
    "p",
    "p_holm",
    "w",
    "p_w",
    "p_w_holm",
)
MODEL_COLUMNS = ("instrument", "outcome", "formula", "term", "coef", "se", "ci_low", "ci_high", "p")
ORDER_COLUMNS = ("instrument", "outcome", "condition", "position", "n", "mean", "sd")


def study_outcomes(
    folder: Path, participants: Sequence[Mapping[str, Any]]
) -> dict[tuple[str, str], list[dict[str, Any]]]:
    """(instrument, variable) -> observations (participant, group, condition, position, value)."""
    outcomes: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for block in study_blocks(folder, participants):
        if block["practice"] or block["block"] is None:
            continue
        head = {k: block[k] for k in ("participant", "group", "condition")}
        head["position"] = block["block"]
        if block["block_status"] == COUNTED_STATUS:
            for measure in MEASURES:
                value = block["summary"].get(measure)
                if isinstance(value, int | float) and not isinstance(value, bool):
                    outcomes.setdefault(("blocks", measure), []).append({**head, "value": value})
        for entry in read_answers(block["path"] / QUESTIONNAIRES_NAME):
            for score, value in entry.get("scores", {}).items():
                key = (str(entry.get("questionnaire")), str(score))
                outcomes.setdefault(key, []).append({**head, "value": value})
    return outcomes


def study_markdown(
    name: str,
    design: str,
    participants: Sequence[Mapping[str, Any]],
    result: Mapping[str, list[dict[str, Any]]],
    attention: Sequence[str] = (),
) -> str:
    """``study.md``."""
    included = [p for p in participants if p.get("status") not in EXCLUDED]
    left_out = [p for p in participants if p.get("status") in EXCLUDED]
    groups = sorted({str(p.get("group")) for p in included})
    lines = [
        f"# Study {name}: the analysis",
        "",
        f"Design: **{design}**. {len(included)} participants analysed"
        + (f" (groups: {', '.join(groups)})" if design != "within" else "")
        + f"; {len(left_out)} left out: "
        + (", ".join(f"{p['id']} ({p['status']})" for p in left_out) or "none")
        + ". Practice blocks never count; a block's measures count when it is "
        f"`{COUNTED_STATUS}`; every answered questionnaire counts.",
        "",
        "A participant's value in a condition is the mean of their blocks in it. Pairs of "
        "conditions that two or more participants did both are compared within subjects "
        "(paired t and Wilcoxon signed-rank, d_z); others between subjects (Welch's t, "
        "Cohen's d). Mean difference a - b with its 95 % CI; p Holm-adjusted over each "
        "instrument's tests (the blocks' measures; each questionnaire); p < 0.05 marked *.",
        "",
    ]
    if attention:
        lines += ["Attention checks failed: " + ", ".join(attention) + " (kept in the data).", ""]
    lines += ["## Pairwise tests", ""]
    lines.append(
        markdown_table(
            [
                "instrument",
                "outcome",
                "a",
                "b",
                "design",
                "n",
                "mean (a)",
                "mean (b)",
                "a - b [95 % CI]",
                "effect",
                "test",
                "p (Holm)",
                "Wilcoxon p (Holm)",
            ],
            [
                [
                    t["instrument"],
                    t["outcome"],
                    t["a"],
                    t["b"],
                    t["design"],
                    t["n"],
                    _f(t["mean_a"]),
                    _f(t["mean_b"]),
                    _diff(t),
                    f"{t['effect']} {_f(t['effect_size'])}",
                    t["test"],
                    f"{_p(t['p'])} ({_p(t['p_holm'])})",
                    f"{_p(t['p_w'])} ({_p(t['p_w_holm'])})",
                ]
                for t in result["tests"]
            ],
        )
        if result["tests"]
        else "No pair of conditions to compare."
    )
    lines += ["", "## Mixed models (participant as a random intercept)", ""]
    lines += _model_lines(result["models"])
    lines += ["## Order effects (mean by block position)", ""]
    lines.append(
        markdown_table(
            ["instrument", "outcome", "condition", "position", "n", "mean ± sd"],
            [
                [
                    o["instrument"],
                    o["outcome"],
                    o["condition"],
                    o["position"],
                    o["n"],
                    _f(o["mean"]) + ("" if math.isnan(o["sd"]) else f" ± {_f(o['sd'])}"),
                ]
                for o in result["order"]
            ],
        )
        if result["order"]
        else "No analysed block."
    )
    return "\n".join(lines) + "\n"


def _model_lines(models: Sequence[Mapping[str, Any]]) -> list[str]:
    """The mixed models: how each was fitted, then every fixed effect in one table."""
    if not models:
        return ["Not called for: a within design with one block per condition.", ""]
    fits = []
    for m in models:
        if "error" in m:
            fitted = f"not fitted: {m['error']}"
        else:
            notes = "; ".join(m["notes"]) or "none"
            fitted = (
                f"variance: participants {_f(m['participant_variance'])}, residual "
                f"{_f(m['residual_variance'])}; converged {m['converged']}; warnings: {notes}"
            )
        fits.append(
            [
                m["instrument"],
                m["outcome"],
                f"`{m['formula']}`",
                f"{m['observations']} / {m['participants']}",
                fitted,
            ]
        )
    effects = [
        [
            m["instrument"],
            m["outcome"],
            e["term"],
            _f(e["coef"]),
            _f(e["se"]),
            f"[{_f(e['ci_low'])}, {_f(e['ci_high'])}]",
            _p(e["p"]),
        ]
        for m in models
        for e in m.get("effects", ())
    ]
    lines = [
        "statsmodels `MixedLM` (REML); the condition terms are differences to the first "
        "condition, `position` the change per block (the order effect).",
        "",
        markdown_table(["instrument", "outcome", "model", "blocks / participants", "fit"], fits),
        "",
    ]
    if effects:
        lines += [
            markdown_table(
                ["instrument", "outcome", "term", "coef", "se", "95 % CI", "p"], effects
            ),
            "",
        ]
    return lines


def attention_failures(folder: Path, participants: Sequence[Mapping[str, Any]]) -> list[str]:
    """``participant (session: item)`` for every attention check answered wrong."""
    failed = []
    for block in study_blocks(folder, participants):
        for entry in read_answers(block["path"] / QUESTIONNAIRES_NAME):
            for item, passed in entry.get("attention", {}).items():
                if not passed:
                    failed.append(f"{block['participant']} ({block['session']}: {item})")
    return failed


def write_study_report(
    folder: Path,
    name: str,
    design: str,
    conditions: Sequence[str],
    participants: Sequence[Mapping[str, Any]],
    out: Path,
) -> list[Path]:
    """Analyse the study and write ``study.md`` and its CSVs to ``out``; their paths."""
    from pil.atomic import write_text_atomic
    from pil.experiments.sweep_store import rows_to_csv

    result = analyse(study_outcomes(folder, participants), design, conditions)
    models = [
        {**{k: m[k] for k in MODEL_COLUMNS[:3]}, **e}
        for m in result["models"]
        for e in m.get("effects", ())
    ]
    text = study_markdown(
        name, design, participants, result, attention_failures(folder, participants)
    )
    return [
        write_text_atomic(out / "study.md", text),
        write_text_atomic(
            out / "study_tests.csv", rows_to_csv(result["tests"], STUDY_TEST_COLUMNS)
        ),
        write_text_atomic(out / "study_models.csv", rows_to_csv(models, MODEL_COLUMNS)),
        write_text_atomic(out / "study_order.csv", rows_to_csv(result["order"], ORDER_COLUMNS)),
    ]


def _f(value: Any) -> str:
    return (
        "n/a"
        if value is None or (isinstance(value, float) and math.isnan(value))
        else f"{value:.2f}"
    )


def _p(value: float) -> str:
    return "n/a" if math.isnan(value) else f"{value:.3g}{' *' if value < 0.05 else ''}"


def _diff(row: Mapping[str, Any]) -> str:
    if math.isnan(row["mean_diff"]):
        return "n/a"
    if math.isnan(row["ci_low"]):
        return _f(row["mean_diff"])
    return f"{_f(row['mean_diff'])} [{_f(row['ci_low'])}, {_f(row['ci_high'])}]"
