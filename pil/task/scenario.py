"""Scenarios: the handover types and the assembly task, loaded from YAML and validated.

A *handover type* is the script of instruction gestures the person performs to get one table
leg, each with the action they mean by it. An *assembly* says how many tables are built, how
many legs each has, how many tables the pre-trained conditions train on, and in which order
the handover types are drawn. See ``scenarios/*.yaml`` and the README.

Every rule of the task is checked on load; a broken one raises
:class:`ScenarioError` naming the file, the key and the valid choices.
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, TypeVar

from pil.errors import RobinPilError
from pil.task.layout import LayoutError, LayoutSection, parse_layout
from pil.task.params import ASSEMBLY, ASSEMBLY_DEFAULTS, ParamError
from pil.task.yaml_files import (
    find_shipped,
    read_yaml_mapping,
    reject_unknown,
    shipped_in,
    text_field,
)
from pil.types import START_ACTION, START_HAND, Action, Gesture, Hand, State
from pil.validity import is_valid, why_invalid

# The shipped scenarios are package data (a link to the repository's scenarios/ in a checkout).
SCENARIOS_DIR = Path(str(resources.files("pil.task") / "scenarios"))
DEFAULT_SCENARIO = SCENARIOS_DIR / "assembly.yaml"
DEFAULT_TYPES = SCENARIOS_DIR / "handover_types.yaml"
MIN_STEPS, MAX_STEPS = 4, 7
ASSEMBLY_KEYS: tuple[str, ...] = (
    "name",
    "description",
    "types",
    "sequence",
    "tables",
    "legs_per_table",
    "training_tables",
    "draw",
    "spots",
    "layout",
)
TYPE_KEYS: tuple[str, ...] = ("description", "steps")


class ScenarioError(RobinPilError):
    """A scenario file that is malformed or breaks a rule of the task."""


@dataclass(frozen=True, slots=True)
class Step:
    """One instruction gesture of a handover and the action the person means by it."""

    gesture: Gesture
    action: Action
    state: State  # the state the robot is in when this step is performed correctly


@dataclass(frozen=True, slots=True)
class HandoverType:
    """A named script of 4-7 steps that hands one leg over."""

    name: str
    steps: tuple[Step, ...]
    description: str = ""

    def __len__(self) -> int:
        return len(self.steps)


@dataclass(frozen=True, slots=True)
class Scenario:
    """The assembly task: handover types plus how many tables, legs and in which order."""

    types: tuple[HandoverType, ...]
    tables: int = ASSEMBLY_DEFAULTS["tables"]
    legs_per_table: int = ASSEMBLY_DEFAULTS["legs_per_table"]
    training_tables: int = ASSEMBLY_DEFAULTS["training_tables"]
    draw: str = ASSEMBLY_DEFAULTS["draw"]
    sequence: tuple[str, ...] = ()  # handover types to draw from (default: all, file order)
    spots: int = ASSEMBLY_DEFAULTS["spots"]
    layout: LayoutSection = field(default_factory=LayoutSection)  # parsed; the scene checks it
    name: str = "assembly"
    source: str = "<scenario>"

    def type_named(self, name: str) -> HandoverType:
        """The handover type called ``name``."""
        for handover_type in self.types:
            if handover_type.name == name:
                return handover_type
        raise ScenarioError(
            f"{self.source}: unknown handover type {name!r}; valid choices: "
            + ", ".join(t.name for t in self.types)
        )

    def pool(self) -> tuple[HandoverType, ...]:
        """The handover types the draw uses (``sequence`` if given, else all types)."""
        if not self.sequence:
            return self.types
        return tuple(self.type_named(n) for n in self.sequence)

    def draw_types(self, count: int, seed: int) -> tuple[HandoverType, ...]:
        """``count`` handover types in the order the person performs them (seeded)."""
        pool = self.pool()
        rng = random.Random(seed)
        if self.draw == "cycle":
            return tuple(pool[i % len(pool)] for i in range(count))
        if self.draw == "random":
            return tuple(rng.choice(pool) for _ in range(count))
        rounds, rest = divmod(count, len(pool))
        drawn = list(pool) * rounds + rng.sample(pool, rest)
        rng.shuffle(drawn)
        return tuple(drawn)

    def scripted_gestures(self, types: Sequence[HandoverType]) -> int:
        """The number of instruction gestures ``types`` need when every one is read right."""
        return sum(len(t) for t in types)

    def correct_actions(self) -> dict[State, Action]:
        """T_c: the one correct action of every state the types use."""
        return {step.state: step.action for t in self.types for step in t.steps}

    def with_changes(self, **changes: Any) -> Scenario:
        """A copy with some assembly fields replaced (validated like a file)."""
        values = {key: getattr(self, key) for key in ASSEMBLY_DEFAULTS}
        for key, value in changes.items():
            if key not in values:
                raise ScenarioError(
                    f"{self.source}: unknown key {key!r}; valid choices: " + ", ".join(values)
                )
            values[key] = value
        return Scenario(
            types=self.types,
            sequence=self.sequence,
            layout=self.layout,
            name=self.name,
            source=self.source,
            **_check_assembly(values, self.source),
        )


def parse_step(text: object, where: str) -> tuple[Gesture, Action]:
    """``"give me -> human"`` as (gesture, action); a bad text raises naming the valid names."""
    if not isinstance(text, str) or text.count("->") != 1:
        raise ScenarioError(f"{where}: a step is written 'gesture -> action', got {text!r}")
    gesture_text, action_text = (part.strip() for part in text.split("->"))
    return _named(Gesture, gesture_text, where), _named(Action, action_text, where)


_Named = TypeVar("_Named", Gesture, Action)


def _named(kind: type[_Named], text: str, where: str) -> _Named:
    """The member of ``kind`` named ``text``; else a ScenarioError listing the valid names."""
    try:
        return kind(text)
    except ValueError:
        raise ScenarioError(
            f"{where}: unknown {kind.__name__.lower()} {text!r}; valid choices: "
            + ", ".join(member.value for member in kind)
        ) from None


def states_along(pairs: Sequence[tuple[Gesture, Action]]) -> tuple[State, ...]:
    """The states a handover passes through when every step is read and done right.

    Start: previous action open, hand free. After each step the previous action becomes the
    step's action; close fills a free hand and open empties an occupied one.
    """
    previous, hand = START_ACTION, START_HAND
    states = []
    for gesture, action in pairs:
        states.append(State(gesture, previous, hand))
        previous = action
        if action is Action.CLOSE and hand is Hand.FREE:
            hand = Hand.OCCUPIED
        elif action is Action.OPEN and hand is Hand.OCCUPIED:
            hand = Hand.FREE
    return tuple(states)


def build_type(name: str, raw: object, source: str) -> HandoverType:
    """Validate one handover type's mapping and compute its states."""
    where = f"{source}: types.{name}"
    if not isinstance(raw, Mapping):
        raise ScenarioError(f"{where}: expected a mapping with keys {', '.join(TYPE_KEYS)}")
    reject_unknown(raw, TYPE_KEYS, where, ScenarioError)
    steps_raw = raw.get("steps")
    if not isinstance(steps_raw, list):
        raise ScenarioError(f"{where}.steps: expected a list of 'gesture -> action' steps")
    if not MIN_STEPS <= len(steps_raw) <= MAX_STEPS:
        raise ScenarioError(
            f"{where}.steps: a handover type has {MIN_STEPS} to {MAX_STEPS} gestures, "
            f"got {len(steps_raw)}"
        )
    pairs = [parse_step(text, f"{where}.steps[{i}]") for i, text in enumerate(steps_raw)]
    states = states_along(pairs)
    for i, state in enumerate(states):
        if not is_valid(state):
            raise ScenarioError(
                f"{where}.steps[{i}]: {steps_raw[i]!r} happens in the invalid state {state} "
                f"({why_invalid(state)})"
            )
    steps = tuple(Step(g, a, s) for (g, a), s in zip(pairs, states, strict=True))
    return HandoverType(str(name), steps, text_field(raw, "description", "", where, ScenarioError))


