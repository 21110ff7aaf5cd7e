"""A pilot study's protocol file: conditions, their order per participant, blocks, instructions.

A protocol is YAML (see ``scenarios/protocols/reactive_vs_proactive.yaml`` and docs/live.md,
"Protocol file")::

    name: reactive_vs_proactive
    scenario: table_one                # optional: a shipped scenario or a path (from this file)
    conditions:                        # system keys of pil.task.systems, neutral labels
      - {system: pil, label: Robot A}
      - {system: proactive, label: Robot B}
    order: counterbalanced             # fixed | counterbalanced | latin-square
    blocks:                            # each condition's blocks (a condition may list its own)
      - {types: [A, B, C], repeat: 2}
    instructions: "Block {block} of {blocks}: you work with {label}."
    questionnaires: [nasa-tlx, godspeed]   # optional: answered after each block

:func:`load_protocol` checks every field; :meth:`Protocol.blocks_for` gives a participant's
blocks in their order. Pure Python and YAML: nothing here imports MuJoCo.
"""

from __future__ import annotations

import re
import string
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pil.errors import RobinPilError, quote
from pil.task.scenario import (
    SCENARIOS_DIR,
    Scenario,
    find_scenario,
    load_scenario,
    shipped_scenarios,
)
from pil.task.yaml_files import find_shipped, read_yaml_mapping, reject_unknown, shipped_in
from robin_sim.live.questionnaires import Questionnaire, load_questionnaires

PROTOCOLS_DIR = SCENARIOS_DIR / "protocols"
PROTOCOL_KEYS: tuple[str, ...] = (
    "name",
    "description",
    "scenario",
    "conditions",
    "order",
    "blocks",
    "instructions",
    "questionnaires",
    "seeds",
)
CONDITION_KEYS: tuple[str, ...] = ("system", "label", "blocks", "instructions")
BLOCK_KEYS: tuple[str, ...] = ("types", "repeat", "instructions")
ORDERS: tuple[str, ...] = ("fixed", "counterbalanced", "latin-square")
# How each block is seeded: its own seed from the study seed, the participant and the block
# (pil.task.seeds.block_seed), or the study seed for every block (the same sequences).
SEEDINGS: tuple[str, ...] = ("per-block", "shared")
PLACEHOLDERS: tuple[str, ...] = ("label", "block", "blocks", "handovers", "types")
DEFAULT_INSTRUCTIONS = (
    "Block {block} of {blocks}: you work with {label}. Hand over {handovers} legs "
    "({types}) with gestures; thumbs up or down tell the robot how it did."
)
MAX_REPEAT, MAX_TYPES = 100, 100  # per block: clear bounds instead of a runaway study
MAX_INSTRUCTIONS = 4000  # characters of an instruction text, before and after filling it in


class ProtocolError(RobinPilError):
    """A protocol file that is malformed or names something that does not exist."""


@dataclass(frozen=True)
class Block:
    """One block of a participant's session: one condition, its handovers, its instructions."""

    index: int  # 0-based position for this participant
    condition: str  # a system key (pil, proactive, c1..c4, ...)
    handover_types: tuple[str, ...]
    instructions: str  # the text shown before the block, placeholders filled in
    label: str = ""  # the condition's neutral name shown to the participant ("Robot A")


@dataclass(frozen=True)
class BlockSpec:
    """A block as the file gives it (before repeats and ordering)."""

    types: tuple[str, ...]
    repeat: int = 1
    instructions: str | None = None  # None: the condition's or the protocol's


@dataclass(frozen=True)
class ProtocolCondition:
    """One condition: a system, the label participants see, and its blocks."""

    system: str
    label: str
    blocks: tuple[BlockSpec, ...]
    instructions: str


@dataclass(frozen=True)
class Protocol:
    """A checked protocol; :meth:`blocks_for` gives one participant's blocks."""

    name: str
    scenario: str | None  # a shipped scenario's name or a file path (None: the default)
    conditions: tuple[ProtocolCondition, ...]
    order: str = "counterbalanced"
    description: str = ""
    source: str = "<protocol>"
    questionnaires: tuple[Questionnaire, ...] = ()  # answered after each block, in this order
    seeds: str = "per-block"  # one of SEEDINGS

    def condition_order(self, participant: str) -> tuple[str, ...]:
        """The system keys in the order ``participant`` meets them."""
        number = participant_number(participant, self.source)
        rows = order_rows(len(self.conditions), self.order)
        return tuple(self.conditions[i].system for i in rows[(number - 1) % len(rows)])

    def blocks_for(self, participant: str) -> tuple[Block, ...]:
        """``participant``'s blocks: each condition's blocks (repeats expanded) in their order."""
        return self.blocks_in(self.condition_order(participant))

    def blocks_in(self, order: Sequence[str]) -> tuple[Block, ...]:
        """The blocks of the conditions ``order`` names (system keys), in that order (a
        study's assignment chooses it: :mod:`robin_sim.lab.assignment`)."""
        by_system = {c.system: c for c in self.conditions}
        planned = [
            (by_system[system], spec)
            for system in order
            for spec in by_system[system].blocks
            for _ in range(spec.repeat)
        ]
        blocks = []
        for index, (condition, spec) in enumerate(planned):
            template = spec.instructions or condition.instructions
            text = template.format(
                label=condition.label,
                block=index + 1,
                blocks=len(planned),
                handovers=len(spec.types),
                types=", ".join(spec.types),
            )
            blocks.append(Block(index, condition.system, spec.types, text.strip(), condition.label))
        return tuple(blocks)


