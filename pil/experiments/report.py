"""Summaries over result rows, generic over grouping columns and metrics (the tests between
systems: :mod:`pil.experiments.stats`).

Rows are mappings of column name to value, as written by the study (numbers) or read back
from a CSV (strings); values are converted where a number is needed. The same functions
serve ``robin-pil study``, sweeps over any parameter, and physical runs with extra columns.
"""

from __future__ import annotations

import csv
import io
import math
import statistics
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.regular_files import LIMITS, FileTooLargeError, read_regular_text

Row = Mapping[str, Any]
DEFAULT_GROUP_BY: tuple[str, ...] = ("system", "rate")
DEFAULT_METRICS: tuple[str, ...] = ("total_gestures", "total_actions")
MAX_RESULTS_BYTES = LIMITS["results"]  # a results CSV read whole: 2 GB is millions of runs
MAX_MAGNITUDE = 1e15  # no count or time of a run comes near; larger is a corrupt cell


class ReportError(RobinPilError):
    """A results file or row set that cannot be summarised as asked."""


def load_rows(path: str | Path) -> list[dict[str, str]]:
    """The rows of a results CSV (values stay strings)."""
    path = Path(path)
    try:
        text = read_regular_text(path, MAX_RESULTS_BYTES)
        rows = list(csv.DictReader(io.StringIO(text, newline="")))
    except OSError as error:
        raise ReportError(f"{path}: cannot read the results: {error.strerror}") from None
    except FileTooLargeError as error:
        raise ReportError(f"{path}: {error}; a results file is a CSV of run rows") from None
    except UnicodeDecodeError as error:
        raise ReportError(
            f"{path}: not UTF-8 text (byte {error.start}); a results file is a UTF-8 CSV"
        ) from None
    except csv.Error as error:
        raise ReportError(f"{path}: not a readable CSV ({error})") from None
    if not rows:
        raise ReportError(f"{path}: no result rows")
    check_row_shapes(rows, path)
    return rows


def check_row_shapes(rows: Sequence[Mapping[Any, Any]], source: object) -> None:
    """Raise naming the row when a CSV row has more cells than the header (csv keeps them
    under the key None) or fewer (a row cut short: its last columns are None)."""
    width = len([key for key in rows[0] if key is not None])
    for number_, row in enumerate(rows, 2):  # line 1 is the header
        if None in row:
            extra = len(row[None])
            raise ReportError(
                f"{source}: line {number_} has {width + extra} cells, the header {width}; "
                "each run is one row of the header's columns"
            )
        missing = [key for key, value in row.items() if value is None]
        if missing:
            raise ReportError(
                f"{source}: line {number_} has {width - len(missing)} of the header's {width} "
                f"cells (no {missing[0]!r}: a row cut short?); remove or complete it"
            )


COUNT_METRICS: frozenset[str] = frozenset(
    {"total_gestures", "total_actions", "gestures", "actions", "physical_failures"}
)  # counts of a run: whole numbers >= 0


def count(value: Any, column: str) -> int:
    """A count column's value (:data:`COUNT_METRICS`): a whole number >= 0, else raises
    naming the column and the value."""
    real = number(value, column)
    if real < 0 or not real.is_integer():
        raise ReportError(
            f"column {column!r} holds {quote(value)}; a run's {column} is a whole number >= 0"
        )
    return int(real)


RUN_ID_COLUMNS: tuple[str, ...] = ("system", "rate", "rep", "seed")  # named in the message


def check_unique_runs(rows: Sequence[Row], source: object) -> None:
    """Raise when a run appears twice: the same ``run_id`` (a sweep's), or where the rows have
    no ``run_id`` but a ``rep`` or ``seed`` (a study's, whose other columns may tell runs
    apart too: a person, a training rate) the same row twice. Rows without either (hand-made
    tables) are not checked: they name no run."""
    if not rows:
        return
    columns = list(rows[0])
    by_id = "run_id" in columns
    if not by_id and not {"rep", "seed"} & set(columns):
        return
    key = ("run_id",) if by_id else tuple(columns)
    named = ("run_id",) if by_id else tuple(c for c in RUN_ID_COLUMNS if c in columns)
    seen: dict[tuple[str, ...], int] = {}
    for number_, row in enumerate(rows, 1):
        ident = tuple(str(row.get(c)) for c in key)
        if ident in seen:
            shown = ", ".join(f"{c}={row.get(c)}" for c in named)
            raise ReportError(
                f"{source}: the run {shown} appears twice (rows {seen[ident]} and {number_}); "
                "each run is one row: remove the copy (a file appended to twice?)"
            )
        seen[ident] = number_


