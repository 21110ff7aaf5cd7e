"""The report of a results CSV (a sweep's ``results.csv`` or a study's ``runs.csv``): summary
table, paired tests and figures, grouped by the grid that was run.

The grouping is the detection rate plus every parameter the sweep varied (the columns a sweep
writes between ``rate`` and ``rep``). Failed runs are counted and left out of the statistics.
For physical runs (a ``legs_delivered`` column) the report adds the share of legs delivered (in
%) and the physical failures per rate. The baseline is compared with every other system per
grid cell: a sweep gives every system of one cell and repetition the same seed, so the runs pair
by ``rep`` and ``seed`` (paired t and Wilcoxon, :mod:`pil.experiments.stats`); where they do not
(a failed run, another seed) Welch's test is used and ``tests.csv`` says so. Used by
``robin-pil report`` and at the end of ``robin-pil sweep``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.experiments.paper import BASELINE

METRICS: tuple[str, ...] = ("total_gestures", "total_actions", "gestures", "actions")
PHYSICAL_METRICS: tuple[str, ...] = ("legs_delivered_percent", "physical_failures")


def grid_axes(rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """``rate`` plus the swept parameters (sweep columns between rate and rep, > 1 value)."""
    columns = list(rows[0])
    axes = ["rate"] if "rate" in columns else []
    if {"run_id", "rate", "rep"} <= set(columns):
        between = columns[columns.index("rate") + 1 : columns.index("rep")]
        axes += [c for c in between if len({str(r[c]) for r in rows}) > 1]
    return axes


def with_physical(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Physical rows plus ``legs_delivered_percent`` (100 x legs delivered / legs of the task).

    The task's legs are ``legs_total`` where the run wrote it, else ``tables`` x
    ``legs_per_table`` (a column where the sweep set it, else 4); without either the run's own
    ``legs_delivered_fraction`` is used. Rows without ``legs_delivered`` (learner runs) are
    returned unchanged.
    """
    from pil.experiments.report import number
    from pil.task.scenario import ASSEMBLY_DEFAULTS

    out = []
    for row in rows:
        row = dict(row)
        if "legs_delivered" in row:
            if row.get("legs_total") not in (None, ""):
                legs = number(row["legs_total"], "legs_total")
                delivered = number(row["legs_delivered"], "legs_delivered")
                fraction = delivered / legs if legs > 0 else float("nan")
            elif row.get("tables") not in (None, ""):
                per_table = row.get("legs_per_table")
                legs = number(row["tables"], "tables") * (
                    number(per_table, "legs_per_table")
                    if per_table not in (None, "")
                    else ASSEMBLY_DEFAULTS["legs_per_table"]
                )
                delivered = number(row["legs_delivered"], "legs_delivered")
                fraction = delivered / legs if legs > 0 else float("nan")
            else:
                fraction = number(row.get("legs_delivered_fraction"), "legs_delivered_fraction")
            row["legs_delivered_percent"] = 100.0 * fraction
        out.append(row)
    return out


def write_report(
    results: str | Path,
    out: str | Path,
    *,
    metrics: Sequence[str] | None = None,
    baseline: str = BASELINE,
) -> list[Path]:
    """Write ``summary.md``, ``tests.csv`` and one PNG per metric (and swept cell) to ``out``."""
    from pil.atomic import write_text_atomic
    from pil.experiments.figures import plot_metric
    from pil.experiments.report import (
        COUNT_METRICS,
        ReportError,
        check_columns,
        check_unique_runs,
        count,
        load_rows,
        number,
        summary_markdown,
    )
    from pil.experiments.stats import (
        WILCOXON,
        compare,
        csv_columns,
        describe_tests,
        measures,
        tests_markdown,
    )
    from pil.experiments.study_tests import READINGS
    from pil.experiments.sweep_store import rows_to_csv
    from pil.outdir import check_out_dir

    results, out = Path(results), Path(out)
    rows = load_rows(results)
    check_unique_runs(rows, results)  # a row twice would double n and shrink every p
    failed = [r for r in rows if r.get("status", "ok") != "ok"]
    rows = with_physical([r for r in rows if r.get("status", "ok") == "ok"])
    if not rows:
        raise ReportError(f"{results}: all {len(failed)} runs failed; nothing to summarise")
    physical = "legs_delivered" in rows[0]
    if metrics is None:
        metrics = [m for m in METRICS if m in rows[0]]
        metrics += [m for m in PHYSICAL_METRICS if physical and m in rows[0]]
    check_columns(rows, metrics)
    if not metrics:
        raise ReportError(f"{results}: none of the metrics {', '.join(METRICS)} is a column")
    axes = grid_axes(rows)
    has_system = "system" in rows[0]
    group_by = [*axes, "system"] if has_system else axes
    numeric = [*metrics, *(["rate"] if "rate" in axes else [])]
    for row in rows:  # every number checked before anything is written
        for column in numeric:
            (count if column in COUNT_METRICS else number)(row[column], column)
    check_out_dir(out)

    lines = [
        f"# Report: {results.name}",
        "",
        f"{len(rows)} runs summarised; {len(failed)} failed runs left out.",
        "",
    ]
    if failed:
        lines += (
            ["Failed runs:", ""]
            + [f"- `{r.get('run_id', '?')}`: {r.get('error', '')}" for r in failed[:20]]
            + [""]
        )
    lines += ["## Summary (mean ± sd)", "", summary_markdown(rows, group_by, metrics), ""]
    if physical:
        counts = [m for m in PHYSICAL_METRICS if m in rows[0]]
        lines += ["## Physical outcome per rate", "", summary_markdown(rows, group_by, counts), ""]
    written = [out / "summary.md"]
    systems = {str(r["system"]) for r in rows} if has_system else set()
    if baseline in systems and len(systems) > 1:
        pair_by = [c for c in ("rep", "seed") if c in rows[0]]
        tests = compare(
            rows,
            baseline,
            compare_by="system",
            within=axes,
            metrics=measures(metrics, READINGS),
            pair_by=pair_by,
        )
        lines += [
            f"## Paired tests: {baseline} against each other system",
            "",
            describe_tests(tests) + " All rows in `tests.csv`.",
            "",
            tests_markdown([t for t in tests if t["test"] != WILCOXON], within=axes),
            "",
        ]
        write_text_atomic(out / "tests.csv", rows_to_csv(tests, csv_columns(axes)))
        written.append(out / "tests.csv")
    else:
        lines += [f"No tests: the results hold no {baseline!r} rows next to other systems.", ""]
    write_text_atomic(out / "summary.md", "\n".join(lines))

    if has_system and axes and axes[0] == "rate":
        cells = _cells(rows, axes[1:])
        for metric in metrics:
            for label, members in cells.items():
                name = f"{metric}{label}.png"
                written.append(plot_metric(members, metric, out / name, ("rate", "system")))
    return written


def _cells(rows: Sequence[Mapping[str, Any]], names: Sequence[str]) -> dict[str, list[Any]]:
    """Rows split by the values of ``names`` -> file-name suffix (``""`` when no names)."""
    cells: dict[str, list[Any]] = {}
    for row in rows:
        label = "".join(f"_{n}={row[n]}" for n in names)
        cells.setdefault(re.sub(r"[^\w=.+-]", "_", label), []).append(row)
    return dict(sorted(cells.items()))
