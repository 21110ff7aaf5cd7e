"""The leaderboard: tables written from a results folder, never typed.

:func:`write_results` writes, beside the journal, ``summary.csv`` (per track, agent and
condition), ``tests.csv`` (every entrant's declared family), ``equivalence.csv`` (TOST and
the mixed model) and ``curves.csv`` (the mean actions per table of the runs that finished);
:func:`render` turns the folder into the Markdown page (``docs/leaderboard.md`` for the
reference agents), headed by the suite version, the seed block and the commit that
made the runs. :func:`row_line` is the one-line row ``robin-pil bench --agent`` prints.
The same folder always renders the same page (``tests/test_bench_leaderboard.py`` checks the
shipped page against its folder).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.bench.analysis import BENCH_TEST_COLUMNS, comparisons, curves, equivalence, summaries
from pil.bench.journal import Journal, read_runs, sorted_runs
from pil.bench.suite import Suite
from pil.experiments.report import markdown_table

BENCH_SUMMARY_COLUMNS = (
    "track",
    "agent",
    "condition",
    "runs",
    "failed",
    "mean",
    "ci_low",
    "ci_high",
    "regret",
    "curve_area",
    "recovery",
    "recovery_missing",
    "savings",
    "savings_missing",
)
EQUIVALENCE_COLUMNS = (
    "track",
    "entrant",
    "anchor",
    "condition",
    "n",
    "dropped",
    "margin",
    "tost_p",
    "noninferior_p",
    "mixed_coef",
    "mixed_low",
    "mixed_high",
    "mixed_p",
    "mixed_note",
)


def csv_text(rows: Sequence[Mapping[str, Any]], columns: Sequence[str]) -> str:
    import csv
    import io

    buffer = io.StringIO()
    writer = csv.DictWriter(
        buffer, fieldnames=list(columns), lineterminator="\n", extrasaction="ignore"
    )
    writer.writeheader()
    for row in rows:
        writer.writerow({c: _cell(row.get(c, "")) for c in columns})
    return buffer.getvalue()


def _cell(value: Any) -> Any:
    if isinstance(value, float):
        return "" if math.isnan(value) else f"{value:.6g}"
    return value


def analyse(
    suite: Suite, rows: Sequence[Mapping[str, Any]], quick: bool = False
) -> dict[str, list[dict]]:
    """Summaries, tests and equivalence of every agent on every track in ``rows`` (``quick``:
    the quick conditions)."""
    rows = sorted_runs(rows)
    out: dict[str, list[dict]] = {"summary": [], "tests": [], "equivalence": []}
    for track in dict.fromkeys(str(r["track"]) for r in rows):
        out["summary"] += summaries(suite, rows, track, quick)
        for agent in dict.fromkeys(str(r["agent"]) for r in rows if r["track"] == track):
            out["tests"] += comparisons(suite, rows, track, agent, quick)
            out["equivalence"] += equivalence(suite, rows, track, agent, quick)
    return out


def write_results(suite: Suite, out: str | Path) -> list[Path]:
    """``summary.csv``, ``tests.csv`` and ``equivalence.csv`` from the folder's journal."""
    out = Path(out)
    stamp = Journal.read_stamp(out) or {}
    rows = read_runs(out)
    found = analyse(suite, rows, bool(stamp.get("quick")))
    curve_rows = [
        {"track": track, "agent": agent, "condition": condition, "table": k + 1, "actions": v}
        for track in dict.fromkeys(str(r["track"]) for r in sorted_runs(rows))
        for (agent, condition), curve in sorted(curves(rows, track).items())
        for k, v in enumerate(curve)
    ]
    return [
        write_text_atomic(
            out / "curves.csv",
            csv_text(curve_rows, ("track", "agent", "condition", "table", "actions")),
        ),
        write_text_atomic(out / "summary.csv", csv_text(found["summary"], BENCH_SUMMARY_COLUMNS)),
        write_text_atomic(out / "tests.csv", csv_text(found["tests"], BENCH_TEST_COLUMNS)),
        write_text_atomic(
            out / "equivalence.csv", csv_text(found["equivalence"], EQUIVALENCE_COLUMNS)
        ),
    ]


