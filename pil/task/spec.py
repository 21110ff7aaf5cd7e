"""A run's typed, frozen specification (:class:`RunSpec`), parsed once at the edge.

Whatever describes a run (a command line, a scenario YAML, a study's config, a sweep grid's
row, a Python call) becomes a :class:`RunSpec` through :func:`parse_run_spec`, which checks
every value by its spec in the one registry (:mod:`pil.task.params`). Below it nothing checks
a parameter again or reads an untyped ``values`` dict: :func:`pil.task.assemble.assemble`
builds the run from the spec's typed fields::

    spec = parse_run_spec(system="c1", rate="0.6", seed=3, params={"discard": "0.3"})
    run = assemble(spec)                      # learner, person, detector, world
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from pil.errors import InvalidChoiceError
from pil.task.detector import CAMERAS, MODELS
from pil.task.params import ASSEMBLY, PARAMS, RATE, SCENARIO, SEED, ParamSpec, parse_all
from pil.task.scenario import Scenario, load_scenario
from pil.task.seeds import RunSeeds, sub_seeds
from pil.task.systems import DEFAULT_SYSTEM, SYSTEM_SPECS, SystemSpec, check_system

SYMBOLIC, PHYSICAL = "symbolic", "physical"
WORLDS: tuple[str, ...] = (SYMBOLIC, PHYSICAL)  # the instant world, or MuJoCo (robin_sim)
# The detector a run of each world may name: the eye cameras only where there is a body to see.
DETECTOR_SPECS: dict[str, ParamSpec] = {
    SYMBOLIC: PARAMS["detector"],
    PHYSICAL: replace(
        PARAMS["detector"], choices=(*MODELS, CAMERAS), doc="detection model or the eye cameras"
    ),
}


@dataclass(frozen=True, slots=True)
class LearnerSettings:
    """Which PIL rule learns, how it explores, adapts, anticipates; the baselines' settings;
    the loop's cap."""

    learner: str
    exploration: str
    adaptation: str
    proactive: bool
    proactive_threshold: float
    proactive_min_count: int
    epsilon: float
    epsilon_decay: float
    bandit_prior: float
    step_size: float
    step_memory: str
    max_actions_per_gesture: int


@dataclass(frozen=True, slots=True)
class PersonSettings:
    """The scripted person's mind: silence, patience, take-backs, reaction, and the handover
    timeout."""

    silent_ok: float
    patience: int
    take_back: float
    take_back_delay: int
    reaction_time: float
    reaction_spread: float
    handover_timeout: float


@dataclass(frozen=True, slots=True)
class DetectorSettings:
    """How the robot reads the person (``model``: the parameter ``detector``)."""

    model: str
    discard: float
    confusion: list[list[float]] | None
    repeat_discarded: bool


_GROUPS = (LearnerSettings, PersonSettings, DetectorSettings)
_RENAMED = {"model": "detector"}  # field -> parameter, where the names differ


def group_params(group: type) -> tuple[str, ...]:
    """The parameter names (:data:`pil.task.params.PARAMS`) of a settings class's fields."""
    return tuple(_RENAMED.get(f.name, f.name) for f in fields(group))


def _settings(group: type, values: Mapping[str, Any]) -> Any:
    return group(**{f.name: values[_RENAMED.get(f.name, f.name)] for f in fields(group)})


def _flat(settings: Any) -> dict[str, Any]:
    return {_RENAMED.get(f.name, f.name): getattr(settings, f.name) for f in fields(settings)}


