"""The people of the appearance study, read from a YAML file (``scenarios/people_appearance.yaml``).

Each person is a name and their looks: vision parameters of
:data:`robin_sim.vision.condition_params.CONDITION_PARAMS` (``skin``, ``pose_jitter``,
``lighting``, ``camera_noise``; ``adapt`` is the study's to set), each checked by its spec.
``scenario`` names the assembly (as in the other study files) and ``tables`` how many tables
each person assembles in one run.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pil.experiments.study_files import read_study_file
from pil.task.params import ASSEMBLY
from pil.task.scenario import SCENARIOS_DIR, Scenario, ScenarioError
from robin_sim.vision.condition_params import CONDITION_PARAMS, VisionSettings, parse_conditions

DEFAULT_APPEARANCE = SCENARIOS_DIR / "people_appearance.yaml"
_APPEARANCE_KEYS = ("name", "description", "scenario", "tables", "people")
LOOKS = tuple(name for name in CONDITION_PARAMS if name != "adapt")
MAX_PEOPLE = 12


@dataclass(frozen=True, slots=True)
class Looks:
    """One person as Robin's eye cameras see them."""

    name: str
    settings: VisionSettings  # adapt False: the study sets it per run

    def values(self) -> dict[str, Any]:
        """The looks as ``--param`` values (the study's results columns)."""
        return {name: getattr(self.settings, name) for name in LOOKS}


@dataclass(frozen=True, slots=True)
class AppearancePeople:
    """The assembly, the tables per run and the people."""

    scenario: Scenario
    tables: int
    people: tuple[Looks, ...]
    source: str
    scenario_file: str | None  # what an episode's --scenario is given (None: the assembly)

    def only(self, names: list[str]) -> AppearancePeople:
        """The study restricted to ``names`` (each must be one of the file's people)."""
        known = {p.name: p for p in self.people}
        for name in names:
            if name not in known:
                raise ScenarioError(
                    f"person {name!r} is not in {self.source}; valid choices: {', '.join(known)}"
                )
        chosen = tuple(known[n] for n in names)
        return AppearancePeople(self.scenario, self.tables, chosen, self.source, self.scenario_file)


def load_appearance(path: str | Path = DEFAULT_APPEARANCE) -> AppearancePeople:
    """Read an appearance people file; anything malformed raises :class:`ScenarioError`
    naming the file, the key and the valid choices."""
    path, raw, scenario = read_study_file(path, _APPEARANCE_KEYS, "appearance people file")
    people = raw.get("people")
    if not isinstance(people, Mapping) or not 1 <= len(people) <= MAX_PEOPLE:
        raise ScenarioError(
            f"{path}: people: expected 1 to {MAX_PEOPLE} people, each name: {{looks}}"
        )
    out = []
    for name, looks in people.items():
        where = f"{path}: people.{name}"
        if not isinstance(name, str) or not name.isidentifier():
            raise ScenarioError(f"{where}: a person's name is letters, digits and _")
        if not isinstance(looks, Mapping):
            raise ScenarioError(f"{where}: expected a mapping of {', '.join(LOOKS)}")
        for key in looks:
            if key not in LOOKS:
                valid = ", ".join(LOOKS)
                raise ScenarioError(f"{where}: unknown key {key!r}; valid choices: {valid}")
        try:
            settings = parse_conditions(dict(looks))
        except ValueError as problem:
            raise ScenarioError(f"{where}: {problem}") from None
        out.append(Looks(name, settings))
    try:
        tables = ASSEMBLY["tables"].required().parse(raw.get("tables", 3), f"{path}: tables")
    except ValueError as problem:
        raise ScenarioError(str(problem)) from None
    base = raw.get("scenario")
    near = None if base is None else path.parent / str(base)
    ref = None if base is None else str(near) if near and near.exists() else str(base)
    return AppearancePeople(scenario, tables, tuple(out), str(path), ref)
