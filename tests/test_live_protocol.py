"""The protocol file (robin_sim/live/protocol.py): parsing, counterbalancing, every refusal."""

from __future__ import annotations

import itertools
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest

from pil.errors import RobinPilError
from pil.task.scenario import load_scenario
from pil.task.systems import SYSTEM_SPECS
from robin_sim.live.protocol import (
    ORDERS,
    PROTOCOLS_DIR,
    Block,
    ProtocolError,
    find_protocol,
    load_protocol,
    order_rows,
    participant_number,
    shipped_protocols,
)

GOOD = """\
name: pilot
scenario: table_one
conditions:
  - {system: pil, label: Robot A}
  - {system: proactive, label: Robot B}
order: ORDER
blocks:
  - {types: [A, B, C], repeat: 2}
instructions: "Block {block} of {blocks}: {label}, {handovers} legs ({types})."
"""


def write(tmp_path: Path, text: str, name: str = "p.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def good(tmp_path: Path, order: str = "counterbalanced") -> Path:
    return write(tmp_path, GOOD.replace("ORDER", order))


def test_shipped_protocol_loads_by_name_and_counterbalances() -> None:
    assert "reactive_vs_proactive" in shipped_protocols()
    assert find_protocol("reactive_vs_proactive") == PROTOCOLS_DIR / "reactive_vs_proactive.yaml"
    protocol = load_protocol("reactive_vs_proactive")
    assert protocol.name == "reactive_vs_proactive"
    assert protocol.scenario == "table_one"
    assert [c.system for c in protocol.conditions] == ["pil", "proactive"]
    types = {t.name for t in load_scenario(protocol.scenario).types}
    orders = {}
    for number in (1, 2, 3, 4):
        blocks = protocol.blocks_for(f"P{number:02d}")
        assert [b.index for b in blocks] == list(range(len(blocks)))
        assert all(set(b.handover_types) <= types for b in blocks)
        for block in blocks:  # neutral labels: the text never names the system
            assert block.label in block.instructions
            assert "proactive" not in block.instructions and "pil" not in block.instructions
        orders[number] = [b.condition for b in blocks]
    assert orders[1] == orders[3] == ["pil", "pil", "proactive", "proactive"]
    assert orders[2] == orders[4] == ["proactive", "proactive", "pil", "pil"]


def test_counterbalanced_for_participants_1_to_4(tmp_path: Path) -> None:
    protocol = load_protocol(good(tmp_path))
    firsts = [protocol.blocks_for(f"P{n}")[0].condition for n in (1, 2, 3, 4)]
    assert firsts == ["pil", "proactive", "pil", "proactive"]
    blocks = protocol.blocks_for("P1")
    assert blocks[0] == Block(
        0, "pil", ("A", "B", "C"), "Block 1 of 4: Robot A, 3 legs (A, B, C).", "Robot A"
    )
    assert blocks[3].instructions == "Block 4 of 4: Robot B, 3 legs (A, B, C)."
    assert protocol.condition_order("P2") == ("proactive", "pil")


def test_fixed_order_is_the_same_for_everyone(tmp_path: Path) -> None:
    protocol = load_protocol(good(tmp_path, "fixed"))
    for number in (1, 2, 3, 4):
        assert protocol.condition_order(f"S{number}") == ("pil", "proactive")


@pytest.mark.parametrize("count", [2, 3, 4, 5])
def test_latin_square_is_balanced(count: int) -> None:
    rows = order_rows(count, "latin-square")
    assert len(rows) == (2 * count if count % 2 else count)
    for row in rows:
        assert sorted(row) == list(range(count))
    for position in range(count):  # each condition equally often at each position
        assert set(Counter(row[position] for row in rows).values()) == {len(rows) // count}
    follows = Counter(pair for row in rows for pair in itertools.pairwise(row))
    expected = len(rows) // count  # each ordered pair adjacent equally often (Williams)
    assert set(follows.values()) == {expected}
    assert len(follows) == count * (count - 1)


def test_latin_square_over_four_conditions(tmp_path: Path) -> None:
    text = GOOD.replace("ORDER", "latin-square").replace(
        "  - {system: proactive, label: Robot B}\n",
        "  - {system: proactive, label: Robot B}\n  - c1\n  - {system: c2}\n",
    )
    protocol = load_protocol(write(tmp_path, text))
    assert [c.label for c in protocol.conditions] == ["Robot A", "Robot B", "Robot C", "Robot D"]
    orders = [protocol.condition_order(f"P{n}") for n in range(1, 9)]
    assert orders[:4] == orders[4:]  # four rows, then around again
    assert orders[0] == ("pil", "proactive", "c2", "c1")
    assert {o[0] for o in orders[:4]} == {"pil", "proactive", "c1", "c2"}


def test_per_condition_blocks_and_instructions(tmp_path: Path) -> None:
    text = """\
scenario: table_one
conditions:
  - pil
  - system: proactive
    instructions: "Now {label}."
    blocks:
      - {types: [A]}
      - {types: [B, C], instructions: "Last: {label} ({handovers})"}
order: fixed
blocks:
  - {types: [C, B, A]}
"""
    protocol = load_protocol(write(tmp_path, text, "mine.yaml"))
    assert protocol.name == "mine"  # the file's stem when the name is not given
    blocks = protocol.blocks_for("P7")
    assert [(b.condition, b.handover_types) for b in blocks] == [
        ("pil", ("C", "B", "A")),
        ("proactive", ("A",)),
        ("proactive", ("B", "C")),
    ]
    assert blocks[0].instructions.startswith("Block 1 of 3: you work with Robot A.")
    assert [b.instructions for b in blocks[1:]] == ["Now Robot B.", "Last: Robot B (2)"]


def test_scenario_beside_the_protocol_file(tmp_path: Path) -> None:
    scenario = load_scenario("table_one").source
    (tmp_path / "task.yaml").write_text(
        Path(scenario)
        .read_text()
        .replace("handover_types.yaml", str(Path(scenario).parent / "handover_types.yaml"))
    )
    path = write(tmp_path, GOOD.replace("ORDER", "fixed").replace("table_one", "task.yaml"))
    assert load_protocol(path).scenario == str(tmp_path / "task.yaml")


def test_participant_number_is_the_digits() -> None:
    assert participant_number("P07") == 7
    assert participant_number("s-1-2") == 12
    assert participant_number("12") == 12
    with pytest.raises(ProtocolError, match="participant id 'anna' has no digits"):
        participant_number("anna")


def test_participant_without_digits_is_refused(tmp_path: Path) -> None:
    protocol = load_protocol(good(tmp_path))
    with pytest.raises(ProtocolError, match=r"p\.yaml: participant id 'Pxx' has no digits"):
        protocol.blocks_for("Pxx")


BASE = GOOD.replace("ORDER", "counterbalanced")
SYSTEMS = ", ".join(SYSTEM_SPECS)
TYPES = "A, B, C, D, E, F, G, H, I, J"
REFUSALS = [
    ("name: [unclosed", r"p\.yaml: malformed YAML at line 1"),
    ("- a list", r"p\.yaml: expected a mapping at the top level$"),
    (BASE.replace("order:", "ordre:"), r"p\.yaml: unknown key 'ordre'; valid choices: name, "),
    (
        GOOD.replace("ORDER", "random"),
        r"p\.yaml: order: unknown order 'random'; valid choices: fixed, counterbalanced, "
        r"latin-square",
    ),
    (
        BASE.replace("system: proactive", "system: anticipating"),
        rf"p\.yaml: conditions\[1\]\.system: unknown system 'anticipating'; valid choices: "
        rf"{SYSTEMS}$",
    ),
    (
        BASE.replace("label: Robot B", "label: Robot B, colour: red"),
        r"conditions\[1\]: unknown key 'colour'; valid choices: system, label, blocks, "
        r"instructions",
    ),
    (
        BASE.replace("[A, B, C]", "[A, B, Z]"),
        rf"p\.yaml: blocks\[0\]\.types: unknown handover type 'Z'; valid choices "
        rf"\(scenario .*table_one\.yaml\): {TYPES}$",
    ),
    (BASE.replace("[A, B, C]", "[]"), r"blocks\[0\]\.types: expected a list of 1 to 100 handover"),
    (
        BASE.replace("  - {types: [A, B, C], repeat: 2}\n", "  []\n"),
        r"p\.yaml: blocks: expected a non-empty list of blocks",
    ),
    (
        BASE.replace("blocks:\n  - {types: [A, B, C], repeat: 2}\n", ""),
        r"p\.yaml: blocks: expected a non-empty list of blocks",
    ),
    (
        BASE.replace("repeat: 2", "repeat: 0"),
        r"blocks\[0\]\.repeat: expected a whole number from 1 to 100, got 0",
    ),
    (BASE.replace("repeat: 2", "repeat: true"), r"blocks\[0\]\.repeat: .* got True"),
    (
        BASE.replace("repeat: 2", "times: 2"),
        r"blocks\[0\]: unknown key 'times'; valid choices: types, repeat, instructions",
    ),
    (
        BASE.replace("{label},", "{robot},"),
        r"instructions: unknown placeholder \{robot\}; valid choices: \{label\}, \{block\}, "
        r"\{blocks\}, \{handovers\}, \{types\}",
    ),
    (BASE.replace("{label},", "{label,"), r"p\.yaml: instructions: .*literal braces"),
    (
        BASE.replace('instructions: "', 'instructions: ""\n#"'),
        r"p\.yaml: instructions: expected a non-empty text, got ''",
    ),
    (
        BASE.replace("system: proactive, label: Robot B", "system: pil, label: Robot B"),
        r"conditions: system 'pil' is given twice",
    ),
    (BASE.replace("label: Robot B", "label: Robot A"), r"conditions: label 'Robot A' is given"),
    (
        BASE.replace(
            "conditions:\n  - {system: pil, label: Robot A}\n"
            "  - {system: proactive, label: Robot B}\n",
            "conditions: []\n",
        ),
        rf"p\.yaml: conditions: expected a non-empty list of conditions.*systems: {SYSTEMS}$",
    ),
    (
        BASE.replace("  - {system: pil, label: Robot A}", "  - 3"),
        r"conditions\[0\]: expected a system key or a mapping",
    ),
    (
        BASE.replace("table_one", "no_such_task"),
        r"p\.yaml: scenario: no scenario 'no_such_task' \(neither a file beside the protocol nor "
        r"a shipped scenario\); valid choices: a YAML path or .*table_one",
    ),
]


@pytest.mark.parametrize(("text", "message"), REFUSALS)
def test_refusals_name_the_file_the_field_and_the_choices(
    tmp_path: Path, text: str, message: str
) -> None:
    path = write(tmp_path, text)
    with pytest.raises(ProtocolError, match=message) as caught:
        load_protocol(path)
    assert str(path) in str(caught.value)
    assert isinstance(caught.value, RobinPilError)
    assert len(str(caught.value).splitlines()) == 1


def test_missing_file_lists_the_shipped_protocols(tmp_path: Path) -> None:
    with pytest.raises(ProtocolError, match=r"cannot read the protocol.*reactive_vs_proactive"):
        load_protocol(tmp_path / "nope.yaml")
    with pytest.raises(ProtocolError, match="shipped protocols: reactive_vs_proactive"):
        load_protocol("no_such_protocol")


def test_bad_scenario_file_is_named(tmp_path: Path) -> None:
    write(tmp_path, "tables: zero\n", "task.yaml")
    path = write(tmp_path, BASE.replace("table_one", "task.yaml"))
    with pytest.raises(ProtocolError, match=r"p\.yaml: scenario: .*task\.yaml: tables"):
        load_protocol(path)


def test_not_utf8_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "p.yaml"
    path.write_bytes(b"name: \xff\n")
    with pytest.raises(ProtocolError, match=r"not UTF-8 text \(byte 6\)"):
        load_protocol(path)


def test_orders_constant_lists_the_documented_ones() -> None:
    assert ORDERS == ("fixed", "counterbalanced", "latin-square")


def test_import_needs_no_mujoco() -> None:
    code = "import sys, robin_sim.live.protocol as p; p.load_protocol('reactive_vs_proactive'); "
    code += "print('mujoco' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_without_scenario_the_default_scenarios_types_count(tmp_path: Path) -> None:
    path = write(tmp_path, BASE.replace("scenario: table_one\n", "").replace("[A, B, C]", "[J]"))
    protocol = load_protocol(path)
    assert protocol.scenario is None
    assert protocol.blocks_for("P1")[0].handover_types == ("J",)
