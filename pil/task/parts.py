"""Build the parts of one learner run (learner, scripted person, detector) from a seed.

Shared by the study (:mod:`pil.experiments.systems`) and the physical episode, so that the same
scenario,
rate, seed and parameters give the same decisions in both (with a world whose actions all
succeed)::

    parts = build_parts(load_scenario(), rate=0.8, seed=3)
    for record in steps(parts.learner, parts.person, parts.detector, world, **parts.options):
        ...

:data:`PARAMS` names every parameter with its default; an unknown name raises an error that
lists them.
"""

from __future__ import annotations

from collections.abc import Mapping, MutableMapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from pil.anticipation import DEFAULT_MIN_COUNT, DEFAULT_THRESHOLD
from pil.errors import InvalidChoiceError, RobinPilError
from pil.exploration import DEFAULT_RULE, check_rule
from pil.learner import Learner
from pil.table import AssociationTable
from pil.task.detector import DEFAULT_DISCARD, Detector, MeasuredDetector, make_detector
from pil.task.person import PersonBody, ScriptedPerson, ScriptStep, plan_script
from pil.task.runner import MAX_ACTIONS_PER_GESTURE
from pil.task.scenario import ASSEMBLY_DEFAULTS, Scenario, load_scenario
from pil.task.watching import DEFAULT_REACTION_MEAN, DEFAULT_REACTION_SPREAD, ReactionTime

# The assembly's own settings: None (the default) keeps the scenario file's value.
SCENARIO_KEYS: tuple[str, ...] = tuple(ASSEMBLY_DEFAULTS)
_SCENARIO_KINDS: dict[str, Any] = ASSEMBLY_DEFAULTS  # the type each setting converts to
PARAMS: dict[str, Any] = {
    **dict.fromkeys(SCENARIO_KEYS),
    "detector": "exact",  # exact | independent | measured:FILE (pil.task.detector)
    "discard": DEFAULT_DISCARD,  # share of misses discarded as low-confidence
    "confusion": None,  # 4x4 rows: how a miss of each gesture is misread; None = uniform
    "repeat_discarded": True,  # the robot asks for a repeat of a discarded gesture
    "silent_ok": 0.0,  # chance that the person approves by saying nothing
    "patience": 0,  # rejections in a row after which the person repeats the gesture; 0 = off
    "reaction_time": DEFAULT_REACTION_MEAN,  # s, mean delay from recognising to thumb down
    "reaction_spread": DEFAULT_REACTION_SPREAD,  # s, its standard deviation
    "handover_timeout": 180.0,  # s from a handover's first gesture (physical episodes)
    "max_actions_per_gesture": MAX_ACTIONS_PER_GESTURE,
    "exploration": DEFAULT_RULE,  # the learner's rule after a not-OK (pil.exploration.RULES)
    "adaptation": "none",  # "halve": a not-OK halves the refused count (pil.learner)
    "proactive": False,  # act on the likely next state before its gesture (pil.anticipation)
    "proactive_threshold": DEFAULT_THRESHOLD,  # P(next state | state) needed to act unasked
    "proactive_min_count": DEFAULT_MIN_COUNT,  # transitions seen before that share counts
    "epsilon": 0.1,  # the bandit baseline's chance of a random action (pil.agents.bandit)
    "step_size": 0.5,  # the TAMER baseline's regression step (pil.agents.tamer)
}
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
    """All parameters with defaults filled in; an unknown name raises listing the valid ones.

    Values are converted to the type of their default, so text from a command line or a CSV
    works (``"0.3"``, ``"false"``); a value that does not convert raises naming the parameter.
    """
    values = dict(PARAMS)
    for name, value in params.items():
        if name not in PARAMS:
            raise InvalidChoiceError("parameter", name, PARAMS)
        kind = _SCENARIO_KINDS.get(name, PARAMS[name])
        values[name] = None if value is None else _convert(name, value, kind)
    return values


_TRUE, _FALSE = ("true", "yes", "1", "on"), ("false", "no", "0", "off")


def _convert(name: str, value: Any, default: Any) -> Any:
    """``value`` as the type of ``default`` (bool, int, float, str; None: as given)."""
    kind = type(default)
    if default is None:
        return value
    if isinstance(value, kind) and (kind is bool or not isinstance(value, bool)):
        return value
    try:
        if kind is bool:
            text = str(value).strip().lower()
            if text in _TRUE or text in _FALSE:
                return text in _TRUE
            raise ValueError
        if kind is int:
            number = float(value)
            if isinstance(value, bool) or not number.is_integer():
                raise ValueError
            return int(number)
        return kind(value)
    except (TypeError, ValueError):
        raise RobinPilError(
            f"parameter {name!r} must be of type {kind.__name__} (default {default!r}), "
            f"got {value!r}"
        ) from None


def derive_seeds(seed: int) -> dict[str, int]:
    """Independent sub-seeds of one run or repetition (numpy SeedSequence of ``seed``)."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise RobinPilError(f"seed must be a whole number >= 0, got {seed!r}")
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
    key = ("script", phase, seeds[f"{phase}_draw"])
    script = None if cache is None else cache.get(key)
    if script is None:
        tables = scenario.training_tables if phase == "train" else scenario.tables
        types = scenario.draw_types(tables * scenario.legs_per_table, seeds[f"{phase}_draw"])
        script = plan_script(types, scenario.legs_per_table, scenario.spots)
        if cache is not None:
            cache[key] = script
    return script


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
    learner = Learner(seeds[f"{phase}_learner"], table=table, correction=not manual,
                      exploration=check_rule(values["exploration"]),
                      adaptation=values["adaptation"], proactive=values["proactive"],
                      proactive_threshold=values["proactive_threshold"],
                      proactive_min_count=values["proactive_min_count"])  # fmt: skip
    options = {
        "manual": manual,
        "repeat_discarded": bool(values["repeat_discarded"]),
        "max_actions_per_gesture": values["max_actions_per_gesture"],
    }
    return RunParts(learner, person, detector, options)
