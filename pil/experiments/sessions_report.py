"""The live page's sessions, summarised per condition like the study: mean ± sd and t-tests.

A sessions folder holds ``<participant>/<session>/summary.json`` files written by
``robin-pil live``; only summaries with a ``"live"`` block count as sessions. One row per
session (:data:`SESSION_COLUMNS`); sessions whose status is ``finished`` are *counted*, the rest
(ended early, closed, interrupted, failed) are listed and left out of the means and tests.
Sessions of different studies are never pooled: the rows are split by scenario and protocol
(:func:`study_groups`) and each group is summarised and tested on its own. Tests compare
participants, not sessions: a participant's value in a condition is the mean of
their counted sessions (repeated blocks) in it. Within-subject designs (some participant did more
than one condition) get paired t-tests over the participants who did both conditions of a pair;
between-subject designs get Welch's t-test. A condition with one value shows that value and
n = 1, no sd. Pure Python, numpy and scipy: no MuJoCo.
"""

from __future__ import annotations

import math
import statistics
import warnings
from collections.abc import Mapping, Sequence
from itertools import combinations
from pathlib import Path
from typing import Any

from pil.experiments.report import markdown_table, mean_sd
from pil.experiments.sessions_load import (
    COUNTED_STATUS,
    EXPECTED,
    MEASURES,
    SESSION_COLUMNS,
    SessionsError,
    load_sessions,
    unreported_sessions,
)

__all__ = [  # the reading is re-exported: the report's callers import from here only
    "COUNTED_STATUS",
    "EXPECTED",
    "MEASURES",
    "SESSION_COLUMNS",
    "SessionsError",
    "conditions_of",
    "is_within",
    "load_sessions",
    "participant_means",
    "report_markdown",
    "session_tests",
    "study_groups",
    "summarize_sessions",
    "unreported_sessions",
    "write_sessions_report",
]


