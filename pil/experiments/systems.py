"""The study's systems (the paper's five, section IV-B, and baselines) and :func:`run_one`.

* ``pil``: Proactive Incremental Learning from scratch, with correction, on the test tables.
* ``c1``: pre-trained at the test rate d, with correction.
* ``c2``: pre-trained at 100 %, with correction.
* ``c3``: pre-trained at d, manual repetition (the person repeats a misread gesture).
* ``c4``: pre-trained at 100 %, manual repetition.
* ``proactive`` (ours): ``pil`` that acts on the likely next state before its gesture
  (:mod:`pil.anticipation`); ``pil-halve`` (ours): a not-OK halves the refused count.
* ``bandit``, ``tamer``: the baselines of :mod:`pil.agents`, from scratch, same person, detector
  and counting (they act on the detected state as it is: no correction).

Pre-training is a PIL run (with correction) on ``training_tables`` tables (5 x 4 = 20
handovers, each handover type exactly twice). Its gestures and actions are reported apart
(``train_gestures``, ``train_actions``) and added to the totals, as the paper does. The learner
keeps learning during the test. A run's sub-seeds (handover order, detector, learner, person)
derive from ``seed`` alone, not from the system or the rate, so all systems of one repetition
face the same handover order and detector deck (common random numbers); c1 and c3 therefore
share one training run, and c2 and c4 another.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, MutableMapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pil.agents import AGENTS
from pil.errors import InvalidChoiceError, check_rate
from pil.experiments.run_row import ROW_COLUMNS, run_row
from pil.learner import Learner
from pil.table import AssociationTable
from pil.task.params import SCENARIO
from pil.task.parts import (
    PARAMS,
    SCENARIO_KEYS,
    RunParts,
    build_parts,
    cached,
    check_params,
    derive_seeds,
    resolve_scenario,
)
from pil.task.person import PersonBody
from pil.task.runner import RunStats, run
from pil.task.scenario import Scenario
from pil.task.world import SymbolicWorld

__all__ = [
    "PAPER_SYSTEMS",
    "PARAMS",
    "ROW_COLUMNS",
    "SYSTEMS",
    "SYSTEM_SPECS",
    "check_params",
    "check_run",
    "check_system",
    "derive_seeds",
    "resolve_scenario",
    "run_one",
    "test_parts",
    "training_for",
]


@dataclass(frozen=True, slots=True)
class SystemSpec:
    """How one study system learns and is tested.

    ``trained_at``: None (from scratch), "d" (pre-trained at the test rate) or "full" (at 100 %);
    ``manual``: the person repeats a misread gesture (no correction); ``agent``: a key of
    :data:`pil.agents.AGENTS` (pre-training is always a PIL run); ``params``: parameters of
    :data:`PARAMS` this system sets for its test run.
    """

    description: str
    trained_at: str | None = None
    manual: bool = False
    agent: str = "pil"
    params: Mapping[str, Any] = field(default_factory=dict)  # parameters it overrides


# The registry of study systems; add an entry to make a new one selectable everywhere.
SYSTEM_SPECS: dict[str, SystemSpec] = {
    "pil": SystemSpec("PIL from scratch, with correction"),
    "c1": SystemSpec("pre-trained at d, with correction", "d"),
    "c2": SystemSpec("pre-trained at 100 %, with correction", "full"),
    "c3": SystemSpec("pre-trained at d, manual repetition", "d", manual=True),
    "c4": SystemSpec("pre-trained at 100 %, manual repetition", "full", manual=True),
    "bandit": SystemSpec("epsilon-greedy contextual bandit from scratch", agent="bandit"),
    "tamer": SystemSpec("TAMER-style feedback regression from scratch", agent="tamer"),
    "pil-halve": SystemSpec(
        "PIL from scratch, a not-OK halves the refused count (ours)",
        params={"adaptation": "halve"},
    ),
    "proactive": SystemSpec(
        "PIL from scratch, acting on the likely next state before its gesture (ours)",
        params={"proactive": True},
    ),
}
PAPER_SYSTEMS: tuple[str, ...] = ("pil", "c1", "c2", "c3", "c4")


class _Descriptions(Mapping[str, str]):
    """A read-only view: system name -> description, always in step with SYSTEM_SPECS."""

    def __getitem__(self, name: str) -> str:
        return SYSTEM_SPECS[name].description

    def __iter__(self) -> Iterator[str]:
        return iter(SYSTEM_SPECS)

    def __len__(self) -> int:
        return len(SYSTEM_SPECS)


SYSTEMS: Mapping[str, str] = _Descriptions()


@dataclass(frozen=True, slots=True)
class Training:
    """The outcome of a pre-training run: the learnt table and what it cost."""

    table: AssociationTable
    stats: RunStats


def check_system(system: str) -> str:
    """``system`` if it is one of :data:`SYSTEMS`, else an error naming them."""
    if system not in SYSTEM_SPECS:
        raise InvalidChoiceError("system", system, SYSTEM_SPECS)
    return system


def simulate(
    scenario: Scenario,
    rate: float,
    seeds: Mapping[str, int],
    phase: str,
    values: Mapping[str, Any],
    *,
    table: AssociationTable | None = None,
    manual: bool = False,
    cache: MutableMapping[Any, Any] | None = None,
) -> tuple[Learner, RunStats]:
    """One learner-only run of ``phase`` ("train" or "test") at ``rate``."""
    parts = build_parts(
        scenario, rate, seeds, phase=phase, table=table, manual=manual, cache=cache, **values
    )
    stats = run(parts.learner, parts.person, parts.detector, SymbolicWorld(), **parts.options)
    learner = parts.learner
    return learner, stats


def pretrain(
    scenario: Scenario,
    rate: float,
    seeds: Mapping[str, int],
    values: Mapping[str, Any],
    cache: MutableMapping[Any, Any] | None = None,
) -> Training:
    """A PIL run with correction on the training tables at ``rate``."""
    learner, stats = simulate(scenario, rate, seeds, "train", values, cache=cache)
    return Training(learner.table, stats)


def training_for(
    system: str,
    rate: float,
    seed: int,
    scenario: Scenario,
    values: Mapping[str, Any],
    cache: MutableMapping[Any, Any] | None = None,
) -> Training | None:
    """The pre-training ``system`` starts from (None for ``pil``), from ``cache`` if there."""
    trained_at = SYSTEM_SPECS[check_system(system)].trained_at
    if trained_at is None:
        return None
    train_rate = check_rate(rate) if trained_at == "d" else 1.0
    key = ("training", train_rate, int(seed))
    return cached(
        cache, key, lambda: pretrain(scenario, train_rate, derive_seeds(seed), values, cache)
    )


def test_parts(
    system: str,
    rate: float,
    seed: int,
    scenario: Scenario,
    values: Mapping[str, Any],
    cache: MutableMapping[Any, Any] | None = None,
    training: Training | None = None,
    body: PersonBody | None = None,
) -> RunParts:
    """Learner (pre-trained for c1-c4), person and detector for ``system``'s test tables.

    ``values`` are checked parameters (:func:`check_params`); the physical episode drives these
    parts through :func:`pil.task.runner.steps` with its own world. ``training`` defaults to
    :func:`training_for`; ``body`` is the person's body in a physical world.
    """
    spec = SYSTEM_SPECS[check_system(system)]
    if training is None:
        training = training_for(system, rate, seed, scenario, values, cache)
    table = None if training is None else training.table.copy()
    seeds = derive_seeds(seed)
    values = {**values, **spec.params}
    parts = build_parts(
        scenario,
        rate,
        seeds,
        phase="test",
        table=table,
        manual=spec.manual,
        cache=cache,
        body=body,
        **values,
    )
    if spec.agent == "pil":
        return parts
    agent = AGENTS[spec.agent](seeds["test_learner"], table, values)
    return RunParts(agent, parts.person, parts.detector, parts.options)  # type: ignore[arg-type]


test_parts.__test__ = False  # type: ignore[attr-defined]  # not a pytest test


def run_system(
    system: str,
    rate: float,
    seed: int,
    scenario: Scenario,
    values: Mapping[str, Any],
    cache: MutableMapping[Any, Any] | None = None,
) -> dict[str, Any]:
    """:func:`run_one` on a resolved scenario and checked parameters.

    ``cache`` (a dict) lets a study reuse what the systems of one repetition share (training
    runs, the person's scripts); share it only between calls with the same scenario, the same
    parameters and the same ``seed``'s sub-seeds. Results are the same with or without it.
    """
    rate = check_rate(rate)
    training = training_for(system, rate, seed, scenario, values, cache)
    parts = test_parts(system, rate, seed, scenario, values, cache, training)
    stats = run(parts.learner, parts.person, parts.detector, SymbolicWorld(), **parts.options)
    train = RunStats() if training is None else training.stats
    effective = {**values, **SYSTEM_SPECS[system].params}
    used = {name: effective[name] for name in PARAMS}
    used.update({name: getattr(scenario, name) for name in SCENARIO_KEYS})
    run_cells = {"system": system, "rate": rate, "seed": int(seed), "scenario": scenario.name}
    return run_row(run_cells, stats, train, used)


def check_run(system: str, rate: float, seed: int, **params: Any) -> Scenario:
    """Everything :func:`run_one` checks before it runs (system, rate, seed, parameters, the
    scenario file); returns the resolved scenario. A sweep calls it before its first run."""
    check_system(system)
    check_rate(rate)
    derive_seeds(seed)
    scenario = params.pop("scenario", None)
    values = check_params({**params, "detector": params.pop("detector", "exact")})
    return resolve_scenario(SCENARIO.parse(scenario, "scenario"), values)


def run_one(
    system: str,
    rate: float,
    seed: int,
    *,
    tables: int | None = None,
    scenario: Scenario | str | Path | None = None,
    detector: str = "exact",
    **params: Any,
) -> dict[str, Any]:
    """One learner-only run of ``system`` at detection rate ``rate``: a flat CSV row.

    ``tables`` and the other assembly fields default to the scenario file's (10 tables in
    ``scenarios/assembly.yaml``). ``params`` are any of :data:`PARAMS` (e.g. ``discard=0.3``,
    ``silent_ok=0.1``, ``legs_per_table=4``); an unknown name raises an error listing the
    valid ones. The row's columns are :data:`ROW_COLUMNS`; the same arguments always give the
    same row.
    """
    values = check_params({**params, "tables": tables, "detector": detector})
    return run_system(system, rate, seed, resolve_scenario(scenario, values), values)