@dataclass(frozen=True, slots=True)
class RunSpec:
    """Everything a run is made of, typed and checked (build it with :func:`parse_run_spec`).

    ``scenario`` is resolved (the assembly fields given applied); ``world``: one of
    :data:`WORLDS` (a physical run's own options, e.g. video, are ``robin_sim``'s companion
    spec). The system's own parameters (:class:`~pil.task.systems.SystemSpec`) apply to its
    test run (:meth:`effective`), not to its pre-training.
    """

    system: str
    rate: float
    seed: int
    scenario: Scenario
    learner: LearnerSettings
    person: PersonSettings
    detector: DetectorSettings
    world: str = SYMBOLIC
    # derived when the spec is made (a changed copy derives them again), so that assembling
    # reads them as data: the run's sub-seeds (pil.task.seeds, the one place they are
    # derived) and how the system learns and is tested
    seeds: RunSeeds = field(init=False, repr=False, compare=False)
    system_spec: SystemSpec = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "seeds", sub_seeds(self.seed))
        object.__setattr__(self, "system_spec", SYSTEM_SPECS[self.system])

    def for_run(self, system: str, rate: float, seed: int) -> RunSpec:
        """This spec for another system, rate and seed, all already checked (a study's grid)."""
        return replace(self, system=system, rate=rate, seed=seed)

    def effective(self) -> RunSpec:
        """This spec with the system's own parameters applied (typed constants, not parsed)."""
        return self.changed(self.system_spec.params)

    def changed(self, typed: Mapping[str, Any]) -> RunSpec:
        """This spec with run parameters of the settings groups replaced by ``typed`` values
        (typed constants of the code, e.g. a system's or a tuning grid's: not parsed); a name
        of no settings group raises."""
        overrides = dict(typed)
        if not overrides:
            return self
        changed: dict[str, Any] = {}
        for name in ("learner", "person", "detector"):
            group = getattr(self, name)
            mine = {
                f.name: overrides.pop(_RENAMED.get(f.name, f.name))
                for f in fields(group)
                if _RENAMED.get(f.name, f.name) in overrides
            }
            if mine:
                changed[name] = replace(group, **mine)
        if overrides:  # naming no run parameter of a group: a bug in the code that names it
            raise InvalidChoiceError("run parameter", next(iter(overrides)), PARAMS)
        return replace(self, **changed)

    def values(self) -> dict[str, Any]:
        """Every parameter's value, in :data:`PARAMS` order (assembly fields: the scenario's);
        for results rows and summaries."""
        flat = {**_flat(self.learner), **_flat(self.person), **_flat(self.detector)}
        return {n: getattr(self.scenario, n) if n in ASSEMBLY else flat[n] for n in PARAMS}


def parse_run_spec(
    *,
    system: str | None = None,
    rate: Any = None,
    seed: Any = None,
    scenario: Scenario | str | Path | None = None,
    params: Mapping[str, Any] | None = None,
    world: str = SYMBOLIC,
    labels: Mapping[str, str] | None = None,
) -> RunSpec:
    """A :class:`RunSpec` from values given as text or typed, each checked once by its spec.

    ``params`` are any of :data:`pil.task.params.PARAMS` (assembly ones change the scenario);
    an unknown name raises listing the valid ones. ``labels`` name values in messages (e.g.
    ``{"rate": "--rate"}``). ``system``, ``rate`` and ``seed`` not given (None) are the
    defaults (pil, the registry's rate and seed), typed constants not checked (a study's base
    spec, whose runs set them with :meth:`RunSpec.for_run`).
    """
    label = dict(labels or {})
    if world not in WORLDS:
        raise InvalidChoiceError("world", world, WORLDS)
    if system is not None:
        check_system(system)
    specs = {**PARAMS, "detector": DETECTOR_SPECS[world]}
    given = dict(params or {})
    for name in given:
        if name not in specs:
            raise InvalidChoiceError("parameter", name, specs)
    values = {name: specs[name].parse(value, label.get(name)) for name, value in given.items()}
    if isinstance(scenario, str):
        scenario = SCENARIO.parse(scenario, label.get("scenario", "scenario"))
    return build_run_spec(
        system=DEFAULT_SYSTEM if system is None else system,
        rate=RATE.default
        if rate is None
        else RATE.parse(rate, label.get("rate", "detection rate")),
        seed=SEED.default if seed is None else SEED.parse(seed, label.get("seed", "seed")),
        scenario=scenario,
        values=values,
        world=world,
    )


def build_run_spec(
    *,
    system: str,
    rate: float,
    seed: int,
    scenario: Scenario | str | Path | None,
    values: Mapping[str, Any],
    world: str = SYMBOLIC,
) -> RunSpec:
    """A :class:`RunSpec` of values already parsed by their specs (:func:`parse_run_spec`'s
    own, or a sweep grid's row, checked by the grid), nothing checked again: ``values`` are
    any of :data:`~pil.task.params.PARAMS` (the others: their defaults); ``scenario`` a
    :class:`Scenario`, a file or name (read here), or None (the assembly)."""
    values = {**parse_all(PARAMS, {}), **values}  # defaults (not parsed) for the others
    base = (
        scenario
        if isinstance(scenario, Scenario)
        else (load_scenario() if scenario is None else load_scenario(scenario))
    )
    changes = {name: values[name] for name in ASSEMBLY if values[name] is not None}
    return RunSpec(
        system=system,
        rate=rate,
        seed=seed,
        scenario=replace(base, **changes) if changes else base,
        learner=_settings(LearnerSettings, values),
        person=_settings(PersonSettings, values),
        detector=_settings(DetectorSettings, values),
        world=world,
    )