def _f(value: float, spec: str = ".1f") -> str:
    return "–" if value is None or math.isnan(value) else format(value, spec)


def _p(value: float) -> str:
    if math.isnan(value):
        return "–"
    star = " *" if value < 0.05 else ""
    return (f"{value:.2g}" if value >= 0.001 else "<0.001") + star


def row_line(suite: Suite, found: Mapping[str, list[dict]], track: str, agent: str) -> str:
    """One leaderboard row of ``agent`` on ``track``: mean [95 % CI] per condition, failures,
    and the difference to the first anchor with its Holm p."""
    cells = [f"{track:<14} {agent:<24}"]
    for s in found["summary"]:
        if s["track"] == track and s["agent"] == agent:
            fails = f" ({s['failed']} failed)" if s["failed"] else ""
            cells.append(
                f"{s['condition']} {_f(s['mean'])} [{_f(s['ci_low'])}, {_f(s['ci_high'])}]{fails}"
            )
    anchor = suite.equivalence_anchor
    diffs = [
        t
        for t in found["tests"]
        if t["track"] == track
        and t["entrant"] == agent
        and t["anchor"] == anchor
        and t["test"] == "paired t"
    ]
    if diffs:
        cells.append(
            f"vs {anchor}: "
            + ", ".join(
                f"{t['condition']} {_f(t['mean_diff'], '+.1f')} p_holm {_p(t['p_holm'])}"
                for t in diffs
            )
        )
    return " | ".join(cells)


REFERENCE_FOLDER = "bench/results/leaderboard"


def render(
    suite: Suite,
    out: str | Path,
    title: str = "Reference leaderboard",
    source: str = REFERENCE_FOLDER,
) -> str:
    """The Markdown page of the results folder ``out``, named ``source`` on the page."""
    out = Path(out)
    stamp = Journal.read_stamp(out) or {}
    found = {name: read_table(out / f"{name}.csv") for name in ("summary", "tests", "equivalence")}
    tuned = _tuned(out)
    seeds = sorted({int(r["seed"]) for r in read_runs(out)})
    parts = [
        f"# {title}",
        "",
        "Generated by `robin-pil bench --leaderboard` from "
        f"`{source}/` (never edited by hand): suite version "
        f"{stamp.get('suite_version', '?')} (`pil/bench/suite.yaml`, sha256 "
        f"{str(stamp.get('suite_sha256', '?'))[:12]}), the **{stamp.get('block', '?')}** seed "
        f"block ({len(seeds)} seeds), commit `{stamp.get('commit', '?')}`. What the tracks, "
        "conditions, metrics and tests are: [bench.md](bench.md).",
        "",
        f"Cells: mean robot actions to finish [95 % CI over seeds]; `(k✗)`: k runs failed "
        f"(past the cap of {suite.cap:g} x the scripted gestures, or a gesture that never got "
        "an approved action) and are left out of the mean. Lower is better.",
    ]
    if tuned:
        parts += [
            "",
            "Tuned on the dev seeds (`tuned.json`): "
            + "; ".join(
                f"{a} {', '.join(f'{k}={v:g}' for k, v in t['params'].items())} "
                f"({', '.join(f'{k} {w}' for k, w in t['optimum'].items())})"
                for a, t in tuned.items()
            )
            + ".",
        ]
    for track in dict.fromkeys(str(r["track"]) for r in found["summary"]):
        parts += _track_section(suite, found, track)
    return "\n".join(parts) + "\n"


def read_table(path: Path) -> list[dict[str, Any]]:
    """A results CSV of :func:`write_results`: numbers as floats (NaN for empty cells)."""
    import csv

    text = path.read_text(encoding="utf-8")
    rows = []
    for raw in csv.DictReader(text.splitlines()):
        row: dict[str, Any] = {}
        for key, value in raw.items():
            if key in _TEXT:
                row[key] = value
            elif value == "":
                row[key] = math.nan
            else:
                try:
                    row[key] = float(value)
                except ValueError:
                    row[key] = value
        rows.append(row)
    return rows


_TEXT = ("track", "agent", "condition", "entrant", "anchor", "measure", "test", "mixed_note")


def _tuned(out: Path) -> dict[str, Any]:
    path = out / "tuned.json"
    if not path.is_file():
        return {}
    return dict(json.loads(path.read_text(encoding="utf-8")))


