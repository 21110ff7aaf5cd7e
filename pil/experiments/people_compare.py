"""The fitted people's simulated sessions against the recorded ones: CSV, markdown, figure.

For each participant, each measure (:data:`pil.experiments.people_observed.MEASURES`) and each
of their recorded sessions: the recorded value, the simulated sessions' mean with its 95 %
interval (Student's t over the simulated sessions), their 2.5-97.5 % range (the range within
which 95 % of the person's simulated sessions fall), and whether the recorded value lies in
that range. A recorded session is compared with the simulated sessions run in its own setting
(system, scenario, handover types). Pure Python but the figure (matplotlib).
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

from pil.experiments.people_observed import COMPARED_MEASURES
from pil.experiments.report import ReportError, number_or_nan
from pil.regular_files import UnreadableFileError, read_kind_text

COMPARISON_COLUMNS = (
    "participant",
    "session",
    "measure",
    "recorded",
    "simulated_n",
    "simulated_mean",
    "mean_low",
    "mean_high",
    "range_low",
    "range_high",
    "inside",
)


def _values(rows: Sequence[Mapping[str, Any]], measure: str) -> np.ndarray:
    return np.array([float(r[measure]) for r in rows if r.get(measure) is not None])


def compare(
    recorded: Sequence[Mapping[str, Any]], simulated: Sequence[Mapping[str, Any]]
) -> list[dict[str, Any]]:
    """One row per participant, recorded session and measure (see the module doc); rows carry
    ``participant``, ``session``, ``setting`` and the measures."""
    rows = []
    for rec in recorded:
        sims = [
            s
            for s in simulated
            if s["participant"] == rec["participant"] and s["setting"] == rec["setting"]
        ]
        for measure in COMPARED_MEASURES:
            values, value = _values(sims, measure), rec.get(measure)
            row: dict[str, Any] = {
                "participant": rec["participant"],
                "session": rec["session"],
                "measure": measure,
                "recorded": value,
                "simulated_n": int(values.size),
            }
            if values.size:
                mean = float(values.mean())
                half = (
                    float(stats.t.ppf(0.975, values.size - 1) * values.std(ddof=1))
                    / math.sqrt(values.size)
                    if values.size > 1
                    else 0.0
                )
                low, high = np.percentile(values, [2.5, 97.5])
                row.update(
                    simulated_mean=round(mean, 4),
                    mean_low=round(mean - half, 4),
                    mean_high=round(mean + half, 4),
                    range_low=round(float(low), 4),
                    range_high=round(float(high), 4),
                    inside=None if value is None else bool(low <= float(value) <= high),
                )
            rows.append(row)
    return rows


def write_csv(rows: Sequence[Mapping[str, Any]], columns: Sequence[str], path: Path) -> Path:
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(columns), extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow({k: "" if row.get(k) is None else row.get(k) for k in columns})
    return path


def _cell(value: Any) -> str:
    if value is None:
        return "–"
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e6:
        return str(int(value))
    if isinstance(value, float):
        return f"{value:.3g}" if abs(value) < 10 else f"{value:.1f}"
    return str(value)


def markdown(
    rows: Sequence[Mapping[str, Any]],
    people: Sequence[Mapping[str, Any]],
    left_out: Mapping[str, str],
    sessions_per_person: int,
    statuses: Mapping[str, Mapping[str, int]] | None = None,
) -> str:
    """The comparison as a markdown page: the fitted parameters, how the simulated sessions
    ended (``statuses``: person -> status -> sessions), then one table per person."""
    statuses = statuses or {}
    lines = [
        "# Fitted people: simulated sessions against the recorded ones",
        "",
        f"{sessions_per_person} simulated sessions per person; a recorded value is *inside* "
        "when it lies within the 2.5-97.5 % range of the person's simulated sessions.",
        "",
        "| person | sessions | gesture latency median (s) [95 % CI] | sigma | thumb down: "
        "wrong move / wrong fingers / right | thumb up on right | late thumbs |",
        "|---|---|---|---|---|---|---|",
    ]
    for p in people:
        g = p["gesture_latency"]
        rates = " / ".join(
            _rate(p[k]) for k in ("down_on_wrong_move", "down_on_wrong_fingers", "down_on_right")
        )
        lines.append(
            f"| {p['participant']} | {len(p['sources'])} | {g['median']:.2f} "
            f"[{g['median_low']:.2f}, {g['median_high']:.2f}] | {g['sigma']:.2f} | {rates} | "
            f"{_rate(p['up_on_right'])} | {p['late_thumbs']} |"
        )
    if left_out:
        lines += ["", "Left out: " + ", ".join(f"{k} ({v})" for k, v in left_out.items()) + "."]
    inside = [r["inside"] for r in rows if r.get("inside") is not None]
    if statuses:
        lines += [
            "",
            "Simulated sessions by how they ended: "
            + "; ".join(
                f"{who} " + ", ".join(f"{k} {n}" for k, n in sorted(counts.items()))
                for who, counts in sorted(statuses.items())
            )
            + ".",
        ]
    lines += [
        "",
        f"Recorded values inside the simulated 95 % range: {sum(inside)} of {len(inside)}.",
        "",
    ]
    for person in sorted({r["participant"] for r in rows}):
        lines += [
            f"## {person}",
            "",
            "| measure | session | recorded | simulated mean [95 % CI] | 95 % range | inside |",
            "|---|---|---|---|---|---|",
        ]
        for r in rows:
            if r["participant"] != person:
                continue
            mean = (
                f"{_cell(r.get('simulated_mean'))} [{_cell(r.get('mean_low'))}, "
                f"{_cell(r.get('mean_high'))}]"
            )
            span = f"{_cell(r.get('range_low'))} – {_cell(r.get('range_high'))}"
            yes = {True: "yes", False: "**no**", None: "–"}[r.get("inside")]
            lines.append(
                f"| {COMPARED_MEASURES[r['measure']]} | {r['session']} | {_cell(r['recorded'])} | "
                f"{mean} | {span} | {yes} |"
            )
        lines.append("")
    return "\n".join(lines)


def _rate(rate: Mapping[str, Any]) -> str:
    if rate.get("p") is None:
        return "–"
    return f"{rate['k']}/{rate['n']}"


def figure(
    recorded: Sequence[Mapping[str, Any]], simulated: Sequence[Mapping[str, Any]], path: Path
) -> Path:
    """Per measure, each person's simulated sessions (dots, 95 % range as a bar) and the
    recorded sessions (crosses)."""
    from pil.experiments.plotting import finish_figure, pyplot

    plt = pyplot()
    measures = list(COMPARED_MEASURES)
    people = sorted({r["participant"] for r in recorded})
    fig, axes = plt.subplots(1, len(measures), figsize=(2.3 * len(measures), 3.4))
    for ax, measure in zip(axes, measures, strict=True):
        for i, person in enumerate(people):
            sims = _values([s for s in simulated if s["participant"] == person], measure)
            recs = _values([r for r in recorded if r["participant"] == person], measure)
            if sims.size:
                jitter = np.linspace(-0.12, 0.12, sims.size)
                ax.scatter(i + jitter, sims, s=8, color="tab:blue", alpha=0.5)
                low, high = np.percentile(sims, [2.5, 97.5])
                ax.plot([i + 0.22, i + 0.22], [low, high], color="tab:blue", lw=3)
            ax.scatter(np.full(recs.size, i), recs, marker="x", s=50, color="tab:red", zorder=3)
        ax.set_xticks(range(len(people)), people)
        ax.set_xlim(-0.6, len(people) - 0.4)
        ax.set_title(COMPARED_MEASURES[measure], fontsize=8)
        ax.tick_params(labelsize=7)
    title = "Simulated (blue, bar: 95 % range) vs recorded (red x) sessions"
    return finish_figure(plt, fig, title, path)


def summary_table(rows: Sequence[Mapping[str, Any]]) -> str:
    """Per person and measure, one line: the recorded sessions' values, the simulated mean
    [95 % CI], the 95 % range and how many recorded values lie in it (the docs' table)."""
    lines = [
        "| person | measure | recorded | simulated mean [95 % CI] | simulated 95 % range | "
        "inside |",
        "|---|---|---|---|---|---|",
    ]
    people = sorted({r["participant"] for r in rows})
    for person in people:
        for measure, label in COMPARED_MEASURES.items():
            mine = [r for r in rows if r["participant"] == person and r["measure"] == measure]
            if not mine:
                continue
            first = mine[0]
            recorded = " / ".join(_cell(r["recorded"]) for r in mine)
            inside = [r["inside"] for r in mine if r.get("inside") is not None]
            lines.append(
                f"| {person} | {label} | {recorded} | {_cell(first.get('simulated_mean'))} "
                f"[{_cell(first.get('mean_low'))}, {_cell(first.get('mean_high'))}] | "
                f"{_cell(first.get('range_low'))} – {_cell(first.get('range_high'))} | "
                f"{sum(inside)} of {len(inside)} |"
            )
    return "\n".join(lines)


def read_comparison(path: Path) -> list[dict[str, Any]]:
    """``comparison.csv`` read back (through the guarded reader) with its numbers as numbers;
    a cell that is not a finite number raises naming the file and the column."""
    rows = []
    text = read_kind_text(path, "results", "the comparison")
    for raw in csv.DictReader(io.StringIO(text, newline="")):
        row: dict[str, Any] = dict(raw)
        for key in COMPARISON_COLUMNS[3:]:
            value = row.get(key)
            if value in (None, ""):
                row[key] = None
            elif key == "inside":
                row[key] = value == "True"
            else:
                try:
                    row[key] = number_or_nan(value, key)
                except ReportError as error:
                    raise UnreadableFileError(f"{path}: {error}") from None
        rows.append(row)
    return rows
