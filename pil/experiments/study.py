"""The paper's simulation study (section IV-B): five systems, four rates, 20 repetitions.

:func:`run_study` returns one row per run (see :data:`pil.experiments.run_row.ROW_COLUMNS`, plus
``rep``);
:func:`write_outputs` writes ``runs.csv``, ``tests.csv`` (paired tests of PIL against every
other system, :mod:`pil.experiments.study_tests`), ``summary.md`` and the figures; with pil, c1
and c2 at a low rate also ``claim_runs.csv`` (those three re-run under the other reading of a
discarded gesture, for the paper's claim). Repetition ``r``
gets its seed from ``numpy.random.SeedSequence(seed).spawn``; every system and rate of one
repetition uses that seed (common random numbers: same handover order, same detector deck).
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from pil.atomic import write_text_atomic
from pil.errors import RobinPilError
from pil.experiments import report
from pil.experiments.paper import LOW_RATES, PAPER_RATES, PAPER_REPS, PAPER_TRAINING
from pil.experiments.paper_comparison import (
    Figures,
    rule_training,
    rules_markdown,
    training_figures,
    training_markdown,
)
from pil.experiments.proactive_report import proactive_figures, proactive_markdown
from pil.experiments.rep_journal import RepJournal
from pil.experiments.report import Row, summary_markdown
from pil.experiments.run_row import ROW_COLUMNS, spec_row
from pil.experiments.stats import PAIRED_T, csv_columns, describe_tests, tests_markdown
from pil.experiments.study_tests import (
    CLAIM_SYSTEMS,
    TEST_TABLES,
    TRAINING_INCLUDED,
    claim_markdown,
    claim_rows,
    discard_reading,
    study_tests,
)
from pil.file_names import RUNS_NAME
from pil.task.detector import MEASURED_PREFIX, load_measured
from pil.task.params import RATE, REPS, SEED
from pil.task.scenario import Scenario
from pil.task.spec import RunSpec, parse_run_spec
from pil.task.systems import PAPER_SYSTEMS, check_system

STUDY_COLUMNS: tuple[str, ...] = ("rep", *ROW_COLUMNS)
METRICS: tuple[str, ...] = ("total_gestures", "total_actions")


@dataclass(frozen=True)
class StudyConfig:
    """What to run; the defaults are the paper's setup."""

    # given as numbers or text: parsed here, once; DETECTOR_RATES (none given): the
    # detector's own (a measured file's measured rate, else the paper's rates)
    rates: tuple[float, ...] = PAPER_RATES
    reps: int = PAPER_REPS
    seed: int = 0
    systems: tuple[str, ...] = PAPER_SYSTEMS
    scenario: Scenario | str | Path | None = None
    params: Mapping[str, Any] = field(default_factory=dict)  # see pil.task.params.PARAMS
    labels: Mapping[str, str] = field(default_factory=dict, compare=False)  # names in messages
    # the runs' spec: scenario and params parsed once, here (the system, rate and seed vary)
    base: RunSpec = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.rates:
            label = self.labels.get("rate", "detection rate")
            rates = tuple(RATE.parse(r, label) for r in self.rates)
            object.__setattr__(self, "rates", rates)
            repeated = sorted({r for r in rates if rates.count(r) > 1})
            if repeated:
                raise RobinPilError(f"rate {repeated[0]:g} is given twice; give each rate once")
        named = self.labels.get
        object.__setattr__(self, "seed", SEED.parse(self.seed, named("seed", "seed")))
        object.__setattr__(self, "systems", tuple(self.systems))
        for system in self.systems:
            check_system(system, named("system", "system"))
            if self.systems.count(system) > 1:
                raise RobinPilError(f"system {system!r} is given twice; give each system once")
        if not self.systems:
            raise RobinPilError("no system given: give at least one")
        object.__setattr__(self, "reps", REPS.parse(self.reps, named("reps", "reps")))
        base = parse_run_spec(scenario=self.scenario, params=self.params, labels=self.labels)
        object.__setattr__(self, "base", base)
        if not self.rates:
            object.__setattr__(self, "rates", detector_rates(base.detector.model))

    def for_seed(self, seed: int) -> StudyConfig:
        """This study with another master seed (a whole number >= 0, e.g. of
        :func:`pil.experiments.study_seeds.seeds_of`): its checked values, not parsed again."""
        other = copy.copy(self)
        object.__setattr__(other, "seed", seed)
        return other

    def runs(self) -> int:
        """How many runs the study makes."""
        return len(self.rates) * self.reps * len(self.systems)


