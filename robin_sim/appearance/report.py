"""The appearance study's files: runs, tables, paired tests, a report and a figure.

``appearance_runs.csv`` has a row per run (person, classifier, repetition, the person's looks,
the measured detection rate, PIL's gestures and actions); ``appearance_tables.csv`` a row per
table of each run. ``tests.csv`` compares ``adapted`` with ``fixed`` for each person on the
detection rate, gestures and actions, paired by repetition (the same seed: the same handovers
and performances; paired t and Wilcoxon, Holm over each family, :mod:`pil.experiments.stats`);
only runs that finished pair. ``appearance.md`` tells it; ``appearance.png`` shows the
detection rate per table, fixed against adapted (mean and 95 % interval over repetitions).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from robin_sim.appearance.runs import CLASSIFIERS

APPEARANCE_MEASURES = ("detection_rate", "gestures", "actions")


def _csv(rows: Sequence[dict[str, Any]]) -> str:
    from pil.experiments.study import csv_text

    columns: list[str] = []
    for row in rows:
        columns += [key for key in row if key not in columns]
    return csv_text(list(rows), columns)


SAME_VIEWS = "shipped_same_views"  # the shipped model on the adapted runs' own views


def appearance_tests(rows: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Two families, per person: ``adapted`` against ``fixed`` runs (each pair one seed: the
    whole session, learner included) on the detection rate, gestures and actions; and, in the
    adapted runs, the adapted model against the shipped one reading the very same views
    (:data:`SAME_VIEWS`), on the detection rate. Finished runs only (with their twins)."""
    from pil.experiments.stats import compare

    done = [r for r in rows if r["status"] == "finished"]
    pairs = {(r["person"], r["rep"]) for r in done if r["classifier"] == "adapted"}
    pairs &= {(r["person"], r["rep"]) for r in done if r["classifier"] == "fixed"}
    paired = [r for r in done if (r["person"], r["rep"]) in pairs]
    if not paired:
        return []
    runs = compare(
        paired,
        "fixed",
        compare_by="classifier",
        within=("person",),
        metrics=APPEARANCE_MEASURES,
        pair_by=("rep", "seed"),
    )
    adapted = [r for r in done if r["classifier"] == "adapted"]
    views = [
        {**r, "classifier": SAME_VIEWS, "detection_rate": r["shipped_detection_rate"]}
        for r in adapted
    ] + adapted
    same = compare(
        views,
        SAME_VIEWS,
        compare_by="classifier",
        within=("person",),
        metrics=("detection_rate",),
        pair_by=("rep", "seed"),
    )
    return runs + same


def _mean_ci(values: Sequence[float]) -> tuple[float, float, float]:
    from pil.experiments.stats import mean_ci

    if len(values) < 2:
        v = float(values[0]) if values else float("nan")
        return v, v, v
    return mean_ci(values)


def _series(
    tables_rows: Sequence[dict[str, Any]], person: str, classifier: str, key: str
) -> dict[int, list[float]]:
    """Per table number, the values of ``key`` in ``person``'s ``classifier`` runs (the shipped
    model on the adapted runs' views: classifier :data:`SAME_VIEWS`)."""
    source = "adapted" if classifier == SAME_VIEWS else classifier
    column = "shipped_detection_rate" if classifier == SAME_VIEWS else key
    out: dict[int, list[float]] = {}
    for t in tables_rows:
        if t["person"] == person and t["classifier"] == source and t[column] is not None:
            out.setdefault(int(t["table"]), []).append(float(t[column]))
    return out


def per_table_lines(
    tables_rows: Sequence[dict[str, Any]], rows: Sequence[dict[str, Any]]
) -> list[str]:
    """The detection rate per table (mean over finished runs): fixed runs, adapted runs, and
    the shipped model reading the adapted runs' own views."""
    finished = {(r["person"], r["classifier"], r["rep"]) for r in rows if r["status"] == "finished"}
    kept = [t for t in tables_rows if (t["person"], t["classifier"], t["rep"]) in finished]
    numbers = sorted({int(t["table"]) for t in kept})
    lines = [
        "## Detection rate per table (mean over the finished runs)",
        "",
        "`shipped_same_views`: the shipped model reading the adapted runs' own views (the same "
        "images, so only the classifier differs).",
        "",
        "| person | classifier | " + " | ".join(f"table {n}" for n in numbers) + " |",
        "|---|---|" + "---|" * len(numbers),
    ]
    for person in dict.fromkeys(t["person"] for t in kept):
        for classifier in (*CLASSIFIERS, SAME_VIEWS):
            series = _series(kept, person, classifier, "detection_rate")
            cells = [f"{np.mean(series[n]):.3f}" if n in series else "-" for n in numbers]
            lines.append(f"| {person} | {classifier} | " + " | ".join(cells) + " |")
    return lines