def conditions_of(rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """The conditions in registry order (pil, c1, ..., proactive), unknown ones after, by name."""
    from pil.task.systems import SYSTEM_SPECS

    known = list(SYSTEM_SPECS)
    names = {str(r["condition"]) for r in rows}
    return sorted(names, key=lambda n: (known.index(n) if n in known else len(known), n))


def study_groups(rows: Sequence[Mapping[str, Any]]) -> list[tuple[str, str]]:
    """The (scenario, protocol) pairs the rows hold, sorted (protocol "" for none)."""
    return sorted({(str(r["scenario"]), str(r["protocol"] or "")) for r in rows})


def _in_group(rows: Sequence[Mapping[str, Any]], group: tuple[str, str]) -> list[Mapping[str, Any]]:
    return [r for r in rows if (str(r["scenario"]), str(r["protocol"] or "")) == group]


def _group_text(group: tuple[str, str]) -> str:
    scenario, protocol = group
    return f"scenario `{scenario}`, " + (f"protocol `{protocol}`" if protocol else "no protocol")


def participant_means(
    rows: Sequence[Mapping[str, Any]], measure: str
) -> dict[str, dict[str, float]]:
    """condition -> participant -> the mean of their counted sessions' ``measure`` values."""
    values: dict[str, dict[str, list[float]]] = {}
    for row in rows:
        if row["counted"] and row[measure] is not None and not math.isnan(row[measure]):
            by = values.setdefault(row["condition"], {})
            by.setdefault(row["participant"], []).append(float(row[measure]))
    return {c: {p: statistics.fmean(v) for p, v in by.items()} for c, by in values.items()}


def is_within(rows: Sequence[Mapping[str, Any]]) -> bool:
    """True when some participant has counted sessions in more than one condition."""
    seen: dict[str, set[str]] = {}
    for row in rows:
        if row["counted"]:
            seen.setdefault(row["participant"], set()).add(row["condition"])
    return any(len(c) > 1 for c in seen.values())


def summarize_sessions(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Per scenario, protocol and condition: ``n`` counted sessions, participants and
    ``<measure>_mean`` / ``_sd`` / ``_n`` (sd NaN for fewer than two values)."""
    out = []
    counted = [r for r in rows if r["counted"]]
    for group in study_groups(counted):
        members_of_group = _in_group(counted, group)
        for condition in conditions_of(members_of_group):
            members = [r for r in members_of_group if r["condition"] == condition]
            people = len({r["participant"] for r in members})
            entry: dict[str, Any] = {
                "scenario": group[0],
                "protocol": group[1] or None,
                "condition": condition,
                "n": len(members),
                "participants": people,
            }
            for measure in MEASURES:
                values = [float(r[measure]) for r in members if r[measure] is not None]
                mean, sd = mean_sd(values)
                entry[f"{measure}_mean"] = mean
                entry[f"{measure}_sd"] = sd if len(values) > 1 else math.nan
                entry[f"{measure}_n"] = len(values)
            out.append(entry)
    return out


def session_tests(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Per scenario and protocol, pair of conditions and measure: a paired t-test
    (within-subject) or Welch's.

    Each result: ``scenario``, ``protocol``, ``test`` ("paired" | "welch"), ``measure``,
    ``a``, ``b``, ``n`` (pairs, or "n_a/n_b"), both means over participants, ``t`` and ``p``
    (NaN when too few participants or no variation: paired differences all equal, or both
    groups constant).
    """
    results = []
    for group in study_groups([r for r in rows if r["counted"]]):
        for result in _group_tests(_in_group(rows, group)):
            results.append({"scenario": group[0], "protocol": group[1] or None, **result})
    return results


def _group_tests(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """:func:`session_tests` within one scenario and protocol."""
    from scipy.stats import ttest_ind, ttest_rel  # imported here: scipy is slow to import

    within = is_within(rows)
    results = []
    for a, b in combinations(conditions_of([r for r in rows if r["counted"]]), 2):
        for measure in MEASURES:
            means = participant_means(rows, measure)
            in_a, in_b = means.get(a, {}), means.get(b, {})
            if within:
                both = sorted(set(in_a) & set(in_b))
                xs, ys = [in_a[p] for p in both], [in_b[p] for p in both]
                varied = len({x - y for x, y in zip(xs, ys, strict=True)}) > 1
                n: Any = len(both)
            else:
                xs, ys = list(in_a.values()), list(in_b.values())
                varied = len(set(xs)) > 1 or len(set(ys)) > 1
                n = f"{len(xs)}/{len(ys)}"
            t = p = math.nan
            if len(xs) > 1 and len(ys) > 1 and varied:
                with warnings.catch_warnings():  # nearly constant groups: p is still valid
                    warnings.filterwarnings("ignore", "Precision loss", RuntimeWarning)
                    test = ttest_rel(xs, ys) if within else ttest_ind(xs, ys, equal_var=False)
                t, p = float(test.statistic), float(test.pvalue)
            results.append(
                {
                    "test": "paired" if within else "welch",
                    "measure": measure,
                    "a": a,
                    "b": b,
                    "n": n,
                    "mean_a": statistics.fmean(xs) if xs else math.nan,
                    "mean_b": statistics.fmean(ys) if ys else math.nan,
                    "t": t,
                    "p": p,
                }
            )
    return results


def report_markdown(
    rows: Sequence[Mapping[str, Any]],
    folder: str | Path,
    unreported: Sequence[tuple[str, str]] = (),
) -> str:
    """``report.md``: the counting rule; per scenario and protocol the per-condition table and
    the tests; the sessions left out and the ``unreported`` session folders (no readable
    summary)."""
    counted = [r for r in rows if r["counted"]]
    left_out = [r for r in rows if not r["counted"]]
    lines = [
        f"# Live sessions: {Path(folder).name}",
        "",
        f"{len(rows)} sessions of {len({r['participant'] for r in rows})} participants; "
        f"{len(counted)} counted, {len(left_out)} left out.",
        "",
        f"**Which sessions count:** those with status `{COUNTED_STATUS}` (every leg of the block "
        "handed over). Sessions ended early, closed, interrupted or failed are listed below and "
        "left out of the means and the tests; all sessions are in `sessions.csv` (`counted`). "
        "Sessions of different scenarios or protocols are summarised apart, never pooled.",
        "",
    ]
    if not counted:
        lines += [f"No session is `{COUNTED_STATUS}` yet: nothing to summarise.", ""]
    groups = study_groups(counted)
    for group in groups:
        level = "###" if len(groups) > 1 else "##"
        if len(groups) > 1:
            lines += [f"## {_group_text(group)}", ""]
        else:
            lines += [f"Sessions of {_group_text(group)}.", ""]
        lines += _group_lines(_in_group(rows, group), level)
    if left_out:
        lines += [
            "## Left out (not finished)",
            "",
            markdown_table(
                ["participant", "session", "condition", "scenario", "status", "legs", "summary"],
                [
                    [
                        r["participant"],
                        r["session"],
                        r["condition"],
                        r["scenario"],
                        r["status"],
                        _legs_text(r),
                        f"`{r['summary']}`",
                    ]
                    for r in left_out
                ],
            ),
            "",
        ]
    if unreported:
        body = [[f"`{where}`", why] for where, why in unreported]
        lines += [
            "## Not reported (no readable summary)",
            "",
            markdown_table(["session folder", "why"], body),
            "",
        ]
    return "\n".join(lines)


def _legs_text(row: Mapping[str, Any]) -> str:
    total = row.get("legs_total")
    delivered = row["legs_delivered"]
    done = "n/a" if delivered is None else f"{delivered:g}"
    return done if total is None else f"{done} / {total}"


def _group_lines(rows: Sequence[Mapping[str, Any]], level: str) -> list[str]:
    """The per-condition table and the tests of one scenario and protocol."""
    within = is_within(rows)
    lines = [f"{level} Per condition (mean ± sd over counted sessions; n = 1: the value)", ""]
    header = ["condition", "sessions", "participants", *MEASURES.values()]
    body = [
        [s["condition"], s["n"], s["participants"]] + [_mean_sd_text(s, m) for m in MEASURES]
        for s in summarize_sessions(rows)
    ]
    lines += [markdown_table(header, body), ""]
    tests = _group_tests(rows)
    if not tests:
        lines += ["No t-tests: the counted sessions hold fewer than two conditions.", ""]
    elif within:
        lines += [
            f"{level} Paired t-tests (within-subject)",
            "",
            "Some participants did more than one condition, so each pair of conditions is "
            "compared over the participants who did both (`scipy.stats.ttest_rel`; a "
            "participant's value is the mean of their counted sessions in that condition; "
            "n = participants; p < 0.05 marked *).",
            "",
            _tests_table(tests),
            "",
        ]
    else:
        lines += [
            f"{level} Welch t-tests (between-subject)",
            "",
            "Every participant did one condition, so the conditions are compared as independent "
            "groups of participants (`scipy.stats.ttest_ind(equal_var=False)` on each "
            "participant's mean; n = participants per condition; p < 0.05 marked *).",
            "",
            _tests_table(tests),
            "",
        ]
    return lines


def write_sessions_report(
    rows: Sequence[Mapping[str, Any]], folder: str | Path, out: str | Path
) -> list[Path]:
    """Write ``sessions.csv``, ``report.md`` and ``sessions.png`` to ``out``; their paths."""
    from pil.atomic import write_text_atomic
    from pil.experiments.sessions_figure import Panel, plot_paired
    from pil.experiments.sweep_store import rows_to_csv

    out = Path(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise SessionsError(f"--out {out}: cannot make the folder: {error.strerror}") from None
    text = report_markdown(rows, folder, unreported_sessions(folder))
    written = [write_text_atomic(out / "sessions.csv", rows_to_csv(rows, SESSION_COLUMNS))]
    written.append(write_text_atomic(out / "report.md", text))
    if not any(r["counted"] for r in rows):
        return written  # listed in report.md; no figure without a counted session
    groups = study_groups([r for r in rows if r["counted"]])
    labelled = [{**r, "condition": _label(r, len(groups))} for r in rows]
    summary = {_label(s, len(groups)): s for s in summarize_sessions(rows)}
    panels = [
        Panel(
            title,
            participant_means(labelled, measure),
            {
                c: (s[f"{measure}_mean"], _sd_or_zero(s[f"{measure}_sd"]))
                for c, s in summary.items()
            },
        )
        for measure, title in MEASURES.items()
    ]
    written.append(plot_paired(list(summary), panels, out / "sessions.png"))
    return written


def _label(entry: Mapping[str, Any], groups: int) -> str:
    """A condition's name on the figure's axis (with its scenario when the report has several)."""
    if groups == 1:
        return str(entry["condition"])
    protocol = f"/{entry['protocol']}" if entry["protocol"] else ""
    return f"{entry['condition']}\n{entry['scenario']}{protocol}"


def _sd_or_zero(sd: float) -> float:
    return 0.0 if math.isnan(sd) else sd


def _tests_table(tests: Sequence[Mapping[str, Any]]) -> str:
    header = ["measure", "a", "b", "n", "mean (a)", "mean (b)", "t", "p"]
    body = []
    for r in tests:
        p_text = "n/a" if math.isnan(r["p"]) else f"{r['p']:.3g}{' *' if r['p'] < 0.05 else ''}"
        t_text = "n/a" if math.isnan(r["t"]) else f"{r['t']:.2f}"
        body.append(
            [
                MEASURES[r["measure"]],
                r["a"],
                r["b"],
                r["n"],
                f"{r['mean_a']:.2f}",
                f"{r['mean_b']:.2f}",
                t_text,
                p_text,
            ]
        )
    return markdown_table(header, body)


def _mean_sd_text(entry: Mapping[str, Any], measure: str) -> str:
    mean, sd = entry[f"{measure}_mean"], entry[f"{measure}_sd"]
    if math.isnan(mean):
        return "n/a"
    n = entry[f"{measure}_n"]
    if n < 2:
        return f"{mean:.2f} (n = 1)"
    missing = "" if n == entry["n"] else f" (n={n})"
    return f"{mean:.2f} ± {sd:.2f}{missing}"
