"""A results folder's tables, computed from its journal by the analysis fixed in advance.

:func:`write_results` writes, beside the journal, ``summary.csv`` (per track, agent and
condition: runs, failed, stalled, means), ``tests.csv`` (every entrant's declared family with
the anchors, and the suite's focus family: column ``family``), ``equivalence.csv`` (TOST and
the mixed model), ``noninferiority.csv`` (the declared one-sided test) and ``curves.csv`` (the
mean actions per table of the runs that finished); :func:`read_table` reads one back (numbers
as floats) through the guarded reader, strictly: its columns must be the table's (a table of an
older version may lack some), every row has one cell per column, and every number is finite
and written in ASCII; anything else is one error naming the file and the line.
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
from pil.numbers import is_decimal_text
from pil.regular_files import UnreadableFileError, read_kind_text

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
CURVE_COLUMNS = ("track", "agent", "condition", "table", "actions")
TABLE_COLUMNS: dict[str, tuple[str, ...]] = {
    "summary.csv": BENCH_SUMMARY_COLUMNS,
    "tests.csv": BENCH_TEST_COLUMNS,
    "equivalence.csv": BENCH_EQUIVALENCE_COLUMNS,
    "noninferiority.csv": NONINFERIORITY_COLUMNS,
    "curves.csv": CURVE_COLUMNS,
}


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
    rows = read_runs(out, suite)
    found = analyse(suite, rows, bool(stamp.get("quick")))
    curve_rows = [
        {"track": track, "agent": agent, "condition": condition, "table": k + 1, "actions": v}
        for track in dict.fromkeys(str(r["track"]) for r in sorted_runs(rows))
        for (agent, condition), curve in sorted(curves(rows, track).items())
        for k, v in enumerate(curve)
    ]
    return [
        write_text_atomic(out / "curves.csv", csv_text(curve_rows, CURVE_COLUMNS)),
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
    """A results CSV of :func:`write_results` (module docstring): numbers as floats, NaN for
    empty cells; :class:`UnreadableFileError` naming the file and the line."""
    import csv
    import io

    known = TABLE_COLUMNS.get(path.name)
    if known is None:
        raise UnreadableFileError(
            f"{path}: not a results table; valid: " + ", ".join(TABLE_COLUMNS)
        )
    text = read_kind_text(path, "results", "a results table")
    reader = csv.reader(io.StringIO(text, newline=""), strict=True)
    try:
        header = next(reader, [])
        if not header or len(set(header)) != len(header) or set(header) - set(known):
            raise ValueError(f"its columns {header} are not those of {path.name}: {list(known)}")
        rows = [_row(header, cells) for cells in reader]
    except (ValueError, csv.Error) as error:
        raise UnreadableFileError(f"{path}:{reader.line_num}: {error}") from None
    return rows


def _row(header: list[str], cells: list[str]) -> dict[str, Any]:
    """One table row: text columns as they are, the others finite numbers (NaN if empty)."""
    if len(cells) != len(header):
        raise ValueError(f"{len(cells)} cells, not {len(header)} (one per column)")
    row: dict[str, Any] = {}
    for key, value in zip(header, cells, strict=True):
        if key in _TEXT:
            row[key] = value
        elif value == "":
            row[key] = math.nan
        elif is_decimal_text(value) and math.isfinite(float(value)):
            row[key] = float(value)
        else:
            raise ValueError(f"{key!r} is {value!r}, not a finite number written with 0-9")
    return row


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
