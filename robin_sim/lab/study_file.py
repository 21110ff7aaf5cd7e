"""A study folder's ``study.yaml``: the protocol, the design, the screens, the limits.

::

    name: pilot
    protocol: protocol.yaml      # a protocol file beside this one, or a shipped protocol's name
    design: between              # within | between | mixed
    groups:                      # between and mixed: each participant is assigned one group
      - {name: learner, conditions: [pil]}
      - {name: trained, conditions: [c2]}
    participants: 12             # planned (robin-pil study-status shows what is left)
    id_prefix: P                 # participant ids P01, P02, ...
    seed: 0                      # the study seed: each block's seed derives from it
    consent: {text: ...}         # robin_sim.live.screens
    demographics: {items: [...]}
    practice: {types: [A], block_seconds: 60}   # a practice block before the first
    limits: {block_seconds: 600, block_actions: 80, inactivity_seconds: 120}
    debrief: {text: ...}

``within``: every participant does every condition of the protocol, in an order of the
protocol's ``order`` (fixed, counterbalanced, latin-square). ``between``: each group has one
condition. ``mixed``: each group its conditions, at least one group several (in an order of
the protocol's ``order`` over them). :func:`load_study` checks everything once, before anything
starts: one :class:`StudyError` (exit 2) naming the file, the field and the valid choices.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.task.params import SEED
from pil.task.scenario import load_scenario
from pil.task.yaml_files import read_yaml_mapping, reject_unknown
from robin_sim.live.limits import BlockLimits
from robin_sim.live.protocol import Protocol, find_protocol, load_protocol, shipped_protocols
from robin_sim.live.screens import Screens, load_screens

STUDY_NAME = "study.yaml"
DESIGNS: tuple[str, ...] = ("within", "between", "mixed")
STUDY_KEYS: tuple[str, ...] = (
    "name",
    "description",
    "protocol",
    "design",
    "groups",
    "participants",
    "id_prefix",
    "seed",
    "consent",
    "demographics",
    "practice",
    "limits",
    "debrief",
)
GROUP_KEYS = ("name", "conditions")
PRACTICE_KEYS = ("system", "types", "instructions", "block_seconds", "block_actions")
LIMIT_KEYS = ("block_seconds", "block_actions", "inactivity_seconds")
GROUP_NAME = re.compile(r"[a-z][a-z0-9_-]{0,31}")
ID_PREFIX = re.compile(r"[A-Za-z][A-Za-z_-]{0,9}")
MAX_PARTICIPANTS = 10_000
MAX_PRACTICE_TYPES = 10
PRACTICE_INSTRUCTIONS = (
    "A short practice: try the gestures and the thumbs with the robot. What happens here "
    "does not count."
)


class StudyError(RobinPilError):
    """A study folder or study file that is malformed or names something that does not exist."""


@dataclass(frozen=True)
class Group:
    """A between-subjects group: its name and the conditions (system keys) its members do."""

    name: str
    conditions: tuple[str, ...]


@dataclass(frozen=True)
class Practice:
    """The practice block before the first: its system (None: the participant's first
    condition), handover types, instructions and caps."""

    types: tuple[str, ...]
    system: str | None = None
    instructions: str = PRACTICE_INSTRUCTIONS
    limits: BlockLimits = field(default_factory=BlockLimits)


@dataclass(frozen=True)
class Study:
    """A checked study file (see the module doc)."""

    folder: Path
    name: str
    protocol: Protocol
    protocol_ref: str  # as the study file names it (a file relative to the folder, or a name)
    design: str
    groups: tuple[Group, ...]
    planned: int | None
    id_prefix: str
    seed: int
    screens: Screens
    practice: Practice | None
    limits: BlockLimits
    description: str = ""
    source: Path = field(default=Path(STUDY_NAME))

    def participant_id(self, number: int) -> str:
        """The id of the ``number``-th participant (1-based): P01, P02, ..."""
        return f"{self.id_prefix}{number:02d}"

    def canonical_id(self, given: str) -> str:
        """The one id of a participant however its number is written: ``p01``, ``P1`` and
        ``P001`` are ``P01`` (the prefix in any case, the number in ASCII digits); an id of
        another form is kept as given."""
        prefix, rest = given[: len(self.id_prefix)], given[len(self.id_prefix) :]
        digits = rest.isascii() and rest.isdigit()
        if prefix.casefold() == self.id_prefix.casefold() and digits and int(rest) > 0:
            return self.participant_id(int(rest))
        return given


def load_study(folder: str | Path) -> Study:
    """Read and check ``folder``'s study file; :class:`StudyError` if anything is wrong."""
    folder = Path(folder)
    path = folder / STUDY_NAME
    if not path.is_file():
        raise StudyError(
            f"{folder}: not a study folder (no {STUDY_NAME}); make one with "
            f"robin-pil study-init {folder}"
        )
    raw = read_yaml_mapping(path, "study", StudyError, ())
    where = str(path)
    reject_unknown(raw, STUDY_KEYS, where, StudyError)
    name = _text(raw.get("name", folder.name), f"{where}: name", 80)
    protocol_ref, protocol = _protocol(raw.get("protocol"), folder, where)
    design = raw.get("design", "within")
    if design not in DESIGNS:
        raise StudyError(
            f"{where}: design: unknown design {quote(design)}; valid choices: " + ", ".join(DESIGNS)
        )
    groups = _groups(raw.get("groups"), design, protocol, where)
    planned = raw.get("participants")
    if planned is not None:
        planned = _whole(planned, f"{where}: participants", 1, MAX_PARTICIPANTS)
    prefix = raw.get("id_prefix", "P")
    if not isinstance(prefix, str) or not ID_PREFIX.fullmatch(prefix):
        raise StudyError(
            f"{where}: id_prefix: expected 1-10 letters, '_' or '-' (ids are the prefix and a "
            f"number: P01), got {quote(prefix)}"
        )
    try:
        seed = SEED.parse(raw.get("seed", 0), "seed")
        screens = load_screens(raw, where)
        limits = _limits(raw.get("limits"), f"{where}: limits", LIMIT_KEYS)
    except RobinPilError as error:
        text = str(error)
        raise StudyError(text if text.startswith(where) else f"{where}: {text}") from None
    practice = _practice(raw.get("practice"), protocol, f"{where}: practice")
    description = _text(raw.get("description", ""), f"{where}: description", 2000, empty=True)
    return Study(
        folder,
        name,
        protocol,
        protocol_ref,
        design,
        groups,
        planned,
        prefix,
        seed,
        screens,
        practice,
        limits,
        description,
        path,
    )


