"""The paper's simulation study (section IV-B): five systems, four rates, 20 repetitions.

:func:`run_study` returns one row per run (see :data:`pil.experiments.systems.ROW_COLUMNS`, plus
``rep``);
:func:`write_outputs` writes ``runs.csv``, ``summary.md`` and the figures. Repetition ``r``
gets its seed from ``numpy.random.SeedSequence(seed).spawn``; every system and rate of one
repetition uses that seed (common random numbers: same handover order, same detector deck).
"""

from __future__ import annotations

import csv
import io
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from pil.atomic import write_text_atomic
from pil.errors import RobinPilError, check_rate
from pil.experiments.report import (
    Row,
    group_rows,
    mean_sd,
    number,
    summary_markdown,
    ttests_markdown,
    welch_ttests,
)
from pil.experiments.systems import (
    ROW_COLUMNS,
    SYSTEMS,
    check_params,
    check_system,
    resolve_scenario,
    run_system,
)
from pil.task.parts import SCENARIO_KEYS
from pil.task.scenario import Scenario

PAPER_RATES: tuple[float, ...] = (0.4, 0.6, 0.8, 1.0)
# The paper's training figures (5 tables): rate -> (gestures, actions)
PAPER_TRAINING: dict[float, tuple[int, int]] = {
    0.4: (170, 222),
    0.6: (148, 203),
    0.8: (126, 181),
    1.0: (111, 144),
}
STUDY_COLUMNS: tuple[str, ...] = ("rep", *ROW_COLUMNS)
METRICS: tuple[str, ...] = ("total_gestures", "total_actions")


@dataclass(frozen=True)
class StudyConfig:
    """What to run; the defaults are the paper's setup."""

    rates: tuple[float, ...] = PAPER_RATES
    reps: int = 20
    seed: int = 0
    systems: tuple[str, ...] = tuple(SYSTEMS)
    scenario: Scenario | str | Path | None = None
    params: Mapping[str, Any] = field(default_factory=dict)  # see pil.experiments.systems.PARAMS

    def __post_init__(self) -> None:
        object.__setattr__(self, "rates", tuple(check_rate(r) for r in self.rates))
        repeated = sorted({r for r in self.rates if self.rates.count(r) > 1})
        if repeated:
            raise RobinPilError(f"rate {repeated[0]:g} is given twice; give each rate once")
        seed = self.seed
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise RobinPilError(f"seed must be a whole number >= 0, got {seed!r}")
        for system in self.systems:
            check_system(system)
        if isinstance(self.reps, bool) or not isinstance(self.reps, int) or self.reps < 1:
            raise RobinPilError(f"reps must be a whole number >= 1, got {self.reps!r}")

    def runs(self) -> int:
        """How many runs the study makes."""
        return len(self.rates) * self.reps * len(self.systems)


def rep_seeds(seed: int, reps: int) -> list[int]:
    """One seed per repetition, derived from ``seed`` (independent streams)."""
    children = np.random.SeedSequence(seed).spawn(reps)
    return [int(child.generate_state(1, np.uint64)[0] >> 1) for child in children]


def run_study(
    config: StudyConfig, progress: Callable[[int], None] | None = None
) -> list[dict[str, Any]]:
    """All runs of the study, ordered by rate, system and repetition."""
    values = check_params(dict(config.params))
    scenario = resolve_scenario(config.scenario, values)
    seeds = rep_seeds(config.seed, config.reps)
    rows: list[dict[str, Any]] = []
    for rep, seed in enumerate(seeds):
        cache: dict[Any, Any] = {}  # training runs and scripts shared within this rep
        for rate in config.rates:
            for system in config.systems:
                row = run_system(system, rate, seed, scenario, values, cache)
                rows.append({"rep": rep, **row})
                if progress is not None:
                    progress(1)
    order = {s: i for i, s in enumerate(config.systems)}
    rows.sort(key=lambda r: (r["rate"], order[r["system"]], r["rep"]))
    return rows