def participant_number(participant: str, source: str = "<protocol>") -> int:
    """The number in a participant id: its digits read together ("P07" -> 7)."""
    digits = "".join(re.findall(r"\d", participant)) if isinstance(participant, str) else ""
    if not digits:
        raise ProtocolError(
            f"{source}: participant id {quote(participant)} has no digits; the protocol orders "
            "conditions by the participant's number, so give ids like P01, P02, ..."
        )
    return int(digits)


def order_rows(count: int, order: str) -> list[list[int]]:
    """The condition orders participants 1, 2, 3, ... cycle through (indices into conditions).

    ``fixed``: the listed order for everyone. ``counterbalanced``: the listed order for odd
    numbers, reversed for even. ``latin-square``: a balanced Latin square (Williams design):
    every condition comes at every position and follows every other equally often; ``count``
    rows, or ``2 * count`` for an odd count (each row and its reverse).
    """
    listed = list(range(count))
    if order == "fixed" or count == 1:
        return [listed]
    if order == "counterbalanced":
        return [listed, listed[::-1]]
    first, low, high = [0], 1, count - 1
    while len(first) < count:
        first.append(low)
        low += 1
        if len(first) < count:
            first.append(high)
            high -= 1
    rows = [[(c + shift) % count for c in first] for shift in range(count)]
    return rows + [row[::-1] for row in rows] if count % 2 else rows


def shipped_protocols() -> tuple[str, ...]:
    """Names of the protocols that ship with the package (``load_protocol(name)`` loads one)."""
    return shipped_in(PROTOCOLS_DIR)


def find_protocol(path: str | Path) -> Path:
    """``path`` if it names a file; else the shipped protocol of that name; else ``path``."""
    return find_shipped(path, PROTOCOLS_DIR)


def load_protocol(path: str | Path) -> Protocol:
    """Load and check a protocol file (or a shipped protocol's name); ProtocolError if bad."""
    path = find_protocol(path)
    source = str(path)
    raw = read_yaml_mapping(path, "protocol", ProtocolError, shipped_protocols())
    reject_unknown(raw, PROTOCOL_KEYS, source, ProtocolError)
    name = _text(raw.get("name", path.stem), f"{source}: name")
    description = _text(raw.get("description", ""), f"{source}: description", empty=True)
    scenario_name, scenario = _scenario(raw.get("scenario"), path)
    order = raw.get("order", "counterbalanced")
    if order not in ORDERS:
        raise ProtocolError(
            f"{source}: order: unknown order {quote(order)}; valid choices: " + ", ".join(ORDERS)
        )
    text = raw.get("instructions", DEFAULT_INSTRUCTIONS)
    instructions = _template(text, f"{source}: instructions")
    blocks = _blocks(raw.get("blocks"), scenario, f"{source}: blocks", required=True)
    conditions = _conditions(raw.get("conditions"), scenario, blocks, instructions, source)
    questionnaires = load_questionnaires(raw.get("questionnaires"), f"{source}: questionnaires")
    seeds = raw.get("seeds", "per-block")
    if seeds not in SEEDINGS:
        raise ProtocolError(
            f"{source}: seeds: unknown seeding {quote(seeds)}; valid choices: "
            + ", ".join(SEEDINGS)
        )
    return Protocol(
        name, scenario_name, conditions, order, description, source, questionnaires, seeds
    )


def _scenario(value: Any, path: Path) -> tuple[str | None, Scenario]:
    """The scenario as LiveConfig takes it (a shipped name or a path) and the loaded scenario."""
    where = f"{path}: scenario"
    if value is None:
        return None, _load_scenario(None, where)
    name = _text(value, where)
    beside = path.parent / name
    if beside.is_file():
        chosen = str(beside)
    elif find_scenario(name).is_file():
        chosen = name
    else:
        raise ProtocolError(
            f"{where}: no scenario {quote(name)} (neither a file beside the protocol nor a "
            "shipped scenario); valid choices: a YAML path or " + ", ".join(shipped_scenarios())
        )
    return chosen, _load_scenario(chosen, where)


def _load_scenario(value: str | None, where: str) -> Scenario:
    try:
        return load_scenario() if value is None else load_scenario(value)
    except RobinPilError as error:
        raise ProtocolError(f"{where}: {error}") from None


