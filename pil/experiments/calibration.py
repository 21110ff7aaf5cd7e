"""The paper's training figures as a calibration and a validation, not as a replication.

Three choices of this project are free where the paper is silent, and each moves the eight
training figures (:data:`pil.experiments.paper.PAPER_TRAINING`): the exploration rule after a
not-OK (``next-best`` or the others of :mod:`pil.exploration`), ``discard`` (the share of
misses discarded as low-confidence, 0.5) and the handover types D-J. :func:`fit` chooses rule
and discard on the *calibration* rates only (40 % and 100 %: the fewest worst |difference|
from the paper over those four figures); :func:`validate` then predicts the *validation*
rates (60 % and 80 %) with the chosen setting: mean with its 95 % interval and the per-run
95 % prediction interval (mean ± t·sd·√(1 + 1/n)), and whether the paper's value falls
inside either. :func:`sensitivity` sweeps discard and the set of handover types at every
rate. A training run is the conditions' pre-training: a PIL run with correction on the
scenario's training tables (:func:`pil.task.assemble.assemble`, phase ``"train"``).
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

from pil.experiments.paper import PAPER_TRAINING
from pil.experiments.stats import mean_ci
from pil.exploration import RULES
from pil.task.spec import RunSpec

CALIBRATION_RATES: tuple[float, ...] = (0.4, 1.0)
VALIDATION_RATES: tuple[float, ...] = (0.6, 0.8)
DISCARDS: tuple[float, ...] = (0.3, 0.4, 0.5, 0.6, 0.7)
SENSITIVITY_DISCARDS: tuple[float, ...] = (0.1, 0.3, 0.5, 0.7, 0.9)
#: name -> handover types used (``A-J`` is the shipped set; A-C are the paper's Table I)
TYPE_SETS: dict[str, tuple[str, ...]] = {
    "A-J": tuple("ABCDEFGHIJ"),
    "A-C": tuple("ABC"),
    "A-G": tuple("ABCDEFG"),
    "A-C+H-J": tuple("ABCHIJ"),
}
DEFAULT_CHOICE: tuple[str, float] = ("next-best", 0.5)
TRAINING_FIGURES: tuple[str, ...] = ("gestures", "actions")


def with_types(base: RunSpec, names: Sequence[str]) -> RunSpec:
    """``base`` whose scenario draws only the handover types ``names``."""
    return replace(base, scenario=replace(base.scenario, sequence=tuple(names)))


def training_runs(spec: RunSpec, rate: float, seeds: Sequence[int]) -> list[tuple[int, int]]:
    """(gestures, actions) of the training run at ``rate`` for every seed."""
    from pil.task.assemble import assemble

    out = []
    for seed in seeds:
        stats = assemble(spec.for_run("pil", rate, seed), phase="train").run()
        out.append((stats.gestures, stats.actions))
    return out


def _diff(ours: float, paper: float) -> float:
    return 100.0 * (ours - paper) / paper


def figure_rows(
    label: Mapping[str, Any], rate: float, runs: Sequence[tuple[int, int]]
) -> list[dict[str, Any]]:
    """One row per figure (gestures, actions) of ``runs`` at ``rate``: the mean, its 95 %
    CI, the per-run 95 % prediction interval, the paper's value and where it falls."""
    from scipy.stats import t as t_dist

    out = []
    for i, name in enumerate(TRAINING_FIGURES):
        values = [float(r[i]) for r in runs]
        mean, low, high = mean_ci(values)
        n = len(values)
        sd = statistics.stdev(values) if n > 1 else math.nan
        if n > 1 and sd > 0:
            half = float(t_dist.ppf(0.975, n - 1)) * sd * math.sqrt(1 + 1 / n)
            pi_low, pi_high = mean - half, mean + half
        else:
            pi_low = pi_high = math.nan
        paper = float(PAPER_TRAINING[rate][i])
        out.append(
            {
                **label,
                "rate": rate,
                "figure": name,
                "n": n,
                "mean": mean,
                "ci_low": low,
                "ci_high": high,
                "pi_low": pi_low,
                "pi_high": pi_high,
                "min": min(values),
                "max": max(values),
                "paper": paper,
                "diff_percent": _diff(mean, paper),
                "paper_in_ci": not math.isnan(low) and low <= paper <= high,
                "paper_in_pi": not math.isnan(pi_low) and pi_low <= paper <= pi_high,
                "paper_possible": min(values) <= paper <= max(values),
            }
        )
    return out


def fit(base: RunSpec, seeds: Sequence[int]) -> tuple[list[dict[str, Any]], tuple[str, float]]:
    """Every rule and discard of the grid at the calibration rates (rows of
    :func:`figure_rows` with ``rule``, ``discard``) and the chosen (rule, discard): the
    fewest worst |difference| over the calibration figures (ties: the grid's order)."""
    rows: list[dict[str, Any]] = []
    scores: dict[tuple[str, float], float] = {}
    for rule in RULES:
        for discard in DISCARDS:
            spec = base.changed({"exploration": rule, "discard": discard})
            found: list[dict[str, Any]] = []
            for rate in CALIBRATION_RATES:
                label = {"rule": rule, "discard": discard}
                found += figure_rows(label, rate, training_runs(spec, rate, seeds))
            scores[(rule, discard)] = max(abs(r["diff_percent"]) for r in found)
            rows += found
    chosen = min(scores, key=lambda k: scores[k])
    return rows, chosen


def validate(
    base: RunSpec, seeds: Sequence[int], choices: Sequence[tuple[str, float]]
) -> list[dict[str, Any]]:
    """The validation rates' figures under each (rule, discard) of ``choices``."""
    rows: list[dict[str, Any]] = []
    for rule, discard in dict.fromkeys(choices):
        spec = base.changed({"exploration": rule, "discard": discard})
        for rate in VALIDATION_RATES:
            label = {"rule": rule, "discard": discard}
            rows += figure_rows(label, rate, training_runs(spec, rate, seeds))
    return rows


def sensitivity(
    base: RunSpec, seeds: Sequence[int], rates: Sequence[float] = tuple(PAPER_TRAINING)
) -> list[dict[str, Any]]:
    """Every discard of :data:`SENSITIVITY_DISCARDS` and type set of :data:`TYPE_SETS` at
    ``rates`` (the default rule): rows of :func:`figure_rows` with ``types``, ``discard``."""
    rows: list[dict[str, Any]] = []
    for name, types in TYPE_SETS.items():
        typed = with_types(base, types)
        for discard in SENSITIVITY_DISCARDS:
            spec = typed.changed({"discard": discard})
            for rate in rates:
                label = {"types": name, "discard": discard}
                rows += figure_rows(label, rate, training_runs(spec, rate, seeds))
    return rows