def number(value: Any, column: str = "value") -> float:
    """``value`` as a float; a non-number, NaN, an infinity or a number beyond
    :data:`MAX_MAGNITUDE` raises naming the column."""
    if isinstance(value, bool):
        return float(value)
    try:
        result = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ReportError(f"column {column!r} holds {quote(value)}, not a number") from None
    if not math.isfinite(result) or abs(result) > MAX_MAGNITUDE:
        raise ReportError(
            f"column {column!r} holds {quote(value)}, not a finite number of magnitude at "
            f"most {MAX_MAGNITUDE:g} (a run's counts and times); fix or remove that row"
        )
    return result


def number_or_nan(value: Any, column: str = "value") -> float:
    """As :func:`number`, but NaN (an untestable comparison's p, a written ``nan``) passes."""
    if str(value).strip().lower() == "nan" or (isinstance(value, float) and math.isnan(value)):
        return math.nan
    return number(value, column)


def sort_key(value: Any) -> tuple[int, float, str]:
    """Numbers before text, numbers by value ("0.4" < "1.0" < "c1" < "pil")."""
    try:
        return (0, float(value), "")
    except (TypeError, ValueError):
        return (1, 0.0, str(value))


def check_columns(rows: Sequence[Row], columns: Iterable[str]) -> None:
    """Raise if a column is missing, listing the columns the rows have."""
    if not rows:
        raise ReportError("no result rows")
    have = list(rows[0])
    for column in columns:
        if column not in rows[0]:
            raise ReportError(
                f"unknown column {column!r}; valid choices: " + ", ".join(map(str, have))
            )


def group_rows(rows: Sequence[Row], group_by: Sequence[str]) -> dict[tuple[str, ...], list[Row]]:
    """Rows grouped by the text of their ``group_by`` values.

    Groups are ordered column by column: numbers by value, text in the order it first
    appears in ``rows`` (so a study's systems keep their order: pil, c1, ..., c4).
    """
    check_columns(rows, group_by)
    groups: dict[tuple[str, ...], list[Row]] = {}
    for row in rows:
        groups.setdefault(tuple(str(row[c]) for c in group_by), []).append(row)
    # text values keep the order they first appear in
    first_seen: list[dict[str, int]] = [{} for _ in group_by]
    for key in groups:
        for seen, value in zip(first_seen, key, strict=True):
            seen.setdefault(value, len(seen))

    def order(key: tuple[str, ...]) -> list[tuple[int, float]]:
        out = []
        for seen, value in zip(first_seen, key, strict=True):
            kind, num, _text = sort_key(value)
            out.append((kind, num if kind == 0 else float(seen[value])))
        return out

    return {k: groups[k] for k in sorted(groups, key=order)}


def mean_sd(values: Sequence[float]) -> tuple[float, float]:
    """Mean and sample standard deviation (0 for a single value)."""
    if not values:
        return math.nan, math.nan
    return statistics.fmean(values), statistics.stdev(values) if len(values) > 1 else 0.0


def summarize(
    rows: Sequence[Row],
    group_by: Sequence[str] = DEFAULT_GROUP_BY,
    metrics: Sequence[str] = DEFAULT_METRICS,
) -> list[dict[str, Any]]:
    """Per group: the group values, ``n``, and ``<metric>_mean`` / ``<metric>_sd``."""
    check_columns(rows, metrics)
    out = []
    for key, members in group_rows(rows, group_by).items():
        entry: dict[str, Any] = dict(zip(group_by, key, strict=True))
        entry["n"] = len(members)
        for metric in metrics:
            mean, sd = mean_sd([number(r[metric], metric) for r in members])
            entry[f"{metric}_mean"], entry[f"{metric}_sd"] = mean, sd
        out.append(entry)
    return out


def markdown_table(header: Sequence[str], body: Iterable[Sequence[Any]]) -> str:
    """A GitHub Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(cell) for cell in line) + " |" for line in body]
    return "\n".join(lines)


def summary_markdown(
    rows: Sequence[Row],
    group_by: Sequence[str] = DEFAULT_GROUP_BY,
    metrics: Sequence[str] = DEFAULT_METRICS,
) -> str:
    """A Markdown table of mean ± sd of each metric per group."""
    header = [*group_by, "n", *metrics]
    body = [
        [*(s[c] for c in group_by), s["n"]]
        + [f"{s[f'{m}_mean']:.1f} ± {s[f'{m}_sd']:.1f}" for m in metrics]
        for s in summarize(rows, group_by, metrics)
    ]
    return markdown_table(header, body)


def csv_text(rows: Sequence[Mapping[str, Any]], columns: Sequence[str]) -> str:
    """The rows as CSV text (fixed columns, ``\\n`` line ends: byte-reproducible)."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(columns), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return buffer.getvalue()