DETECTOR_RATES: tuple[float, ...] = ()  # a study's rates: the detector's own


def detector_rates(model: str) -> tuple[float, ...]:
    """The rates a detection model runs at by default: a measured file's measured rate (the
    file as read when its name was parsed), else the paper's rates."""
    if model.startswith(MEASURED_PREFIX):
        return (round(load_measured(model[len(MEASURED_PREFIX) :]).rate, 4),)
    return PAPER_RATES


def rep_seeds(seed: int, reps: int) -> list[int]:
    """One seed per repetition, derived from ``seed`` (independent streams)."""
    children = np.random.SeedSequence(seed).spawn(reps)
    return [int(child.generate_state(1, np.uint64)[0] >> 1) for child in children]


def journal_settings(config: StudyConfig) -> dict[str, Any]:
    """What makes two studies' repetitions the same (:class:`RepJournal`'s key): all but the
    number of repetitions (repetition ``r``'s seed does not depend on it)."""
    return {
        "study": "study",
        "rates": list(config.rates),
        "systems": list(config.systems),
        "seed": config.seed,
        "scenario": repr(config.base.scenario),
        "params": config.base.values(),
    }


def run_study(
    config: StudyConfig,
    progress: Callable[[int], None] | None = None,
    journal: RepJournal | None = None,
) -> list[dict[str, Any]]:
    """All runs of the study, ordered by rate, system and repetition. With a ``journal``
    (of :func:`journal_settings`), each finished repetition is kept there as it ends and one
    kept already is read back, not run again."""
    base = config.base  # checked once, by the config
    seeds = rep_seeds(config.seed, config.reps)
    rows: list[dict[str, Any]] = []
    for rep, seed in enumerate(seeds):
        kept = None if journal is None else journal.finished(rep, seed)
        if kept is not None:
            rows += kept
            if progress is not None:
                progress(len(kept))
            continue
        cache: dict[Any, Any] = {}  # training runs and scripts shared within this rep
        these = []
        for rate in config.rates:
            for system in config.systems:
                row = spec_row(base.for_run(system, rate, seed), cache)
                these.append({"rep": rep, **row})
                if progress is not None:
                    progress(1)
        rows += these if journal is None else journal.add(rep, seed, these)
    order = {s: i for i, s in enumerate(config.systems)}
    rows.sort(key=lambda r: (r["rate"], order[r["system"]], r["rep"]))
    return rows


def csv_text(rows: Sequence[Row], columns: Sequence[str] = STUDY_COLUMNS) -> str:
    """The study's rows as CSV text (:func:`pil.experiments.report.csv_text`)."""
    return report.csv_text(rows, columns)


def training_by_rule(config: StudyConfig) -> dict[str, Figures]:
    """The training figures of every exploration rule at the study's rates (same seeds)."""
    base = config.base
    rates = sorted({*config.rates, 1.0})
    return rule_training(base, rates, rep_seeds(config.seed, config.reps))


def claim_config(config: StudyConfig) -> StudyConfig | None:
    """pil, c1 and c2 at the study's low rates under the other reading of a discarded gesture
    (same seeds), or None when the study lacks them."""
    rates = tuple(r for r in config.rates if r in LOW_RATES)
    if not rates or not {"pil", *CLAIM_SYSTEMS} <= set(config.systems):
        return None
    repeat = not config.base.detector.repeat_discarded
    claim = copy.copy(config)  # the study's checked values, not parsed again
    typed = {
        "rates": rates,
        "systems": ("pil", *CLAIM_SYSTEMS),
        "params": {**config.params, "repeat_discarded": repeat},
        "base": config.base.changed({"repeat_discarded": repeat}),
    }
    for name, value in typed.items():
        object.__setattr__(claim, name, value)
    return claim


def all_tests(rows: Sequence[Row], claim: Sequence[Row] | None = None) -> list[dict[str, Any]]:
    """The rows of ``tests.csv``: the study's, then the claim runs' (their readings name the
    discard reading, e.g. ``test tables only; discarded corrected``)."""
    tests = study_tests(rows)
    if claim:
        tests += study_tests(claim, f"; discarded {discard_reading(claim[0]['repeat_discarded'])}")
    return tests


