"""The questionnaires answered on the live page, summarised per condition with paired tests.

Each block's session folder may hold ``questionnaires.jsonl`` (one line per questionnaire the
participant answered after the block, with its scores: NASA-TLX ``raw_tlx`` = the mean of the six
ratings, Godspeed one mean per scale, a Likert questionnaire one score per item and ``mean``).
Every answered questionnaire counts, whether or not the block's task was finished: it rates the
block as the participant lived it. A participant's value in a condition is the mean over their
blocks in it; conditions are compared over the participants who rated both, with
paired t and Wilcoxon signed-rank (:func:`pil.experiments.stats.paired`, scipy), Holm-adjusted
within each questionnaire. Pure Python, scipy and statsmodels: no MuJoCo.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping, Sequence
from itertools import combinations
from pathlib import Path
from typing import Any

from pil.experiments.answers_file import read_answers
from pil.experiments.report import markdown_table
from pil.experiments.sessions_load import SessionsError  # noqa: F401 (raised by the reading)
from pil.file_names import QUESTIONNAIRES_NAME

__all__ = ["QUESTIONNAIRES_NAME", "load_answers", "paired_tests", "summarize_answers"]
SUMMARY_COLUMNS = ("questionnaire", "score", "condition", "participants", "mean", "sd")
TEST_COLUMNS = ("questionnaire", "score", "a", "b", "n", "mean_a", "mean_b", "t", "p_t", "w", "p_w")


def load_answers(folder: str | Path) -> list[dict[str, Any]]:
    """Every answered questionnaire under ``folder`` (``[]`` when none); a record that is not a
    questionnaire record, or holds a score off its scale, raises :class:`SessionsError` naming
    its file and line (:func:`pil.experiments.answers_file.read_answers`)."""
    rows = []
    for path in sorted(Path(folder).rglob(QUESTIONNAIRES_NAME)):
        file = path.relative_to(folder).as_posix()
        rows += [{**row, "file": file} for row in read_answers(path)]
    return rows


def participant_scores(rows: Sequence[Mapping[str, Any]]) -> dict[tuple[str, str], dict]:
    """(questionnaire, score) -> condition -> participant -> the mean over their blocks."""
    values: dict[tuple[str, str], dict[str, dict[str, list[float]]]] = {}
    for row in rows:
        for score, value in row["scores"].items():
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                by = values.setdefault((row["questionnaire"], score), {})
                by.setdefault(row["condition"], {}).setdefault(row["participant"], []).append(
                    float(value)
                )
    return {
        key: {c: {p: statistics.fmean(v) for p, v in people.items()} for c, people in by.items()}
        for key, by in values.items()
    }


def summarize_answers(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Per questionnaire, score and condition: participants, mean and sd (None for n = 1)."""
    out = []
    for (questionnaire, score), by in participant_scores(rows).items():
        for condition in sorted(by):
            values = list(by[condition].values())
            out.append(
                {
                    "questionnaire": questionnaire,
                    "score": score,
                    "condition": condition,
                    "participants": len(values),
                    "mean": statistics.fmean(values),
                    "sd": statistics.stdev(values) if len(values) > 1 else None,
                }
            )
    return out