def csv_text(rows: Sequence[Row], columns: Sequence[str] = STUDY_COLUMNS) -> str:
    """The rows as CSV text (fixed columns, ``\\n`` line ends: byte-reproducible)."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(columns), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return buffer.getvalue()


def training_figures(rows: Sequence[Row]) -> dict[float, dict[str, float]]:
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
    out: dict[float, dict[str, float]] = {}
    for rate in sorted({k[0] for k in runs}):
        gestures = [g for (r, _), (g, _a) in runs.items() if r == rate]
        actions = [a for (r, _), (_g, a) in runs.items() if r == rate]
        (g_mean, g_sd), (a_mean, a_sd) = mean_sd(gestures), mean_sd(actions)
        out[rate] = {"gestures": g_mean, "gestures_sd": g_sd, "actions": a_mean,
                     "actions_sd": a_sd, "n": len(gestures)}  # fmt: skip
    return out


def training_markdown(figures: Mapping[float, Mapping[str, float]]) -> str:
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
                diff = 100.0 * (fig[name] - paper[i]) / paper[i]
                cells += [ours, str(paper[i]), f"{diff:+.1f} %"]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def summary_text(rows: Sequence[Row], config: StudyConfig) -> str:
    """The study's ``summary.md``."""
    values = check_params(dict(config.params))
    scenario = resolve_scenario(config.scenario, values)
    values.update({key: getattr(scenario, key) for key in SCENARIO_KEYS})
    setup = ", ".join(f"{k}={v}" for k, v in values.items())
    parts = [
        "# PIL study: gestures and actions per system and detection rate",
        "",
        f"Rates {', '.join(f'{r:g}' for r in config.rates)}; {config.reps} repetitions; "
        f"seed {config.seed}; systems {', '.join(config.systems)}.  ",
        f"Parameters: {setup}.",
        "",
        "Totals include the pre-training of c1-c4 (5 tables), as in the paper's Figs. 3 and 4.",
        "",
        "## Mean ± sd per system and rate",
        "",
        summary_markdown(rows, ("rate", "system"), (*METRICS, "gestures", "actions")),
    ]
    figures = training_figures(rows)
    if figures:
        parts += ["", "## Training (5 tables): ours vs the paper", "", training_markdown(figures)]
    systems = {str(r["system"]) for r in rows}
    if "pil" in systems and len(systems) > 1:
        metrics = (*METRICS, "gestures", "actions")
        tests = welch_ttests(rows, "pil", compare_by="system", within=("rate",), metrics=metrics)
        significant = sum(1 for t in tests if t["p"] < 0.05)
        untestable = sum(1 for t in tests if t["p"] != t["p"])
        parts += [
            "",
            "## Welch t-tests: PIL against each condition",
            "",
            f"Totals (with training, as the paper) and the test tables alone (`gestures`, "
            f"`actions`). {significant} of {len(tests)} comparisons have p < 0.05 (marked *); "
            f"{untestable} have no p-value because both groups are constant.",
            "",
            ttests_markdown(tests, ("rate",)),
        ]
    return "\n".join(parts) + "\n"


def write_outputs(rows: Sequence[Row], config: StudyConfig, out: str | Path) -> list[Path]:
    """Write ``runs.csv``, ``summary.md``, ``gestures.png``, ``actions.png``, ``training.png``."""
    from pil.experiments.figures import plot_comparison, plot_metric

    out = Path(out)
    written = [write_text_atomic(out / "runs.csv", csv_text(rows))]
    written.append(write_text_atomic(out / "summary.md", summary_text(rows, config)))
    for metric, name in (("total_gestures", "gestures"), ("total_actions", "actions")):
        written.append(
            plot_metric(rows, metric, out / f"{name}.png", ("rate", "system"),
                        title=f"{name} to assemble the tables (mean ± sd)",
                        ylabel=f"number of {name}")
        )  # fmt: skip
    figures = training_figures(rows)
    if figures:
        ours = {f"{r * 100:.0f} %": {"gestures": f["gestures"], "actions": f["actions"]}
                for r, f in figures.items()}  # fmt: skip
        paper = {f"{r * 100:.0f} %": {"gestures": g, "actions": a}
                 for r, (g, a) in PAPER_TRAINING.items()}  # fmt: skip
        written.append(plot_comparison(ours, paper, out / "training.png"))
    return written


def rows_by_system(rows: Sequence[Row]) -> dict[str, list[Row]]:
    """Rows grouped by system (a convenience for callers and tests)."""
    return {key[0]: members for key, members in group_rows(rows, ["system"]).items()}
