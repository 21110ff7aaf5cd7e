"""Bar charts of result rows (matplotlib, Agg backend), in the spirit of the paper's Figs. 3-4.

:func:`plot_metric` draws grouped bars: one group per value of the first ``group_by`` column
(e.g. the detection rate), one bar per value of the second (e.g. the system), height = mean,
error bar = sample standard deviation. Works on rows read back from a CSV (strings).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from pil.experiments.plotting import finish_figure, pyplot
from pil.experiments.report import Row, group_rows, number, summarize


def _label(value: str, column: str) -> str:
    """Rates as percentages, everything else as written."""
    if column == "rate":
        return f"{number(value, column) * 100:.0f} %"
    return value


def plot_metric(
    rows: Sequence[Row],
    metric: str,
    path: str | Path,
    group_by: Sequence[str] = ("rate", "system"),
    *,
    title: str | None = None,
    ylabel: str | None = None,
) -> Path:
    """Grouped bar chart of ``metric`` (mean ± sd) over two grouping columns; returns the path."""
    if len(group_by) != 2:
        raise ValueError("group_by names two columns: the x groups and the bars within a group")
    outer, inner = group_by
    stats = {(s[outer], s[inner]): s for s in summarize(rows, group_by, [metric])}
    outers = [k[0] for k in group_rows(rows, [outer])]
    inners = [k[0] for k in group_rows(rows, [inner])]
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(max(6.0, 1.2 * len(outers) * max(1, len(inners)) / 3), 4.0))
    width = 0.8 / max(1, len(inners))
    for j, name in enumerate(inners):
        xs, means, sds = [], [], []
        for i, group in enumerate(outers):
            entry = stats.get((group, name))
            if entry is not None:
                xs.append(i + (j - (len(inners) - 1) / 2) * width)
                means.append(entry[f"{metric}_mean"])
                sds.append(entry[f"{metric}_sd"])
        ax.bar(xs, means, width, yerr=sds, capsize=2, label=_label(name, inner))
    ax.set_xticks(range(len(outers)), [_label(v, outer) for v in outers])
    ax.set_xlabel(outer.replace("_", " "))
    ax.set_ylabel(ylabel or metric.replace("_", " "))
    ax.set_title(title or f"{metric.replace('_', ' ')} (mean ± sd)")
    ax.legend(title=inner, fontsize="small", ncols=min(5, len(inners)))
    ax.grid(axis="y", alpha=0.3)
    return finish_figure(plt, fig, None, path)


def plot_comparison(
    ours: Mapping[str, Mapping[str, float]],
    theirs: Mapping[str, Mapping[str, float]],
    path: str | Path,
    *,
    title: str = "training: ours vs the paper",
    labels: tuple[str, str] = ("ours (mean)", "paper"),
) -> Path:
    """Side-by-side bars per x label and quantity (e.g. rate -> {gestures, actions})."""
    plt = pyplot()
    groups = list(ours)
    quantities = list(next(iter(ours.values())))
    fig, axes = plt.subplots(1, len(quantities), figsize=(5.0 * len(quantities), 3.8))
    axes = axes if len(quantities) > 1 else [axes]
    for ax, quantity in zip(axes, quantities, strict=True):
        xs = range(len(groups))
        ax.bar([x - 0.2 for x in xs], [ours[g][quantity] for g in groups], 0.4, label=labels[0])
        ax.bar(
            [x + 0.2 for x in xs],
            [theirs.get(g, {}).get(quantity, float("nan")) for g in groups],
            0.4,
            label=labels[1],
        )
        ax.set_xticks(list(xs), groups)
        ax.set_title(quantity)
        ax.grid(axis="y", alpha=0.3)
        ax.legend(fontsize="small")
    return finish_figure(plt, fig, title, path)


def plot_rules(
    by_rule: Mapping[str, Mapping[float, Mapping[str, float]]],
    paper: Mapping[float, tuple[float, float]],
    path: str | Path,
    *,
    title: str = "training (5 tables): the paper vs each exploration rule",
) -> Path:
    """Per quantity (gestures, actions): bars per rate, the paper's first, then each rule's
    mean with its sd."""
    plt = pyplot()
    rates = sorted(paper)
    series = len(by_rule) + 1
    width = 0.8 / series
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.0))
    for ax, (i, quantity) in zip(axes, enumerate(("gestures", "actions")), strict=True):
        xs = range(len(rates))
        offset = (series - 1) / 2
        ax.bar(
            [x - offset * width for x in xs],
            [paper[r][i] for r in rates],
            width,
            label="paper",
            color="black",
        )
        for j, (rule, figures) in enumerate(by_rule.items(), start=1):
            means = [figures.get(r, {}).get(quantity, float("nan")) for r in rates]
            sds = [figures.get(r, {}).get(f"{quantity}_sd", 0.0) for r in rates]
            ax.bar(
                [x + (j - offset) * width for x in xs],
                means,
                width,
                yerr=sds,
                capsize=2,
                label=rule,
            )
        ax.set_xticks(list(xs), [f"{r * 100:.0f} %" for r in rates])
        ax.set_xlabel("detection rate")
        ax.set_title(quantity)
        ax.grid(axis="y", alpha=0.3)
        ax.legend(fontsize="small")
    return finish_figure(plt, fig, title, path)