def build_types(raw: object, source: str) -> tuple[HandoverType, ...]:
    """Validate the ``types`` mapping and the rule "one correct action per state"."""
    if not isinstance(raw, Mapping) or not raw:
        raise ScenarioError(f"{source}: types: expected a non-empty mapping of handover types")
    types = tuple(build_type(str(name), body, source) for name, body in raw.items())
    seen: dict[State, tuple[Action, str]] = {}
    for handover_type in types:
        for step in handover_type.steps:
            earlier = seen.setdefault(step.state, (step.action, handover_type.name))
            if earlier[0] is not step.action:
                raise ScenarioError(
                    f"{source}: types: state {step.state} has two correct actions: "
                    f"{earlier[0]} in type {earlier[1]} and {step.action} in type "
                    f"{handover_type.name}; each state must have exactly one"
                )
    return types


def load_scenario(path: str | Path = DEFAULT_SCENARIO) -> Scenario:
    """Load and validate a scenario file (an assembly, or a file holding only ``types``).

    ``path`` is a file, or the name of a shipped scenario (``"table_one"``: see
    :func:`shipped_scenarios`), so an installed package runs without the repository.
    """
    path = find_scenario(path)
    raw = read_yaml_mapping(path, "scenario", ScenarioError, shipped_scenarios())
    reject_unknown(raw, ASSEMBLY_KEYS, str(path), ScenarioError)
    types_raw = raw.get("types", str(DEFAULT_TYPES))
    types_source = str(path)
    if isinstance(types_raw, str):  # a file name, relative to this file
        types_path = (path.parent / types_raw).resolve()
        types_file = read_yaml_mapping(types_path, "scenario", ScenarioError, shipped_scenarios())
        reject_unknown(types_file, ("types",), str(types_path), ScenarioError)
        types_raw, types_source = types_file.get("types"), str(types_path)
    types = build_types(types_raw, types_source)
    sequence_raw = raw.get("sequence", [])
    if not isinstance(sequence_raw, list) or not all(isinstance(n, str) for n in sequence_raw):
        raise ScenarioError(f"{path}: sequence: expected a list of handover type names")
    names = [t.name for t in types]
    for name in sequence_raw:
        if name not in names:
            raise ScenarioError(
                f"{path}: sequence: unknown handover type {name!r}; valid choices: "
                + ", ".join(names)
            )
    try:
        layout = parse_layout(raw.get("layout"))
    except LayoutError as error:
        raise ScenarioError(f"{path}: {error}") from None
    text_field(raw, "description", "", str(path), ScenarioError)
    return Scenario(
        types=types,
        sequence=tuple(sequence_raw),
        layout=layout,
        name=text_field(raw, "name", path.stem, str(path), ScenarioError),
        source=str(path),
        **_check_assembly(raw, str(path)),
    )


def shipped_scenarios() -> tuple[str, ...]:
    """Names of the scenarios that ship with the package (``load_scenario(name)`` loads one)."""
    return shipped_in(SCENARIOS_DIR)


def find_scenario(path: str | Path) -> Path:
    """``path`` if it names a file; else the shipped scenario of that name; else ``path``."""
    return find_shipped(path, SCENARIOS_DIR)


def _check_assembly(raw: Mapping[str, Any], source: str) -> dict[str, Any]:
    """The validated counts and draw of an assembly (defaults for missing keys).

    Each key is checked by its spec in :data:`pil.task.params.ASSEMBLY`, the same that checks
    the command-line and sweep values.
    """
    values: dict[str, Any] = {}
    for key, spec in ASSEMBLY.items():
        value = raw.get(key)
        if value is None:
            value = ASSEMBLY_DEFAULTS[key]
        try:
            values[key] = spec.required().parse(value, f"{source}: {key}")
        except ParamError as error:
            raise ScenarioError(str(error)) from None
    return values
