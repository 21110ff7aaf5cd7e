"""The questionnaires answered on the live page, summarised per condition with paired tests.

Each block's session folder may hold ``questionnaires.jsonl`` (one line per questionnaire the
participant answered after the block, with its scores: NASA-TLX ``raw_tlx`` = the mean of the six
ratings, Godspeed one mean per scale, a Likert questionnaire one score per item and ``mean``).
Every answered questionnaire counts, whether or not the block's task was finished: it rates the
block as the participant lived it. A participant's value in a condition is the mean over their
blocks in it; conditions are compared over the participants who rated both, with
``scipy.stats.ttest_rel`` and ``scipy.stats.wilcoxon`` (exact for small n). Pure Python + scipy.
"""

from __future__ import annotations

import json
import math
import statistics
import warnings
from collections.abc import Mapping, Sequence
from itertools import combinations
from pathlib import Path
from typing import Any

from pil.experiments.report import markdown_table
from pil.experiments.sessions_load import SessionsError

QUESTIONNAIRES_NAME = "questionnaires.jsonl"
REQUIRED = ("participant", "condition", "questionnaire", "scores")
SUMMARY_COLUMNS = ("questionnaire", "score", "condition", "participants", "mean", "sd")
TEST_COLUMNS = ("questionnaire", "score", "a", "b", "n", "mean_a", "mean_b", "t", "p_t",
                "w", "p_w")  # fmt: skip


def load_answers(folder: str | Path) -> list[dict[str, Any]]:
    """Every answered questionnaire under ``folder`` (``[]`` when none); a line that is not a
    questionnaire record raises :class:`SessionsError` naming its file and line."""
    rows = []
    for path in sorted(Path(folder).rglob(QUESTIONNAIRES_NAME)):
        try:
            lines = path.read_text(encoding="utf-8").splitlines()
        except (OSError, UnicodeDecodeError) as error:
            raise SessionsError(f"{path}: cannot read the questionnaires: {error}") from None
        for number, line in enumerate(lines, 1):
            if not line.strip():
                continue
            try:
                row = json.loads(line)
            except (ValueError, RecursionError):
                row = None
            bad = not isinstance(row, dict) or any(k not in row for k in REQUIRED)
            if bad or not isinstance(row["scores"], Mapping):
                raise SessionsError(f"{path}:{number}: not a questionnaire record (a JSON object "
                                    "with " + ", ".join(REQUIRED) + ")")  # fmt: skip
            rows.append({**row, "file": path.relative_to(folder).as_posix()})
    return rows


def participant_scores(rows: Sequence[Mapping[str, Any]]) -> dict[tuple[str, str], dict]:
    """(questionnaire, score) -> condition -> participant -> the mean over their blocks."""
    values: dict[tuple[str, str], dict[str, dict[str, list[float]]]] = {}
    for row in rows:
        for score, value in row["scores"].items():
            if isinstance(value, (int, float)) and not isinstance(value, bool):
                by = values.setdefault((row["questionnaire"], score), {})
                by.setdefault(row["condition"], {}).setdefault(row["participant"], []).append(
                    float(value))  # fmt: skip
    return {key: {c: {p: statistics.fmean(v) for p, v in people.items()}
                  for c, people in by.items()} for key, by in values.items()}  # fmt: skip