def _conditions(
    raw: Any, scenario: Scenario, blocks: tuple[BlockSpec, ...], instructions: str, source: str
) -> tuple[ProtocolCondition, ...]:
    """The ``conditions`` list: system keys (or mappings with system, label, blocks, ...)."""
    from pil.task.systems import SYSTEM_SPECS

    where = f"{source}: conditions"
    if not isinstance(raw, list) or not raw:
        raise ProtocolError(
            f"{where}: expected a non-empty list of conditions, each a system key or a mapping "
            f"with keys {', '.join(CONDITION_KEYS)}; systems: " + ", ".join(SYSTEM_SPECS)
        )
    conditions: list[ProtocolCondition] = []
    for i, item in enumerate(raw):
        here = f"{where}[{i}]"
        entry = {"system": item} if isinstance(item, str) else item
        if not isinstance(entry, Mapping):
            raise ProtocolError(
                f"{here}: expected a system key or a mapping with keys " + ", ".join(CONDITION_KEYS)
            )
        reject_unknown(entry, CONDITION_KEYS, here, ProtocolError)
        system = entry.get("system")
        if system not in SYSTEM_SPECS:
            raise ProtocolError(
                f"{here}.system: unknown system {quote(system)}; valid choices: "
                + ", ".join(SYSTEM_SPECS)
            )
        label = _text(entry.get("label", f"Robot {chr(ord('A') + i)}"), f"{here}.label")
        own = entry.get("blocks")
        own_blocks = blocks if own is None else _blocks(own, scenario, f"{here}.blocks")
        text = entry.get("instructions")
        own_text = instructions if text is None else _template(text, f"{here}.instructions")
        conditions.append(ProtocolCondition(system, label, own_blocks, own_text))
    for key in ("system", "label"):
        values = [getattr(c, key) for c in conditions]
        repeated = next((v for v in values if values.count(v) > 1), None)
        if repeated is not None:
            raise ProtocolError(
                f"{where}: {key} {repeated!r} is given twice; give each condition its own {key}"
            )
    return tuple(conditions)


def _blocks(
    raw: Any, scenario: Scenario, where: str, *, required: bool = False
) -> tuple[BlockSpec, ...]:
    """A ``blocks`` list of mappings with ``types`` (and ``repeat``, ``instructions``)."""
    if raw is None and not required:
        return ()
    if not isinstance(raw, list) or not raw:
        raise ProtocolError(
            f"{where}: expected a non-empty list of blocks, each a mapping with keys "
            + ", ".join(BLOCK_KEYS)
            + " (e.g. - {types: [A, B, C]})"
        )
    names = [t.name for t in scenario.types]
    specs = []
    for i, item in enumerate(raw):
        here = f"{where}[{i}]"
        if not isinstance(item, Mapping):
            raise ProtocolError(f"{here}: expected a mapping with keys " + ", ".join(BLOCK_KEYS))
        reject_unknown(item, BLOCK_KEYS, here, ProtocolError)
        types = item.get("types")
        if not isinstance(types, list) or not types or len(types) > MAX_TYPES:
            raise ProtocolError(
                f"{here}.types: expected a list of 1 to {MAX_TYPES} handover types; valid "
                f"choices (scenario {scenario.source}): " + ", ".join(names)
            )
        for name in types:
            if name not in names:
                raise ProtocolError(
                    f"{here}.types: unknown handover type {quote(name)}; valid choices "
                    f"(scenario {scenario.source}): " + ", ".join(names)
                )
        repeat = item.get("repeat", 1)
        if isinstance(repeat, bool) or not isinstance(repeat, int) or not 1 <= repeat <= MAX_REPEAT:
            raise ProtocolError(
                f"{here}.repeat: expected a whole number from 1 to {MAX_REPEAT}, "
                f"got {quote(repeat)}"
            )
        text = item.get("instructions")
        own = None if text is None else _template(text, f"{here}.instructions")
        specs.append(BlockSpec(tuple(types), repeat, own))
    return tuple(specs)


def _template(value: Any, where: str) -> str:
    """Instructions text; its ``{placeholders}`` must be among :data:`PLACEHOLDERS`."""
    text = _text(value, where)
    valid = ", ".join("{" + p + "}" for p in PLACEHOLDERS)
    if len(text) > MAX_INSTRUCTIONS:
        raise ProtocolError(
            f"{where}: {len(text)} characters is too long; at most {MAX_INSTRUCTIONS}"
        )
    try:
        fields = [
            (f, spec, conv)
            for _lit, f, spec, conv in string.Formatter().parse(text)
            if f is not None
        ]
    except ValueError as error:
        raise ProtocolError(
            f"{where}: {error}; write {{{{ and }}}} for literal braces, placeholders: {valid}"
        ) from None
    for field, spec, conv in fields:
        if field not in PLACEHOLDERS:
            raise ProtocolError(f"{where}: unknown placeholder {{{field}}}; valid choices: {valid}")
        if spec or conv:  # {block:>100000000} would fill a 100 MB text
            shown = field + ("!" + conv if conv else "") + (":" + spec if spec else "")
            raise ProtocolError(
                f"{where}: placeholder {{{shown:.40}}} has a format; write it "
                f"bare, as {{{field}}} (placeholders: {valid})"
            )
    return text


def _text(value: Any, where: str, *, empty: bool = False) -> str:
    if not isinstance(value, str) or not (empty or value.strip()):
        raise ProtocolError(f"{where}: expected a non-empty text, got {quote(value)}")
    return value