def paired_tests(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Per score and pair of conditions: paired t and Wilcoxon signed-rank
    (:func:`pil.experiments.stats.paired`) over the participants who rated both, with the mean
    difference a - b, its 95 % CI, Cohen's d_z, and Holm-adjusted p over each questionnaire's
    tests (NaN where fewer than two pairs or no difference varies)."""
    from pil.experiments.stats import holm, paired

    out = []
    for (questionnaire, score), by in participant_scores(rows).items():
        for a, b in combinations(sorted(by), 2):
            both = sorted(set(by[a]) & set(by[b]))
            xs, ys = [by[a][p] for p in both], [by[b][p] for p in both]
            # one pair or none: no test, whatever its difference
            t_test, w_test = paired(xs, ys) if len(both) > 1 else (_untested(), _untested())
            out.append(
                {
                    "questionnaire": questionnaire,
                    "score": score,
                    "a": a,
                    "b": b,
                    "n": len(both),
                    "mean_a": statistics.fmean(xs) if xs else math.nan,
                    "mean_b": statistics.fmean(ys) if ys else math.nan,
                    "t": t_test["statistic"],
                    "p_t": t_test["p"],
                    "w": w_test["statistic"],
                    "p_w": w_test["p"],
                    "mean_diff": t_test.get("mean_diff", math.nan),
                    "ci_low": t_test.get("ci_low", math.nan),
                    "ci_high": t_test.get("ci_high", math.nan),
                    "d_z": t_test.get("effect_size", math.nan),
                }
            )
    for name in {r["questionnaire"] for r in out}:  # Holm within each questionnaire
        family = [r for r in out if r["questionnaire"] == name]
        for key in ("p_t", "p_w"):
            for r, adjusted in zip(family, holm([r[key] for r in family]), strict=True):
                r[f"{key}_holm"] = adjusted
    return out


def _untested() -> dict[str, float]:
    return {"statistic": math.nan, "p": math.nan}


def answers_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """``questionnaires.md``: the counting rule, the per-condition table, the paired tests."""
    people = len({r["participant"] for r in rows})
    lines = [
        "# Questionnaires",
        "",
        f"{len(rows)} questionnaires answered by {people} participants after their blocks. "
        "A participant's value in a condition is the mean over their blocks in it; every "
        "answered questionnaire counts (finished or not). NASA-TLX raw = the mean of its six "
        "ratings (0-100); Godspeed: the mean of each scale's items (1-5).",
        "",
        "## Per condition (mean ± sd over participants; no sd for n = 1)",
        "",
        markdown_table(
            ["questionnaire", "score", "condition", "n", "mean ± sd"],
            [
                [
                    s["questionnaire"],
                    s["score"],
                    s["condition"],
                    s["participants"],
                    _mean_sd(s["mean"], s["sd"]),
                ]
                for s in summarize_answers(rows)
            ],
        ),
        "",
    ]
    tests = paired_tests(rows)
    if tests:
        lines += [
            "## Paired tests (participants who rated both conditions)",
            "",
            "Paired t (`scipy.stats.ttest_rel`) and Wilcoxon signed-rank "
            "(`scipy.stats.wilcoxon`) via `pil.experiments.stats.paired`; mean difference "
            "a - b with its 95 % CI and Cohen's d_z; p Holm-adjusted within each "
            "questionnaire (statsmodels); n/a with fewer than two pairs or no varying "
            "difference; p < 0.05 marked *, raw and adjusted alike.",
            "",
            markdown_table(
                [
                    "questionnaire",
                    "score",
                    "a",
                    "b",
                    "n",
                    "mean (a)",
                    "mean (b)",
                    "a - b [95 % CI]",
                    "d_z",
                    "t",
                    "p (t, Holm)",
                    "W",
                    "p (W, Holm)",
                ],
                [
                    [
                        r["questionnaire"],
                        r["score"],
                        r["a"],
                        r["b"],
                        r["n"],
                        _number(r["mean_a"]),
                        _number(r["mean_b"]),
                        _diff(r),
                        _number(r["d_z"]),
                        _number(r["t"]),
                        f"{_p(r['p_t'])} ({_p(r['p_t_holm'])})",
                        _number(r["w"], 1),
                        f"{_p(r['p_w'])} ({_p(r['p_w_holm'])})",
                    ]
                    for r in tests
                ],
            ),
            "",
        ]
    else:
        lines += ["No paired tests: the answers hold fewer than two conditions.", ""]
    return "\n".join(lines)


def write_answers_report(
    folder: str | Path, out: str | Path, rows: Sequence[Mapping[str, Any]] | None = None
) -> list[Path]:
    """Write ``questionnaires.md`` and ``questionnaires.csv`` to ``out`` when ``folder`` holds
    answers (``rows``: those :func:`load_answers` read already); their paths (none written
    without answers)."""
    from pil.atomic import write_text_atomic
    from pil.experiments.sweep_store import rows_to_csv

    rows = load_answers(folder) if rows is None else rows
    if not rows:
        return []
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    table = summarize_answers(rows)
    return [
        write_text_atomic(out / "questionnaires.md", answers_markdown(rows)),
        write_text_atomic(out / "questionnaires.csv", rows_to_csv(table, SUMMARY_COLUMNS)),
    ]


def _mean_sd(mean: float, sd: float | None) -> str:
    return f"{mean:.2f}" if sd is None else f"{mean:.2f} ± {sd:.2f}"


def _number(value: float, digits: int = 2) -> str:
    return "n/a" if math.isnan(value) else f"{value:.{digits}f}"


def _diff(row: Mapping[str, Any]) -> str:
    if math.isnan(row["mean_diff"]):
        return "n/a"
    if math.isnan(row["ci_low"]):
        return f"{row['mean_diff']:.2f}"
    return f"{row['mean_diff']:.2f} [{row['ci_low']:.2f}, {row['ci_high']:.2f}]"


def _p(value: float) -> str:
    return "n/a" if math.isnan(value) else f"{value:.3g}{' *' if value < 0.05 else ''}"
