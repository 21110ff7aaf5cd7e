"""The sessions report's figure: per measure, each condition's participants and mean ± sd.

One panel per measure of :data:`pil.experiments.sessions_report.MEASURES`; x = the conditions;
a grey line joins each participant's values (the mean of their counted sessions in a
condition) across the conditions they did, so a within-subject change reads as a slope; black
bars show the condition's mean ± sd over its counted sessions.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.experiments.figures import _finish, _pyplot
from pil.experiments.sessions_report import (
    MEASURES,
    conditions_of,
    participant_means,
    summarize_sessions,
)


def plot_sessions(rows: Sequence[Mapping[str, Any]], path: str | Path) -> Path:
    """Write the figure of the counted sessions in ``rows`` to ``path``; returns the path."""
    conditions = conditions_of([r for r in rows if r["counted"]])
    summary = {s["condition"]: s for s in summarize_sessions(rows)}
    plt = _pyplot()
    columns = 4
    panels = len(MEASURES)
    fig, axes = plt.subplots(
        math.ceil(panels / columns), columns, figsize=(3.2 * columns, 3.0 * math.ceil(panels / 4))
    )
    flat = list(axes.flat)
    xs = range(len(conditions))
    for ax, (measure, title) in zip(flat, MEASURES.items(), strict=False):
        means = participant_means(rows, measure)
        participants = sorted({p for by in means.values() for p in by})
        for participant in participants:
            points = [(i, means[c][participant]) for i, c in enumerate(conditions)
                      if participant in means.get(c, {})]  # fmt: skip
            ax.plot(*zip(*points, strict=True), color="0.6", marker="o", markersize=3, lw=1)
        ax.errorbar(
            [x + 0.08 for x in xs],
            [summary[c][f"{measure}_mean"] for c in conditions],
            yerr=[summary[c][f"{measure}_sd"] for c in conditions],
            fmt="s",
            color="black",
            capsize=4,
            label="mean ± sd",
        )
        ax.set_xticks(list(xs), conditions)
        ax.set_xlim(-0.5, len(conditions) - 0.5)
        ax.set_title(title, fontsize="medium")
        ax.grid(axis="y", alpha=0.3)
    for ax in flat[panels:]:
        ax.axis("off")
    flat[0].legend(fontsize="small")
    title = "live sessions per condition (grey: one participant)"
    return _finish(plt, fig, title, path)
