"""Our figures beside the paper's (:mod:`pil.experiments.paper` holds the paper's own).

* :func:`training_figures` reads ours from a study's rows; :func:`rule_training` reruns the
  training for every exploration rule (same seeds), so the summary can show all of them.

The paper's claim (PIL costlier than c1 and c2 at low rates) is read from the study's paired
tests: :mod:`pil.experiments.study_tests`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from pil.experiments.paper import PAPER_RATES, PAPER_TRAINING
from pil.experiments.report import Row, markdown_table, mean_sd, number
from pil.exploration import RULES
from pil.task.spec import RunSpec

Figures = dict[float, dict[str, float]]


def _figures(runs: Mapping[tuple[float, str], tuple[float, float]]) -> Figures:
    out: Figures = {}
    for rate in sorted({k[0] for k in runs}):
        gestures = [g for (r, _), (g, _a) in runs.items() if r == rate]
        actions = [a for (r, _), (_g, a) in runs.items() if r == rate]
        (g_mean, g_sd), (a_mean, a_sd) = mean_sd(gestures), mean_sd(actions)
        out[rate] = {
            "gestures": g_mean,
            "gestures_sd": g_sd,
            "actions": a_mean,
            "actions_sd": a_sd,
            "n": len(gestures),
        }
    return out


def training_figures(rows: Sequence[Row]) -> Figures:
    """Mean and sd of the training gestures and actions per training rate.

    Training at rate d is taken from c1 (or c3) rows, training at 100 % from c2/c4 rows or
    from c1 at rate 1.0. Each repetition's (or, without a ``rep`` column, each seed's) training
    run is counted once.
    """
    runs: dict[tuple[float, str], tuple[float, float]] = {}
    for row in rows:
        system = str(row["system"])
        if system in ("c1", "c3"):
            train_rate = number(row["rate"], "rate")
        elif system in ("c2", "c4"):
            train_rate = 1.0
        else:
            continue
        key = (train_rate, str(row.get("rep", row.get("seed"))))
        runs[key] = (number(row["train_gestures"]), number(row["train_actions"]))
    return _figures(runs)


def rule_training(
    base: RunSpec, rates: Sequence[float], seeds: Sequence[int]
) -> dict[str, Figures]:
    """The training figures of every exploration rule, at ``rates``, one run per seed:
    ``base``'s training run (a PIL run with correction on the training tables), each rule
    applied as a typed value (nothing parsed again)."""
    from pil.task.assemble import assemble

    out: dict[str, Figures] = {}
    for rule in RULES:
        runs: dict[tuple[float, str], tuple[float, float]] = {}
        spec = base.changed({"exploration": rule})
        for rep, seed in enumerate(seeds):
            cache: dict[Any, Any] = {}
            for rate in rates:
                run = assemble(spec.for_run("pil", rate, seed), phase="train", cache=cache)
                stats = run.run()
                runs[(rate, str(rep))] = (stats.gestures, stats.actions)
        out[rule] = _figures(runs)
    return out


def _diff(ours: float, paper: float) -> float:
    return 100.0 * (ours - paper) / paper


def worst_difference(figures: Figures) -> float:
    """The largest |difference| in % from the paper over the eight figures (NaN if none)."""
    diffs = [
        abs(_diff(fig[name], PAPER_TRAINING[rate][i]))
        for rate, fig in figures.items()
        if rate in PAPER_TRAINING
        for i, name in enumerate(("gestures", "actions"))
    ]
    return max(diffs) if diffs else math.nan


def training_markdown(figures: Figures) -> str:
    """Our training figures next to the paper's, with the % difference."""
    lines = [
        "| rate | gestures (ours) | gestures (paper) | diff | actions (ours) | "
        "actions (paper) | diff |",
        "|---|---|---|---|---|---|---|",
    ]
    for rate, fig in figures.items():
        paper = PAPER_TRAINING.get(rate)
        cells = [f"{rate * 100:.0f} %"]
        for i, name in enumerate(("gestures", "actions")):
            ours = f"{fig[name]:.1f} ± {fig[f'{name}_sd']:.1f}"
            if paper is None:
                cells += [ours, "n/a", "n/a"]
            else:
                cells += [ours, str(paper[i]), f"{_diff(fig[name], paper[i]):+.1f} %"]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def rules_markdown(by_rule: Mapping[str, Figures], chosen: str) -> str:
    """One row per exploration rule: the eight figures' differences and the worst one."""
    rates = [r for r in PAPER_RATES if all(r in f for f in by_rule.values())]
    header = ["rule"]
    header += [f"gestures {r * 100:.0f} %" for r in rates]
    header += [f"actions {r * 100:.0f} %" for r in rates]
    header.append("worst |diff|")
    body = []
    for rule, figures in by_rule.items():
        cells = [f"**{rule}** (used)" if rule == chosen else rule]
        for i, name in enumerate(("gestures", "actions")):
            for rate in rates:
                ours, paper = figures[rate][name], PAPER_TRAINING[rate][i]
                cells.append(f"{ours:.0f} vs {paper} ({_diff(ours, paper):+.0f} %)")
        cells.append(f"{worst_difference({r: figures[r] for r in rates}):.1f} %")
        body.append(cells)
    return markdown_table(header, body)
