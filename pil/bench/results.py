"""A results folder's tables, computed from its journal by the analysis fixed in advance.

:func:`write_results` writes, beside the journal, ``summary.csv`` (per track, agent and
condition: runs, failed, stalled, means), ``tests.csv`` (every entrant's declared family with
the anchors, and the suite's focus family: column ``family``), ``equivalence.csv`` (TOST and
the mixed model), ``noninferiority.csv`` (the declared one-sided test) and ``curves.csv`` (the
mean actions per table of the runs that finished); :func:`read_table` reads one back (numbers
as floats).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.atomic import write_text_atomic
from pil.bench.analysis import BENCH_TEST_COLUMNS, comparisons, curves, equivalence, summaries
from pil.bench.focus import NONINFERIORITY_COLUMNS, focus_comparisons, noninferiority
from pil.bench.journal import Journal, read_runs, sorted_runs
from pil.bench.suite import Suite

BENCH_SUMMARY_COLUMNS = (
    "track",
    "agent",
    "condition",
    "runs",
    "failed",
    "stalled",
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
BENCH_EQUIVALENCE_COLUMNS = (
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
    """The rows as CSV text (fixed columns, NaN as empty cells, `\\n` line ends)."""
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
    out["tests"] += [{c: r[c] for c in BENCH_TEST_COLUMNS} for r in focus_comparisons(suite, rows)]
    out["noninferiority"] = noninferiority(suite, rows)
    return out


def write_results(suite: Suite, out: str | Path) -> list[Path]:
    """``summary.csv``, ``tests.csv``, ``equivalence.csv``, ``noninferiority.csv`` and
    ``curves.csv`` from the folder's journal."""
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
            out / "equivalence.csv", csv_text(found["equivalence"], BENCH_EQUIVALENCE_COLUMNS)
        ),
        write_text_atomic(
            out / "noninferiority.csv", csv_text(found["noninferiority"], NONINFERIORITY_COLUMNS)
        ),
    ]


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


_TEXT = (
    "track",
    "agent",
    "condition",
    "entrant",
    "anchor",
    "measure",
    "test",
    "note",
    "mixed_note",
    "family",
    "noninferior",
)