def summary_lines(
    rows: Sequence[dict[str, Any]],
    tests: Sequence[dict[str, Any]],
    reps: int,
    tables: int,
    tables_rows: Sequence[dict[str, Any]] = (),
) -> list[str]:
    """The report's text (markdown)."""
    from pil.experiments.stats import describe_tests, tests_markdown

    people = list(dict.fromkeys(r["person"] for r in rows))
    lines = [
        "# Appearance: the shipped gesture model against one adapting to each person",
        "",
        f"PIL reads every gesture and thumb with Robin's eye cameras; {tables} tables per run, "
        f"{reps} repetitions per person and classifier (the same seed for both: paired). "
        "Mean [95 % CI] over the finished runs.",
        "",
        "| person | looks | classifier | runs finished | detection rate | gestures | actions |",
        "|---|---|---|---|---|---|---|",
    ]
    for person in people:
        for classifier in CLASSIFIERS:
            mine = [r for r in rows if r["person"] == person and r["classifier"] == classifier]
            done = [r for r in mine if r["status"] == "finished"]
            looks = ", ".join(
                f"{k} {mine[0][k]:g}"
                for k in ("skin", "pose_jitter", "lighting")
                if mine and mine[0].get(k) is not None
            )
            cells = []
            for key, fmt in (("detection_rate", ".3f"), ("gestures", ".1f"), ("actions", ".1f")):
                m, lo, hi = _mean_ci([float(r[key]) for r in done])
                cells.append(f"{m:{fmt}} [{lo:{fmt}}, {hi:{fmt}}]" if done else "-")
            lines.append(
                f"| {person} | {looks} | {classifier} | {len(done)}/{len(mine)} | "
                + " | ".join(cells)
                + " |"
            )
    lines += ["", *per_table_lines(tables_rows, rows)]
    failed = [r for r in rows if r["status"] != "finished"]
    if failed:
        lines += ["", f"{len(failed)} runs did not finish (left out with their twins):", ""]
        lines += [f"- {r['person']} {r['classifier']} rep {r['rep']}: {r['error']}" for r in failed]
    if tests:
        lines += [
            "",
            "## Adapted against fixed, per person (paired by repetition)",
            "",
            describe_tests(tests) + " All rows in `tests.csv`.",
            "",
            tests_markdown(tests, ("person",)),
        ]
    return lines


FIGURE_ROWS = (("detection_rate", "detection rate (read right)"), ("actions", "robot actions"))


def write_figure(tables: Sequence[dict[str, Any]], path: Path) -> Path:
    """Per table (mean and 95 % interval over repetitions): the detection rate (top: fixed,
    adapted, and the shipped model on the adapted runs' views, dashed) and PIL's actions
    (bottom), one column per person."""
    from matplotlib.ticker import MaxNLocator

    from pil.experiments.plotting import pyplot

    plt = pyplot()
    people = list(dict.fromkeys(t["person"] for t in tables)) or ["-"]
    fig, axes = plt.subplots(
        len(FIGURE_ROWS), len(people), figsize=(4.2 * len(people), 6.4), squeeze=False
    )
    lines = (
        ("fixed", "tab:grey", "-"),
        ("adapted", "tab:blue", "-"),
        (SAME_VIEWS, "tab:orange", "--"),
    )
    for column, person in enumerate(people):
        for row, (key, label) in enumerate(FIGURE_ROWS):
            ax = axes[row][column]
            for classifier, colour, style in lines:
                if classifier == SAME_VIEWS and key != "detection_rate":
                    continue
                series = _series(tables, person, classifier, key)
                numbers = sorted(series)
                stats = [_mean_ci(series[n]) for n in numbers]
                ax.errorbar(
                    numbers,
                    [m for m, _, _ in stats],
                    yerr=[[m - lo for m, lo, _ in stats], [hi - m for m, _, hi in stats]],
                    marker="o",
                    capsize=3,
                    color=colour,
                    linestyle=style,
                    label=classifier,
                )
            ax.set_title(person if row == 0 else "")
            ax.xaxis.set_major_locator(MaxNLocator(integer=True))
            ax.set_xlabel("table")
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7)
    fig.suptitle("Eye cameras per table: the shipped model (fixed) and the adapted one")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def write_appearance(
    results: Sequence[dict[str, Any]], out: Path, reps: int, tables: int
) -> list[Path]:
    """Every file of the study (see the module doc)."""
    from pil.experiments.stats import csv_columns
    from pil.experiments.study import csv_text

    rows = [r["row"] for r in results]
    table_rows = [t for r in results for t in r["tables"]]
    finished_tables = [t for r in results if r["row"]["status"] == "finished" for t in r["tables"]]
    written = [out / "appearance_runs.csv", out / "appearance_tables.csv"]
    written[0].write_text(_csv(rows))
    written[1].write_text(_csv(table_rows))
    tests = appearance_tests(rows)
    if tests:
        written.append(out / "tests.csv")
        written[-1].write_text(csv_text(tests, csv_columns(("person",))))
    from robin_sim.appearance.trend import TREND_COLUMNS, trend_rows

    written.append(out / "trend.csv")
    written[-1].write_text(csv_text(trend_rows(finished_tables), TREND_COLUMNS))
    written.append(out / "appearance.md")
    written[-1].write_text("\n".join(summary_lines(rows, tests, reps, tables, table_rows)) + "\n")
    written.append(write_figure(finished_tables, out / "appearance.png"))
    return written
