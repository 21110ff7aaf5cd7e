"""Build the parts of one learner run (learner, scripted person, detector) from a seed.

Shared by the study (:mod:`pil.experiments.systems`) and the physical episode, so that the same
scenario,
rate, seed and parameters give the same decisions in both (with a world whose actions all
succeed)::

    parts = build_parts(load_scenario(), rate=0.8, seed=3)
    for record in steps(parts.learner, parts.person, parts.detector, world, **parts.options):
        ...

:data:`PARAMS` names every parameter with its default; their types and valid ranges are the
specs of :mod:`pil.task.params`, which :func:`check_params` applies.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, MutableMapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from pil.errors import InvalidChoiceError
from pil.exploration import check_rule
from pil.learner import Learner
from pil.step_memory import step_memory_on
from pil.table import AssociationTable
from pil.task.detector import Detector, MeasuredDetector, make_detector
from pil.task.params import ASSEMBLY, SEED, parse_all
from pil.task.params import PARAMS as PARAM_SPECS
from pil.task.person import PersonBody, ScriptedPerson, ScriptStep, plan_script
from pil.task.scenario import Scenario, load_scenario
from pil.task.watching import ReactionTime

T = TypeVar("T")
SCENARIO_KEYS: tuple[str, ...] = tuple(ASSEMBLY)  # None (the default): the scenario file's
PARAMS: dict[str, Any] = {name: spec.default for name, spec in PARAM_SPECS.items()}
# The person's parameters (recorded in an episode's summary).
PERSON_PARAMS: tuple[str, ...] = ("silent_ok", "patience", "reaction_time", "reaction_spread")
PHASES: tuple[str, ...] = ("train", "test")
SEED_NAMES: tuple[str, ...] = tuple(
    f"{phase}_{part}" for part in ("draw", "detector", "learner", "person") for phase in PHASES
)


@dataclass(frozen=True, slots=True)
class RunParts:
    """Everything :func:`pil.task.runner.steps` needs besides the world."""

    learner: Learner
    person: ScriptedPerson
    detector: Detector | MeasuredDetector
    options: Mapping[str, Any]  # keyword options of steps()/run(): manual, repeat_discarded, ...


def check_params(params: Mapping[str, Any]) -> dict[str, Any]:
    """All parameters with defaults filled in, each parsed by its :mod:`pil.task.params` spec.

    Text from a command line or a CSV works (``"0.3"``, ``"false"``); an unknown name raises
    listing the valid ones, a bad value raises naming the parameter and its valid range.
    """
    return parse_all(PARAM_SPECS, params)


def derive_seeds(seed: int) -> dict[str, int]:
    """Independent sub-seeds of one run or repetition (numpy SeedSequence of ``seed``)."""
    seed = SEED.parse(seed, "seed")
    words = np.random.SeedSequence(int(seed)).generate_state(len(SEED_NAMES), np.uint64)
    return {name: int(w) for name, w in zip(SEED_NAMES, words, strict=True)}


def resolve_scenario(scenario: Scenario | str | Path | None, values: Mapping[str, Any]) -> Scenario:
    """The scenario (default: ``scenarios/assembly.yaml``) with the assembly fields given.

    Assembly fields that are None or absent in ``values`` keep the scenario file's value.
    """
    if isinstance(scenario, Scenario):
        base = scenario
    else:
        base = load_scenario() if scenario is None else load_scenario(scenario)
    changes = {k: values[k] for k in SCENARIO_KEYS if values.get(k) is not None}
    return base.with_changes(**changes) if changes else base


def phase_script(
    scenario: Scenario,
    phase: str,
    seeds: Mapping[str, int],
    cache: MutableMapping[Any, Any] | None = None,
) -> tuple[ScriptStep, ...]:
    """The person's script for the training or the test tables (seeded handover order)."""
    if phase not in PHASES:
        raise InvalidChoiceError("phase", phase, PHASES)

    def plan() -> tuple[ScriptStep, ...]:
        tables = scenario.training_tables if phase == "train" else scenario.tables
        types = scenario.draw_types(tables * scenario.legs_per_table, seeds[f"{phase}_draw"])
        return plan_script(types, scenario.legs_per_table, scenario.spots)

    return cached(cache, ("script", phase, seeds[f"{phase}_draw"]), plan)


def cached(cache: MutableMapping[Any, Any] | None, key: Any, make: Callable[[], T]) -> T:
    """``cache[key]``, made by ``make()`` and kept the first time; without a cache, ``make()``."""
    if cache is None:
        return make()
    if key not in cache:
        cache[key] = make()
    return cache[key]


def build_parts(
    scenario: Scenario,
    rate: float,
    seed: int | Mapping[str, int],
    *,
    phase: str = "test",
    table: AssociationTable | None = None,
    manual: bool = False,
    cache: MutableMapping[Any, Any] | None = None,
    body: PersonBody | None = None,
    **params: Any,
) -> RunParts:
    """Learner, person and detector for one run of ``phase`` at detection rate ``rate``.

    ``seed`` is a run seed or the sub-seeds of :func:`derive_seeds`; ``table`` a pre-trained
    association table (used as is, not copied); ``manual`` selects manual repetition (no
    correction); ``params`` are any of :data:`PARAMS` (the assembly ones are taken from
    ``scenario``, not from ``params``); ``body`` makes the person visible in a physical world.
    """
    values = check_params(params)
    seeds = derive_seeds(seed) if isinstance(seed, (int, np.integer)) else seed
    script = phase_script(scenario, phase, seeds, cache)
    person = ScriptedPerson(
        script,
        seeds[f"{phase}_person"],
        silent_ok=values["silent_ok"],
        patience=values["patience"],
        reaction_time=ReactionTime(values["reaction_time"], values["reaction_spread"]),
        body=body,
    )
    detector = make_detector(
        values["detector"],
        rate,
        seeds[f"{phase}_detector"],
        deck_size=max(1, len(script)),
        discard=values["discard"],
        confusion=values["confusion"],
    )
    learner = Learner(
        seeds[f"{phase}_learner"],
        table=table,
        correction=not manual,
        exploration=check_rule(values["exploration"]),
        adaptation=values["adaptation"],
        proactive=values["proactive"],
        proactive_threshold=values["proactive_threshold"],
        proactive_min_count=values["proactive_min_count"],
        step_memory=step_memory_on(values["step_memory"], Learner.STEP_MEMORY_OWN),
    )
    options = {
        "manual": manual,
        "repeat_discarded": bool(values["repeat_discarded"]),
        "max_actions_per_gesture": values["max_actions_per_gesture"],
    }
    return RunParts(learner, person, detector, options)