def _protocol(value: Any, folder: Path, where: str) -> tuple[str, Protocol]:
    if not isinstance(value, str) or not value.strip():
        raise StudyError(
            f"{where}: protocol: expected a protocol file (beside {STUDY_NAME}) or a shipped "
            "protocol's name: " + ", ".join(shipped_protocols())
        )
    beside = folder / value
    chosen = beside if beside.is_file() else find_protocol(value)
    if not Path(chosen).is_file():
        raise StudyError(
            f"{where}: protocol: no file {quote(str(beside))} and no shipped protocol "
            f"{quote(value)}; valid choices: a file beside {STUDY_NAME} or "
            + ", ".join(shipped_protocols())
        )
    return value, load_protocol(chosen)  # a ProtocolError names the protocol file


def _groups(raw: Any, design: str, protocol: Protocol, where: str) -> tuple[Group, ...]:
    systems = [c.system for c in protocol.conditions]
    if design == "within":
        if raw is not None:
            raise StudyError(
                f"{where}: groups: a within design has no groups (every participant does "
                f"every condition); use design: between or mixed for groups"
            )
        return (Group("all", tuple(systems)),)
    if not isinstance(raw, list) or len(raw) < 2:
        raise StudyError(
            f"{where}: groups: a {design} design needs a list of at least two groups, each "
            f"a mapping with keys {', '.join(GROUP_KEYS)} (conditions of the protocol: "
            + ", ".join(systems)
            + ")"
        )
    groups = []
    for i, item in enumerate(raw):
        here = f"{where}: groups[{i}]"
        if not isinstance(item, Mapping):
            raise StudyError(f"{here}: expected a mapping with keys " + ", ".join(GROUP_KEYS))
        reject_unknown(item, GROUP_KEYS, here, StudyError)
        name = item.get("name")
        if not isinstance(name, str) or not GROUP_NAME.fullmatch(name):
            raise StudyError(
                f"{here}.name: expected a name of lower-case letters, digits, _ or -, got "
                f"{quote(name)}"
            )
        conditions = item.get("conditions")
        if not isinstance(conditions, list) or not conditions:
            raise StudyError(f"{here}.conditions: expected a non-empty list of system keys")
        for system in conditions:
            if system not in systems:
                raise StudyError(
                    f"{here}.conditions: {quote(system)} is not a condition of the protocol; "
                    "valid choices: " + ", ".join(systems)
                )
        if len(set(conditions)) != len(conditions):
            raise StudyError(f"{here}.conditions: a condition is listed twice")
        if design == "between" and len(conditions) != 1:
            raise StudyError(
                f"{here}.conditions: in a between design each group does one condition; "
                "use design: mixed for groups with several"
            )
        groups.append(Group(name, tuple(conditions)))
    names = [g.name for g in groups]
    if len(set(names)) != len(names):
        raise StudyError(f"{where}: groups: a group name is given twice")
    if design == "mixed" and all(len(g.conditions) == 1 for g in groups):
        raise StudyError(
            f"{where}: groups: a mixed design needs a group with several conditions (a "
            "within factor); with one condition per group use design: between"
        )
    return tuple(groups)