def summary_text(
    rows: Sequence[Row],
    config: StudyConfig,
    by_rule: Mapping[str, Figures] | None = None,
    tests: Sequence[Mapping[str, Any]] | None = None,
) -> str:
    """The study's ``summary.md`` (``by_rule``: :func:`training_by_rule`, to compare rules;
    ``tests``: :func:`all_tests`, by default the study's own)."""
    tests = study_tests(rows) if tests is None else tests
    values = config.base.values()  # the scenario's assembly fields included
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
        parts += [
            "",
            f"## Training (5 tables): ours ({values['exploration']}) vs the paper",
            "",
            training_markdown(figures),
        ]
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
    ran = discard_reading(values["repeat_discarded"])
    if claim_rows(tests):
        rerun = any(";" in str(t["reading"]) for t in tests)
        parts += [
            "",
            "## The paper's claim",
            "",
            "At 40 and 60 % PIL needs more gestures and more actions than conditions 1 and 2 "
            "(section IV-B). Read from the paired tests below (the same rows as `tests.csv`): "
            "PIL − condition per repetition, Holm-adjusted p of the paired t-test and of the "
            "Wilcoxon signed-rank test; a comparison counts when both are < 0.05 and PIL "
            "needs more. Readings: training included (the paper's figures) or the test "
            "tables only; a discarded gesture repeated by the person (the project's reading, "
            "`--discarded repeated`) or corrected as an invalid state (the paper's section I, "
            f"`--discarded corrected`). This study ran `{ran}`"
            + (
                ", the other reading re-ran pil, c1 and c2 on the same seeds (`claim_runs.csv`)."
                if rerun
                else "."
            ),
            "",
            claim_markdown(tests, ran),
        ]
    main = [t for t in tests if t["reading"] in (TRAINING_INCLUDED, TEST_TABLES)]
    if main:
        parts += [
            "",
            "## Paired tests: PIL against each other system",
            "",
            "Every system and rate of one repetition shares its seed (handover order, detector "
            "deck), so the runs pair by repetition. "
            + describe_tests(main)
            + " All rows in `tests.csv`.",
            "",
            tests_markdown([t for t in main if t["test"] == PAIRED_T]),
        ]
    proactive = proactive_figures(rows, tests)
    if proactive:
        parts += [
            "",
            "## Proactive vs reactive PIL",
            "",
            "`proactive` acts on the likely next state before its gesture "
            f"(P >= {values['proactive_threshold']:g} on at least "
            f"{values['proactive_min_count']} transitions; `pil.anticipation`). Per repetition "
            "(same handover order and detector deck): gestures saved = pil's - proactive's; "
            "actions wasted = anticipations the person stopped. Test tables; p: Holm-adjusted "
            "paired t-tests of pil vs proactive (by repetition; the rows of `tests.csv`; "
            "< 0.05 marked *).",
            "",
            proactive_markdown(proactive),
        ]
    return "\n".join(parts) + "\n"


def write_outputs(rows: Sequence[Row], config: StudyConfig, out: str | Path) -> list[Path]:
    """Write ``runs.csv``, ``tests.csv``, ``summary.md``, ``gestures.png``, ``actions.png``,
    ``training.png``, with pil, c1 and c2 at a low rate ``claim_runs.csv`` and, with ``pil``
    and ``proactive`` among the systems, ``proactive.png``."""
    from pil.experiments.figures import plot_metric, plot_rules
    from pil.experiments.proactive_report import plot_proactive

    out = Path(out)
    figures = training_figures(rows)
    by_rule = training_by_rule(config) if figures else None
    other = claim_config(config)
    claim = run_study(other) if other is not None else None
    tests = all_tests(rows, claim)
    written = [write_text_atomic(out / RUNS_NAME, csv_text(rows))]
    if claim:
        written.append(write_text_atomic(out / "claim_runs.csv", csv_text(claim)))
    if tests:
        written.append(write_text_atomic(out / "tests.csv", csv_text(tests, csv_columns())))
    written.append(
        write_text_atomic(out / "summary.md", summary_text(rows, config, by_rule, tests))
    )
    for metric, name in (("total_gestures", "gestures"), ("total_actions", "actions")):
        written.append(
            plot_metric(
                rows,
                metric,
                out / f"{name}.png",
                ("rate", "system"),
                title=f"{name} to assemble the tables (mean ± sd)",
                ylabel=f"number of {name}",
            )
        )
    if by_rule:
        written.append(plot_rules(by_rule, PAPER_TRAINING, out / "training.png"))
    proactive = proactive_figures(rows, tests)
    if proactive:
        written.append(plot_proactive(proactive, out / "proactive.png"))
    return written