def summarize_answers(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Per questionnaire, score and condition: participants, mean and sd (None for n = 1)."""
    out = []
    for (questionnaire, score), by in participant_scores(rows).items():
        for condition in sorted(by):
            values = list(by[condition].values())
            out.append({"questionnaire": questionnaire, "score": score, "condition": condition,
                        "participants": len(values), "mean": statistics.fmean(values),
                        "sd": statistics.stdev(values) if len(values) > 1 else None})  # fmt: skip
    return out


def paired_tests(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Per score and pair of conditions: paired t and Wilcoxon signed-rank over the participants
    who rated both (NaN statistics when fewer than two or no difference varies)."""
    from scipy.stats import ttest_rel, wilcoxon  # imported here: scipy is slow to import

    out = []
    for (questionnaire, score), by in participant_scores(rows).items():
        for a, b in combinations(sorted(by), 2):
            both = sorted(set(by[a]) & set(by[b]))
            xs, ys = [by[a][p] for p in both], [by[b][p] for p in both]
            differences = [x - y for x, y in zip(xs, ys, strict=True)]
            t = p_t = w = p_w = math.nan
            if len(both) > 1 and len(set(differences)) > 1:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", RuntimeWarning)
                    t_test = ttest_rel(xs, ys)
                    t, p_t = float(t_test.statistic), float(t_test.pvalue)
                    if any(differences):
                        w_test = wilcoxon(xs, ys)
                        w, p_w = float(w_test.statistic), float(w_test.pvalue)
            out.append({"questionnaire": questionnaire, "score": score, "a": a, "b": b,
                        "n": len(both), "mean_a": statistics.fmean(xs) if xs else math.nan,
                        "mean_b": statistics.fmean(ys) if ys else math.nan,
                        "t": t, "p_t": p_t, "w": w, "p_w": p_w})  # fmt: skip
    return out


def answers_markdown(rows: Sequence[Mapping[str, Any]]) -> str:
    """``questionnaires.md``: the counting rule, the per-condition table, the paired tests."""
    people = len({r["participant"] for r in rows})
    lines = [
        "# Questionnaires", "",
        f"{len(rows)} questionnaires answered by {people} participants after their blocks. "
        "A participant's value in a condition is the mean over their blocks in it; every "
        "answered questionnaire counts (finished or not). NASA-TLX raw = the mean of its six "
        "ratings (0-100); Godspeed: the mean of each scale's items (1-5).", "",
        "## Per condition (mean ± sd over participants; no sd for n = 1)", "",
        markdown_table(["questionnaire", "score", "condition", "n", "mean ± sd"],
                       [[s["questionnaire"], s["score"], s["condition"], s["participants"],
                         _mean_sd(s["mean"], s["sd"])] for s in summarize_answers(rows)]),
        "",
    ]  # fmt: skip
    tests = paired_tests(rows)
    if tests:
        lines += ["## Paired tests (participants who rated both conditions)", "",
                  "`scipy.stats.ttest_rel` and `scipy.stats.wilcoxon`; n/a with fewer than two "
                  "pairs or no varying difference; p < 0.05 marked *.", "",
                  markdown_table(["questionnaire", "score", "a", "b", "n", "mean (a)",
                                  "mean (b)", "t", "p (t)", "W", "p (W)"],
                                 [[r["questionnaire"], r["score"], r["a"], r["b"], r["n"],
                                   _number(r["mean_a"]), _number(r["mean_b"]), _number(r["t"]),
                                   _p(r["p_t"]), _number(r["w"], 1), _p(r["p_w"])]
                                  for r in tests]), ""]  # fmt: skip
    else:
        lines += ["No paired tests: the answers hold fewer than two conditions.", ""]
    return "\n".join(lines)


def write_answers_report(folder: str | Path, out: str | Path) -> list[Path]:
    """Write ``questionnaires.md`` and ``questionnaires.csv`` to ``out`` when ``folder`` holds
    answers; their paths (none written without answers)."""
    from pil.atomic import write_text_atomic
    from pil.experiments.sweep_store import rows_to_csv

    rows = load_answers(folder)
    if not rows:
        return []
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    table = summarize_answers(rows)
    return [write_text_atomic(out / "questionnaires.md", answers_markdown(rows)),
            write_text_atomic(out / "questionnaires.csv",
                              rows_to_csv(table, SUMMARY_COLUMNS))]  # fmt: skip


def _mean_sd(mean: float, sd: float | None) -> str:
    return f"{mean:.2f}" if sd is None else f"{mean:.2f} ± {sd:.2f}"


def _number(value: float, digits: int = 2) -> str:
    return "n/a" if math.isnan(value) else f"{value:.{digits}f}"


def _p(value: float) -> str:
    return "n/a" if math.isnan(value) else f"{value:.3g}{' *' if value < 0.05 else ''}"
