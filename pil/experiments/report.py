"""Summaries and Welch t-tests over result rows, generic over grouping columns and metrics.

Rows are mappings of column name to value, as written by the study (numbers) or read back
from a CSV (strings); values are converted where a number is needed. The same functions
serve ``robin-pil study``, sweeps over any parameter, and physical runs with extra columns.
"""

from __future__ import annotations

import csv
import io
import math
import statistics
import warnings
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.regular_files import FileTooLargeError, read_regular_text

Row = Mapping[str, Any]
DEFAULT_GROUP_BY: tuple[str, ...] = ("system", "rate")
DEFAULT_METRICS: tuple[str, ...] = ("total_gestures", "total_actions")
MAX_RESULTS_BYTES = 2_000_000_000  # a results CSV read whole: 2 GB is millions of runs
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
    return rows


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
    first_seen = [{} for _ in group_by]  # text values keep the order they first appear in
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


def welch_ttests(
    rows: Sequence[Row],
    baseline: str = "pil",
    *,
    compare_by: str = "system",
    within: Sequence[str] = ("rate",),
    metrics: Sequence[str] = DEFAULT_METRICS,
) -> list[dict[str, Any]]:
    """Welch's t-test (unequal variances) of ``baseline`` against every other value of
    ``compare_by``, separately for each combination of ``within`` columns and each metric.

    Each result holds the ``within`` values, ``metric``, ``other``, both means, ``t`` and
    ``p`` (NaN when a group has fewer than two runs or both groups are constant).
    """
    from scipy.stats import ttest_ind  # imported here: scipy is slow to import

    check_columns(rows, [compare_by, *within, *metrics])
    values = {str(r[compare_by]) for r in rows}
    if baseline not in values:
        raise ReportError(
            f"baseline {baseline!r} not found in column {compare_by!r}; valid choices: "
            + ", ".join(sorted(values, key=sort_key))
        )
    results = []
    for key, members in group_rows(rows, within).items():
        by_value = group_rows(members, [compare_by])
        base_rows = by_value.get((baseline,), [])
        for metric in metrics:
            base = [number(r[metric], metric) for r in base_rows]
            for (other,), other_rows in by_value.items():
                if other == baseline:
                    continue
                them = [number(r[metric], metric) for r in other_rows]
                t, p = math.nan, math.nan
                if len(base) > 1 and len(them) > 1 and (len(set(base)) > 1 or len(set(them)) > 1):
                    with warnings.catch_warnings():  # nearly constant groups: p is still valid
                        warnings.filterwarnings("ignore", "Precision loss", RuntimeWarning)
                        test = ttest_ind(base, them, equal_var=False)
                    t, p = float(test.statistic), float(test.pvalue)
                entry: dict[str, Any] = dict(zip(within, key, strict=True))
                entry.update(
                    metric=metric,
                    baseline=baseline,
                    other=other,
                    baseline_mean=statistics.fmean(base) if base else math.nan,
                    other_mean=statistics.fmean(them),
                    t=t,
                    p=p,
                )
                results.append(entry)
    return results


def ttests_markdown(results: Sequence[Mapping[str, Any]], within: Sequence[str] = ("rate",)) -> str:
    """A Markdown table of :func:`welch_ttests` results (p < 0.05 marked with *)."""
    header = [*within, "metric", "baseline", "other", "mean (baseline)", "mean (other)", "t", "p"]
    body = []
    for r in results:
        p = r["p"]
        p_text = "n/a" if math.isnan(p) else f"{p:.3g}{' *' if p < 0.05 else ''}"
        t_text = "n/a" if math.isnan(r["t"]) else f"{r['t']:.2f}"
        body.append(
            [*(r[c] for c in within), r["metric"], r["baseline"], r["other"],
             f"{r['baseline_mean']:.1f}", f"{r['other_mean']:.1f}", t_text, p_text]
        )  # fmt: skip
    return markdown_table(header, body)
