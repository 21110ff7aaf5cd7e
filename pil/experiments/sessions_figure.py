"""The sessions report's figure: per measure, each condition's participants and mean ± sd.

One panel per measure; x = the conditions; a grey line joins each participant's values (the
mean of their counted sessions in a condition) across the conditions they did, so a
within-subject change reads as a slope; black bars show the condition's mean ± sd.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from pil.experiments.plotting import finish_figure, pyplot


@dataclass(frozen=True)
class Panel:
    """One measure: its title, condition -> participant -> value, condition -> (mean, sd)."""

    title: str
    participants: Mapping[str, Mapping[str, float]]
    mean_sd: Mapping[str, tuple[float, float]]


def plot_paired(conditions: Sequence[str], panels: Sequence[Panel], path: str | Path) -> Path:
    """Write the figure (four panels a row) to ``path``; returns the path."""
    plt = pyplot()
    columns = min(4, len(panels))
    rows = math.ceil(len(panels) / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(3.2 * columns, 3.0 * rows), squeeze=False)
    flat = list(axes.flat)
    xs = range(len(conditions))
    for ax, panel in zip(flat, panels, strict=False):
        people = sorted({p for by in panel.participants.values() for p in by})
        for person in people:
            points = [
                (i, panel.participants[c][person])
                for i, c in enumerate(conditions)
                if person in panel.participants.get(c, {})
            ]
            ax.plot(*zip(*points, strict=True), color="0.6", marker="o", markersize=3, lw=1)
        ax.errorbar(
            [x + 0.08 for x in xs],
            [panel.mean_sd[c][0] for c in conditions],
            yerr=[panel.mean_sd[c][1] for c in conditions],
            fmt="s",
            color="black",
            capsize=4,
            label="mean ± sd",
        )
        ax.set_xticks(list(xs), conditions)
        ax.set_xlim(-0.5, len(conditions) - 0.5)
        ax.set_title(panel.title, fontsize="medium")
        ax.grid(axis="y", alpha=0.3)
    for ax in flat[len(panels) :]:
        ax.axis("off")
    flat[0].legend(fontsize="small")
    return finish_figure(plt, fig, "live sessions per condition (grey: one participant)", path)
