"""The learner-only pieces of one phase from given parts (a scenario, a rate, sub-seeds).

The run of a system is built by :func:`pil.task.assemble.assemble` from a
:class:`~pil.task.spec.RunSpec`; this module keeps the phase-level entry for the experiments
that assemble a phase from their own sub-seeds (people, transfer, the dm_env environment)::

    parts = build_parts(load_scenario(), rate=0.8, seed=3)
    for record in parts.steps():
        ...

:data:`DEFAULT_VALUES` names every parameter with its default; their types and valid ranges are the
specs of :mod:`pil.task.params`, which :func:`check_params` applies.
"""

from __future__ import annotations

from collections.abc import Mapping, MutableMapping
from pathlib import Path
from typing import Any

import numpy as np

from pil.errors import InvalidChoiceError
from pil.table import AssociationTable
from pil.task.assemble import Run, assemble_phase, cached, script_of
from pil.task.params import ASSEMBLY, parse_all
from pil.task.params import PARAMS as PARAM_SPECS
from pil.task.person import PersonBody, ScriptStep
from pil.task.scenario import Scenario, load_scenario
from pil.task.seeds import PHASES, SEED_NAMES, SEED_PARTS, PhaseSeeds, derive_seeds
from pil.task.spec import spec_of

__all__ = [
    "DEFAULT_VALUES",
    "PERSON_PARAMS",
    "PHASES",
    "SCENARIO_KEYS",
    "SEED_NAMES",
    "RunParts",
    "build_parts",
    "cached",
    "check_params",
    "derive_seeds",
    "phase_script",
    "resolve_scenario",
]

RunParts = Run  # the assembled pieces of a run (the name earlier code knows)
SCENARIO_KEYS: tuple[str, ...] = tuple(ASSEMBLY)  # None (the default): the scenario file's
DEFAULT_VALUES: dict[str, Any] = {name: spec.default for name, spec in PARAM_SPECS.items()}
# The person's parameters (recorded in an episode's summary).
PERSON_PARAMS: tuple[str, ...] = ("silent_ok", "patience", "reaction_time", "reaction_spread")


def check_params(params: Mapping[str, Any]) -> dict[str, Any]:
    """All parameters with defaults filled in, each parsed by its :mod:`pil.task.params` spec.

    Text from a command line or a CSV works (``"0.3"``, ``"false"``); an unknown name raises
    listing the valid ones, a bad value raises naming the parameter and its valid range.
    """
    return parse_all(PARAM_SPECS, params)


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
) -> Run:
    """Learner, person and detector for one run of ``phase`` at detection rate ``rate``.

    ``seed`` is a run seed or the sub-seeds of :func:`derive_seeds`; ``table`` a pre-trained
    association table (used as is, not copied); ``manual`` selects manual repetition (no
    correction); ``params`` are any of :data:`DEFAULT_VALUES` (the assembly ones are taken from
    ``scenario``, not from ``params``); ``body`` makes the person visible in a physical world.
    """
    values = check_params(params)
    run_seed = int(seed) if isinstance(seed, (int, np.integer)) else None
    seeds: Mapping[str, int] = derive_seeds(run_seed) if run_seed is not None else seed  # type: ignore[assignment]
    spec = spec_of("pil", rate, run_seed or 0, scenario, values)
    return assemble_phase(
        spec,
        phase,
        seeds=_phase_seeds(phase, seeds),
        table=table,
        manual=manual,
        body=body,
        cache=cache,
    )
