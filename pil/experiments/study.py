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
from pil.experiments.paper import PAPER_RATES, PAPER_REPS, PAPER_TRAINING
from pil.experiments.paper_comparison import (
    Figures,
    claim_markdown,
    rule_training,
    rules_markdown,
    training_figures,
    training_markdown,
)
from pil.experiments.proactive_report import proactive_figures, proactive_markdown
from pil.experiments.report import (
    Row,
    summary_markdown,
    ttests_markdown,
    welch_ttests,
)
from pil.experiments.systems import (
    PAPER_SYSTEMS,
    ROW_COLUMNS,
    check_params,
    check_system,
    resolve_scenario,
    run_system,
)
from pil.task.parts import SCENARIO_KEYS
from pil.task.scenario import Scenario

STUDY_COLUMNS: tuple[str, ...] = ("rep", *ROW_COLUMNS)
METRICS: tuple[str, ...] = ("total_gestures", "total_actions")


@dataclass(frozen=True)
class StudyConfig:
    """What to run; the defaults are the paper's setup."""

    rates: tuple[float, ...] = PAPER_RATES
    reps: int = PAPER_REPS
    seed: int = 0
    systems: tuple[str, ...] = PAPER_SYSTEMS
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
        object.__setattr__(self, "systems", tuple(self.systems))
        for system in self.systems:
            check_system(system)
        if len(set(self.systems)) != len(self.systems) or not self.systems:
            raise RobinPilError(f"give each system once (at least one), got {self.systems!r}")
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


def training_by_rule(config: StudyConfig) -> dict[str, Figures]:
    """The training figures of every exploration rule at the study's rates (same seeds)."""
    values = check_params(dict(config.params))
    scenario = resolve_scenario(config.scenario, values)
    rates = sorted({*config.rates, 1.0})
    return rule_training(scenario, rates, rep_seeds(config.seed, config.reps), values)


def summary_text(
    rows: Sequence[Row], config: StudyConfig, by_rule: Mapping[str, Figures] | None = None
) -> str:
    """The study's ``summary.md`` (``by_rule``: :func:`training_by_rule`, to compare rules)."""
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
        "`total_*` include the pre-training of c1-c4 (5 tables), as the paper says its Figs. 3 "
        "and 4 do; `gestures` and `actions` are the test tables alone.",
        "",
        "## Mean ± sd per system and rate",
        "",
        summary_markdown(rows, ("rate", "system"), (*METRICS, "gestures", "actions")),
    ]
    figures = training_figures(rows)
    if figures:
        parts += ["", f"## Training (5 tables): ours ({values['exploration']}) vs the paper", "",
                  training_markdown(figures)]  # fmt: skip
    if by_rule:
        parts += [
            "",
            "## The paper's eight training figures under every exploration rule",
            "",
            "Same seeds and settings, only the rule after a not-OK differs "
            "(`pil.exploration`); ours vs the paper's, difference in %.",
            "",
            rules_markdown(by_rule, str(values["exploration"])),
        ]
    systems = {str(r["system"]) for r in rows}
    if {"pil", "c1", "c2"} <= systems:
        parts += [
            "",
            "## The paper's claim: at low rates PIL costs more than conditions 1 and 2",
            "",
            claim_markdown(rows),
        ]
    if "pil" in systems and len(systems) > 1:
        metrics = (*METRICS, "gestures", "actions")
        tests = welch_ttests(rows, "pil", compare_by="system", within=("rate",), metrics=metrics)
        significant = sum(1 for t in tests if t["p"] < 0.05)
        untestable = sum(1 for t in tests if t["p"] != t["p"])
        parts += [
            "",
            "## Welch t-tests: PIL against each other system",
            "",
            f"Totals (with training, as the paper) and the test tables alone (`gestures`, "
            f"`actions`). {significant} of {len(tests)} comparisons have p < 0.05 (marked *); "
            f"{untestable} have no p-value because both groups are constant.",
            "",
            ttests_markdown(tests, ("rate",)),
        ]
    proactive = proactive_figures(rows)
    if proactive:
        parts += [
            "",
            "## Proactive vs reactive PIL",
            "",
            "`proactive` acts on the likely next state before its gesture "
            f"(P >= {values['proactive_threshold']:g} on at least "
            f"{values['proactive_min_count']} transitions; `pil.anticipation`). Per repetition "
            "(same handover order and detector deck): gestures saved = pil's - proactive's; "
            "actions wasted = anticipations the person stopped. Test tables; Welch t-tests of "
            "pil vs proactive (p < 0.05 marked *).",
            "",
            proactive_markdown(proactive),
        ]
    return "\n".join(parts) + "\n"


def write_outputs(rows: Sequence[Row], config: StudyConfig, out: str | Path) -> list[Path]:
    """Write ``runs.csv``, ``summary.md``, ``gestures.png``, ``actions.png``, ``training.png``
    and, with ``pil`` and ``proactive`` among the systems, ``proactive.png``."""
    from pil.experiments.figures import plot_metric, plot_rules
    from pil.experiments.proactive_report import plot_proactive

    out = Path(out)
    figures = training_figures(rows)
    by_rule = training_by_rule(config) if figures else None
    written = [write_text_atomic(out / "runs.csv", csv_text(rows))]
    written.append(write_text_atomic(out / "summary.md", summary_text(rows, config, by_rule)))
    for metric, name in (("total_gestures", "gestures"), ("total_actions", "actions")):
        written.append(
            plot_metric(rows, metric, out / f"{name}.png", ("rate", "system"),
                        title=f"{name} to assemble the tables (mean ± sd)",
                        ylabel=f"number of {name}")
        )  # fmt: skip
    if by_rule:
        written.append(plot_rules(by_rule, PAPER_TRAINING, out / "training.png"))
    proactive = proactive_figures(rows)
    if proactive:
        written.append(plot_proactive(proactive, out / "proactive.png"))
    return written
