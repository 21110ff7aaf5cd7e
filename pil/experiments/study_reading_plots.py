"""The figures of :mod:`pil.experiments.study_reading` (matplotlib, PNG)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pil.experiments.plotting import finish_figure, pyplot
from pil.experiments.stats import mean_ci

_COLOURS = {"pil": "black", "c1": "tab:blue", "c2": "tab:orange", "c3": "tab:green"}
_COLOURS["c4"] = "tab:red"


def experience_figure(rows: Sequence[Mapping[str, Any]], path: Path) -> Path:
    """Mean gestures and actions per table against tables experienced, per rate and system
    (95 % CI over repetitions); the dotted line: where c1-c4's test tables begin."""
    plt = pyplot()
    rates = sorted({float(r["rate"]) for r in rows})
    fig, axes = plt.subplots(2, len(rates), figsize=(3.6 * len(rates), 6.4), squeeze=False)
    for col, rate in enumerate(rates):
        for row_i, measure in enumerate(("gestures", "actions")):
            ax = axes[row_i][col]
            for system in dict.fromkeys(str(r["system"]) for r in rows):
                xs, ms, lows, highs = [], [], [], []
                ks = sorted(
                    {
                        int(r["experienced"])
                        for r in rows
                        if r["system"] == system and r["rate"] == rate
                    }
                )
                for k in ks:
                    values = [
                        float(r[measure])
                        for r in rows
                        if r["system"] == system and r["rate"] == rate and r["experienced"] == k
                    ]
                    m, lo, hi = mean_ci(values)
                    xs.append(k)
                    ms.append(m)
                    lows.append(m if math.isnan(lo) else lo)
                    highs.append(m if math.isnan(hi) else hi)
                colour = _COLOURS.get(system, "grey")
                ax.plot(xs, ms, marker=".", label=system, color=colour)
                ax.fill_between(xs, lows, highs, color=colour, alpha=0.15)
            ax.axvline(5.5, color="grey", linestyle=":")
            ax.set_title(f"{measure}, d = {rate * 100:.0f} %")
            ax.set_xlabel("tables experienced")
            ax.set_ylabel(f"{measure} per table")
    axes[0][0].legend(fontsize=8)
    title = "Cost of each table by experience (c1-c4: 5 training tables, then the test)"
    return finish_figure(plt, fig, title, path)


def validation_figure(
    fitted: Sequence[Mapping[str, Any]],
    validated: Sequence[Mapping[str, Any]],
    chosen: tuple[str, float],
    path: Path,
) -> Path:
    """Ours (95 % CI thick, per-run 95 % PI thin) beside the paper's eight training figures;
    calibration rates (fitted) and validation rates (predicted) marked apart."""
    plt = pyplot()
    mine = [r for r in fitted if (r["rule"], r["discard"]) == chosen]
    mine += [r for r in validated if (r["rule"], r["discard"]) == chosen]
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
    for ax, figure in zip(axes, ("gestures", "actions"), strict=True):
        for r in sorted((r for r in mine if r["figure"] == figure), key=lambda r: r["rate"]):
            x = r["rate"] * 100
            colour = "tab:blue" if r in validated else "tab:grey"
            ax.vlines(x, r["pi_low"], r["pi_high"], color=colour, linewidth=1)
            ax.vlines(x, r["ci_low"], r["ci_high"], color=colour, linewidth=5)
            ax.plot(x, r["mean"], "o", color=colour)
            ax.plot(x + 2.5, r["paper"], "x", color="tab:red", markersize=8)
        ax.set_xticks([40, 60, 80, 100])
        ax.set_xlabel("detection rate (%)  grey: fitted, blue: predicted, x: paper")
        ax.set_ylabel(f"training {figure} (5 tables)")
    title = f"Calibration (40, 100 %) and validation (60, 80 %): {chosen[0]}, discard {chosen[1]:g}"
    return finish_figure(plt, fig, title, path)


def sensitivity_figure(rows: Sequence[Mapping[str, Any]], path: Path) -> Path:
    """Difference from the paper (%) of each training figure against ``discard``, one panel
    per set of handover types."""
    plt = pyplot()
    sets = list(dict.fromkeys(str(r["types"]) for r in rows))
    fig, axes = plt.subplots(1, len(sets), figsize=(3.6 * len(sets), 3.8), sharey=True)
    for ax, name in zip(axes, sets, strict=True):
        for rate in sorted({r["rate"] for r in rows}):
            for figure, style in (("gestures", "-"), ("actions", "--")):
                found = sorted(
                    (
                        r
                        for r in rows
                        if r["types"] == name and r["rate"] == rate and r["figure"] == figure
                    ),
                    key=lambda r: r["discard"],
                )
                ax.plot(
                    [r["discard"] for r in found],
                    [r["diff_percent"] for r in found],
                    style,
                    marker=".",
                    label=f"{figure} {rate * 100:.0f} %",
                )
        ax.axhline(0, color="grey", linewidth=0.8)
        ax.set_title(f"types {name}")
        ax.set_xlabel("discard")
    axes[0].set_ylabel("ours − paper (%)")
    axes[-1].legend(fontsize=7)
    return finish_figure(plt, fig, "Sensitivity of the training figures", path)