def _practice(raw: Any, protocol: Protocol, where: str) -> Practice | None:
    if raw is None:
        return None
    if not isinstance(raw, Mapping):
        raise StudyError(f"{where}: expected a mapping with keys " + ", ".join(PRACTICE_KEYS))
    reject_unknown(raw, PRACTICE_KEYS, where, StudyError)
    from pil.task.systems import SYSTEM_SPECS

    system = raw.get("system")
    if system is not None and system not in SYSTEM_SPECS:
        raise StudyError(
            f"{where}.system: unknown system {quote(system)}; valid choices: "
            + ", ".join(SYSTEM_SPECS)
        )
    types = raw.get("types")
    scenario = load_scenario(protocol.scenario) if protocol.scenario else load_scenario()
    valid = [t.name for t in scenario.types]
    if (
        not isinstance(types, list)
        or not types
        or any(t not in valid for t in types)
        or len(types) > MAX_PRACTICE_TYPES
    ):
        raise StudyError(
            f"{where}.types: expected a list of 1 to {MAX_PRACTICE_TYPES} handover types of "
            f"the protocol's scenario ({scenario.source}), got {quote(types)}; valid choices: "
            + ", ".join(valid)
        )
    instructions = _text(raw.get("instructions", PRACTICE_INSTRUCTIONS), f"{where}.instructions")
    try:
        limits = _limits(
            {k: raw[k] for k in ("block_seconds", "block_actions") if k in raw}, where, LIMIT_KEYS
        )
    except RobinPilError as error:
        raise StudyError(str(error)) from None
    return Practice(tuple(types), system, instructions, limits)


def _limits(raw: Any, where: str, keys: tuple[str, ...]) -> BlockLimits:
    if raw is None:
        return BlockLimits()
    if not isinstance(raw, Mapping):
        raise StudyError(f"{where}: expected a mapping with keys " + ", ".join(keys))
    reject_unknown(raw, keys, where, StudyError)
    limits = BlockLimits(
        raw.get("block_seconds"), raw.get("block_actions"), raw.get("inactivity_seconds")
    )
    return limits.checked(where)


def _whole(value: Any, where: str, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise StudyError(
            f"{where}: expected a whole number from {low} to {high}, got {quote(value)}"
        )
    return value


def _text(value: Any, where: str, longest: int = 4000, *, empty: bool = False) -> str:
    if not isinstance(value, str) or len(value) > longest or not (empty or value.strip()):
        raise StudyError(
            f"{where}: expected a text of 1 to {longest} characters, got {quote(value)}"
        )
    return value.strip()