def _track_section(suite: Suite, found: Mapping[str, list[dict]], track: str) -> list[str]:
    conditions = tuple(
        dict.fromkeys(s["condition"] for s in found["summary"] if s["track"] == track)
    )
    mine = [s for s in found["summary"] if s["track"] == track]
    agents = list(dict.fromkeys(s["agent"] for s in mine))
    by = {(s["agent"], s["condition"]): s for s in mine}

    def cell(agent: str, condition: str) -> str:
        s = by.get((agent, condition))
        if s is None:
            return ""
        fails = f" ({int(s['failed'])}✗)" if s["failed"] else ""
        return f"{_f(s['mean'])} [{_f(s['ci_low'])}, {_f(s['ci_high'])}]{fails}"

    body = [[a, *(cell(a, c) for c in conditions)] for a in agents]
    extra = [
        k for k in ("recovery", "savings") if any(not math.isnan(s.get(k, math.nan)) for s in mine)
    ]
    second = []
    for a in agents:
        rows = [s for s in mine if s["agent"] == a]
        runs, failed = int(sum(s["runs"] for s in rows)), int(sum(s["failed"] for s in rows))
        line = [
            a,
            _f(_mean(s["regret"] for s in rows)),
            _f(_mean(s["curve_area"] for s in rows)),
            f"{failed}/{runs}",
        ]
        line += [_f(_mean(s.get(k, math.nan) for s in rows)) for k in extra]
        second.append(line)
    anchor = suite.equivalence_anchor
    tests = [
        t
        for t in found["tests"]
        if t["track"] == track and t["anchor"] == anchor and t["test"] == "paired t"
    ]
    eq = {(e["entrant"], e["condition"]): e for e in found["equivalence"] if e["track"] == track}
    third = []
    for a in agents:
        if a == anchor:
            continue
        cells = [a]
        for c in conditions:
            t = next((t for t in tests if t["entrant"] == a and t["condition"] == c), None)
            e = eq.get((a, c))
            if t is None:
                cells.append("")
                continue
            tost = (
                ""
                if e is None or math.isnan(e["tost_p"])
                else (" ≡" if e["tost_p"] < suite.alpha else "")
            )
            if t["ci_low"] == t["ci_high"]:  # every pair differs by the same: no interval
                cells.append(f"{_f(t['mean_diff'], '+.1f')} on all {int(t['n'])} pairs{tost}")
                continue
            cells.append(
                f"{_f(t['mean_diff'], '+.1f')} [{_f(t['ci_low'], '+.1f')}, "
                f"{_f(t['ci_high'], '+.1f')}] {_p(t['p_holm'])}{tost}"
            )
        m = eq.get((a, "all"))
        cells.append(
            ""
            if m is None
            else f"{_f(m['mixed_coef'], '+.1f')} "
            f"[{_f(m['mixed_low'], '+.1f')}, {_f(m['mixed_high'], '+.1f')}] "
            f"{_p(m['mixed_p'])}"
        )
        third.append(cells)
    return [
        "",
        f"## {track}: {suite.track(track).description}",
        "",
        markdown_table(["agent", *conditions], body),
        "",
        "Over all conditions: regret = actions − the oracle's on the same seed; curve area = "
        "mean height of the per-table actions curve (the curves: `curves.csv`); failed runs"
        + (f"; {', '.join(extra)} (means)" if extra else "")
        + ".",
        "",
        markdown_table(["agent", "regret", "curve area", "failed", *extra], second),
        "",
        f"Against {anchor} (entrant − anchor, paired by seed over complete pairs): mean "
        "difference [95 % CI], Holm-adjusted paired-t p over the entrant's declared family "
        f"(* < {suite.alpha:g}); ≡: equivalent within ±{suite.margin:g} actions by TOST. Last "
        "column: MixedLM (condition fixed, seed random) agent effect [95 % CI] p.",
        "",
        markdown_table(["entrant", *conditions, "mixed model"], third),
    ]


def _mean(values: Any) -> float:
    kept = [v for v in values if not (v is None or math.isnan(v))]
    return sum(kept) / len(kept) if kept else math.nan
