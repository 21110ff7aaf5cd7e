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

from robin_sim.appearance.runs import CLASSIFIERS

APPEARANCE_MEASURES = ("detection_rate", "gestures", "actions")


def _csv(rows: Sequence[dict[str, Any]]) -> str:
    from pil.experiments.study import csv_text

    columns: list[str] = []
    for row in rows:
        columns += [key for key in row if key not in columns]
    return csv_text(list(rows), columns)


def appearance_tests(rows: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """``adapted`` against ``fixed`` per person (finished runs whose twin finished too)."""
    from pil.experiments.stats import compare

    done = [r for r in rows if r["status"] == "finished"]
    pairs = {(r["person"], r["rep"]) for r in done if r["classifier"] == "adapted"}
    pairs &= {(r["person"], r["rep"]) for r in done if r["classifier"] == "fixed"}
    paired = [r for r in done if (r["person"], r["rep"]) in pairs]
    if not paired:
        return []
    return compare(
        paired,
        "fixed",
        compare_by="classifier",
        within=("person",),
        metrics=APPEARANCE_MEASURES,
        pair_by=("rep", "seed"),
    )


def _mean_ci(values: Sequence[float]) -> tuple[float, float, float]:
    from pil.experiments.stats import mean_ci

    if len(values) < 2:
        v = float(values[0]) if values else float("nan")
        return v, v, v
    return mean_ci(values)


def summary_lines(
    rows: Sequence[dict[str, Any]], tests: Sequence[dict[str, Any]], reps: int, tables: int
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
    """Per table, fixed against adapted (mean and 95 % interval over repetitions): the
    detection rate (top) and PIL's actions (bottom), one column per person."""
    from pil.experiments.plotting import pyplot

    plt = pyplot()
    people = list(dict.fromkeys(t["person"] for t in tables)) or ["-"]
    fig, axes = plt.subplots(
        len(FIGURE_ROWS), len(people), figsize=(4.2 * len(people), 6.4), squeeze=False
    )
    for column, person in enumerate(people):
        for row, (key, label) in enumerate(FIGURE_ROWS):
            ax = axes[row][column]
            for classifier, colour in zip(CLASSIFIERS, ("tab:grey", "tab:blue"), strict=True):
                mine = [
                    t for t in tables if t["person"] == person and t["classifier"] == classifier
                ]
                numbers = sorted({int(t["table"]) for t in mine})
                means, lows, highs = [], [], []
                for number in numbers:
                    values = [
                        float(t[key])
                        for t in mine
                        if int(t["table"]) == number and t[key] is not None
                    ]
                    m, lo, hi = _mean_ci(values)
                    means.append(m)
                    lows.append(m - lo)
                    highs.append(hi - m)
                ax.errorbar(
                    numbers,
                    means,
                    yerr=[lows, highs],
                    marker="o",
                    capsize=3,
                    color=colour,
                    label=classifier,
                )
            ax.set_title(person if row == 0 else "")
            ax.set_xlabel("table")
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
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
    written = [out / "appearance_runs.csv", out / "appearance_tables.csv"]
    written[0].write_text(_csv(rows))
    written[1].write_text(_csv(table_rows))
    tests = appearance_tests(rows)
    if tests:
        written.append(out / "tests.csv")
        written[-1].write_text(csv_text(tests, csv_columns(("person",))))
    written.append(out / "appearance.md")
    written[-1].write_text("\n".join(summary_lines(rows, tests, reps, tables)) + "\n")
    written.append(write_figure(table_rows, out / "appearance.png"))
    return written
