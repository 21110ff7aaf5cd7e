"""The parameters' defaults and the learner-only pieces of a phase from given parts (a scenario,
sub-seeds): a phase's script and the scenario with its assembly fields.

A run is built by :func:`pil.task.assemble.assemble` from a :class:`~pil.task.spec.RunSpec`
(``assemble(parse_run_spec(...))``); its pre-training by ``assemble(spec, phase="train")``.
:data:`DEFAULT_VALUES` names every parameter with its default; their types and valid ranges are
the specs of :mod:`pil.task.params`, which :func:`pil.task.spec.parse_run_spec` applies.
"""

from __future__ import annotations

from collections.abc import Mapping, MutableMapping
from pathlib import Path
from typing import Any

from pil.errors import InvalidChoiceError
from pil.task.assemble import Run, cached, script_of
from pil.task.params import ASSEMBLY
from pil.task.params import PARAMS as PARAM_SPECS
from pil.task.scenario import Scenario, load_scenario
from pil.task.script import ScriptStep
from pil.task.seeds import PHASES, SEED_NAMES, SEED_PARTS, PhaseSeeds, derive_seeds

__all__ = [
    "DEFAULT_VALUES",
    "PERSON_PARAMS",
    "PHASES",
    "SCENARIO_KEYS",
    "SEED_NAMES",
    "RunParts",
    "cached",
    "derive_seeds",
    "phase_script",
    "resolve_scenario",
]

RunParts = Run  # the assembled pieces of a run (the name earlier code knows)
SCENARIO_KEYS: tuple[str, ...] = tuple(ASSEMBLY)  # None (the default): the scenario file's
DEFAULT_VALUES: dict[str, Any] = {name: spec.default for name, spec in PARAM_SPECS.items()}
# The person's parameters (recorded in an episode's summary).
PERSON_PARAMS: tuple[str, ...] = (
    "silent_ok",
    "patience",
    "take_back",
    "take_back_delay",
    "reaction_time",
    "reaction_spread",
)


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


def _phase_seeds(phase: str, seeds: Mapping[str, int]) -> PhaseSeeds:
    if phase not in PHASES:
        raise InvalidChoiceError("phase", phase, PHASES)
    return PhaseSeeds(*(seeds[f"{phase}_{part}"] for part in SEED_PARTS))


def phase_script(
    scenario: Scenario,
    phase: str,
    seeds: Mapping[str, int],
    cache: MutableMapping[Any, Any] | None = None,
) -> tuple[ScriptStep, ...]:
    """The person's script for the training or the test tables (seeded handover order)."""
    return script_of(scenario, phase, _phase_seeds(phase, seeds), cache)
