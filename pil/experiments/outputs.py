"""Outputs of the smaller studies (adaptation, transfer, personal mappings): a CSV, a summary
with mean ± sd and paired tests (by repetition: every compared run of one repetition shares
its seed), ``tests.csv`` and one bar chart, each written atomically."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, TypeVar

from pil.atomic import write_text_atomic
from pil.experiments.report import Row, summary_markdown
from pil.experiments.stats import WILCOXON, compare, csv_columns, describe_tests, tests_markdown
from pil.experiments.study import csv_text
from pil.experiments.study_tests import PAIR_BY

R = TypeVar("R", bound=Mapping[str, Any])  # a result row: a dict, or a CSV's read back


def sort_runs(
    rows: list[R], systems: Sequence[str], column: str = "", values: Sequence[str] = ()
) -> list[R]:
    """``rows`` in the studies' order (in place): rate, the given system order, then
    ``column`` in the order of ``values`` (e.g. the mode or start), then repetition."""
    order = {s: i for i, s in enumerate(systems)}
    rank = {v: i for i, v in enumerate(values)}
    rows.sort(
        key=lambda r: (r["rate"], order[r["system"]], rank[r[column]] if column else 0, r["rep"])
    )
    return rows


def rep_rows_text(rows: Sequence[Row]) -> str:
    """The rows as CSV text in their own column order (byte-reproducible)."""
    return csv_text(rows, list(rows[0]))


def small_study_tests(
    rows: Sequence[Row],
    baseline: str,
    compare_by: str,
    within: Sequence[str],
    metrics: Sequence[str],
) -> list[dict]:
    """The small study's ``tests.csv`` rows (paired by :data:`PAIR_BY`, Holm per test)."""
    return compare(
        rows, baseline, compare_by=compare_by, within=within, metrics=metrics, pair_by=PAIR_BY
    )


def write_small_study(
    rows: Sequence[Row],
    out: str | Path,
    name: str,
    *,
    title: str,
    intro: str,
    group_by: Sequence[str],
    metrics: Sequence[str],
    figure_metric: str,
    baseline: str,
    compare_by: str,
    within: Sequence[str] = ("rate",),
    ylabel: str | None = None,
    extra: str = "",
    figure_group_by: Sequence[str] | None = None,
) -> list[Path]:
    """Write ``NAME.csv``, ``NAME.md``, ``tests.csv`` and ``NAME.png`` under ``out``; returns
    the paths. ``baseline`` is compared with every other value of ``compare_by`` within each
    ``within`` group, paired by :data:`PAIR_BY` (Welch where the runs do not pair).

    ``extra`` is Markdown appended to the summary; ``figure_group_by`` (two columns, default
    ``group_by``) groups the bars.
    """
    from pil.experiments.figures import plot_metric

    out = Path(out)
    tests = small_study_tests(rows, baseline, compare_by, within, metrics)
    text = "\n".join(
        [
            f"# {title}",
            "",
            intro,
            "",
            "## Mean ± sd",
            "",
            summary_markdown(rows, group_by, metrics),
            "",
            f"## Paired tests: {baseline} against each other {compare_by}",
            "",
            describe_tests(tests) + " All rows in `tests.csv`.",
            "",
            tests_markdown([t for t in tests if t["test"] != WILCOXON], within),
            "",
            *([extra, ""] if extra else []),
        ]
    )
    written = [write_text_atomic(out / f"{name}.csv", rep_rows_text(rows))]
    written.append(write_text_atomic(out / f"{name}.md", text))
    written.append(write_text_atomic(out / "tests.csv", csv_text(tests, csv_columns(within))))
    written.append(
        plot_metric(
            rows,
            figure_metric,
            out / f"{name}.png",
            figure_group_by or group_by,
            title=f"{title} (mean ± sd)",
            ylabel=ylabel,
        )
    )
    return written
