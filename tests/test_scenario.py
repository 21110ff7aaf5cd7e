"""Scenario files: the shipped ones load; every broken rule is rejected with a clear error."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from pil.task.layout import LayoutSection
from pil.task.params import ASSEMBLY
from pil.task.scenario import (
    ASSEMBLY_DEFAULTS,
    DEFAULT_SCENARIO,
    DEFAULT_TYPES,
    SCENARIOS_DIR,
    ScenarioError,
    load_scenario,
    states_along,
)
from pil.types import Action, Gesture, State
from pil.validity import VALID_STATES

TYPES_HEADER = "types:\n"


def write(tmp_path: Path, text: str, name: str = "s.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def one_type(steps: list[str], name: str = "X") -> str:
    return TYPES_HEADER + f"  {name}:\n    steps: [{', '.join(steps)}]\n"


def test_shipped_types_use_55_gestures_and_all_12_valid_states() -> None:
    scenario = load_scenario(DEFAULT_TYPES)
    assert [t.name for t in scenario.types] == list("ABCDEFGHIJ")
    assert [len(t) for t in scenario.types] == [4, 4, 6, 5, 6, 5, 6, 7, 5, 7]
    assert sum(len(t) for t in scenario.types) == 55
    assert set(scenario.correct_actions()) == set(VALID_STATES)


def test_table_one_types_follow_the_paper() -> None:
    scenario = load_scenario(SCENARIOS_DIR / "table_one.yaml")
    types = scenario.draw_types(3, seed=0)
    assert [t.name for t in types] == ["A", "B", "C"]
    steps = [s for t in types for s in t.steps]
    assert len(steps) == 14  # "user performs 14 instruction gestures to receive 3 objects"
    # Table I, t = 20-22: give me after close, then pointing after human
    assert steps[11].state == State("give me", "close", "occupied")
    assert steps[12].state == State("pointing", "human", "occupied")
    assert steps[12].action is Action.LOCATION


def test_assembly_defaults() -> None:
    scenario = load_scenario()
    assert (scenario.tables, scenario.legs_per_table, scenario.training_tables) == (10, 4, 5)
    assert scenario.draw == "balanced"


def test_balanced_draw_uses_each_type_equally_often_and_depends_on_the_seed() -> None:
    scenario = load_scenario()
    drawn = scenario.draw_types(20, seed=3)
    assert sorted(t.name for t in drawn) == sorted("ABCDEFGHIJ" * 2)
    assert drawn == scenario.draw_types(20, seed=3)
    assert drawn != scenario.draw_types(20, seed=4)
    uneven = [t.name for t in scenario.draw_types(13, seed=1)]
    assert (
        max(uneven.count(n) for n in "ABCDEFGHIJ") - min(uneven.count(n) for n in "ABCDEFGHIJ") <= 1
    )


def test_states_along_tracks_hand_and_previous_action() -> None:
    pairs = [
        (Gesture.POINTING, Action.OBJECT),
        (Gesture.GRASP, Action.CLOSE),
        (Gesture.RELEASE, Action.OPEN),
        (Gesture.POINTING, Action.OBJECT),
    ]
    states = states_along(pairs)
    assert states[1] == State("grasp", "object", "free")
    assert states[2] == State("release", "close", "occupied")
    assert states[3] == State("pointing", "open", "free")


def test_conflicting_state_is_rejected_naming_state_and_types(tmp_path: Path) -> None:
    text = (
        TYPES_HEADER + "  A:\n    steps: [pointing -> object, grasp -> close, give me -> human, "
        "release -> open]\n"
        + "  Z:\n    steps: [pointing -> object, grasp -> close, give me -> location, "
        "release -> open]\n"
    )
    with pytest.raises(ScenarioError) as info:
        load_scenario(write(tmp_path, text))
    message = str(info.value)
    assert "<give me, close, occupied>" in message
    assert "type A" in message and "type Z" in message


@pytest.mark.parametrize("count", [3, 8])
def test_type_length_outside_4_to_7_is_rejected(tmp_path: Path, count: int) -> None:
    steps = ["pointing -> object", "grasp -> close", "release -> open"] * 3
    with pytest.raises(ScenarioError, match=f"4 to 7 gestures, got {count}"):
        load_scenario(write(tmp_path, one_type(steps[:count])))


def test_unknown_gesture_lists_the_valid_ones(tmp_path: Path) -> None:
    steps = ["pointing -> object", "wave -> close", "give me -> human", "release -> open"]
    with pytest.raises(ScenarioError) as info:
        load_scenario(write(tmp_path, one_type(steps)))
    assert "unknown gesture 'wave'" in str(info.value)
    assert "'pointing', 'give me', 'grasp', 'release'".replace("'", "") in str(info.value)


def test_unknown_action_lists_the_valid_ones(tmp_path: Path) -> None:
    steps = ["pointing -> fly", "grasp -> close", "give me -> human", "release -> open"]
    with pytest.raises(ScenarioError, match="unknown action 'fly'; valid choices: open, close"):
        load_scenario(write(tmp_path, one_type(steps)))


def test_invalid_state_is_rejected(tmp_path: Path) -> None:
    steps = ["grasp -> close", "pointing -> location", "give me -> human", "release -> open"]
    with pytest.raises(ScenarioError, match=r"invalid state <grasp, open, free>"):
        load_scenario(write(tmp_path, one_type(steps)))


def test_zero_tables_is_rejected(tmp_path: Path) -> None:
    path = write(tmp_path, f"types: {DEFAULT_TYPES}\ntables: 0\n")
    with pytest.raises(ScenarioError, match=r"tables must be a whole number from 1 to 1000, got 0"):
        load_scenario(path)


def test_unknown_key_and_draw_are_rejected(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match="unknown key 'tabels'; valid choices: name"):
        load_scenario(write(tmp_path, f"types: {DEFAULT_TYPES}\ntabels: 3\n"))
    with pytest.raises(
        ScenarioError, match="draw must be one of 'balanced', 'cycle', 'random', got 'zigzag'"
    ):
        load_scenario(write(tmp_path, f"types: {DEFAULT_TYPES}\ndraw: zigzag\n"))


def test_malformed_yaml_names_the_file(tmp_path: Path) -> None:
    path = write(tmp_path, "types: [unclosed\n")
    with pytest.raises(ScenarioError, match="malformed YAML") as info:
        load_scenario(path)
    assert str(path) in str(info.value)


def test_missing_file_is_a_scenario_error(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match="cannot read the scenario"):
        load_scenario(tmp_path / "nope.yaml")


def test_layout_is_parsed_when_the_scenario_is_loaded(tmp_path: Path) -> None:
    """The layout section is typed from the load on (issue 26: it stayed an untyped mapping
    until the world was built): legs with their yaw in radians, defaults left as None."""
    path = write(tmp_path, f"types: {DEFAULT_TYPES}\nlayout:\n  legs: [[0.5, 0.1, 90]]\n")
    layout = load_scenario(path).layout
    assert layout.legs == ((0.5, 0.1, pytest.approx(math.pi / 2)),)
    assert (layout.spots, layout.handover, layout.bin) == (None, None, None)
    assert load_scenario().layout == LayoutSection()


@pytest.mark.parametrize(
    ("section", "needle"),
    [
        ("legs: abc", "layout 'legs' must be a list"),
        ("legz: []", "unknown layout key(s) ['legz']; valid keys: ['legs', 'spots'"),
        ("legs: [[0.5, .nan]]", "leg 0 y must be a finite number"),
        ("handover: [0.6, 0.0]", "handover must be [x, y, z]"),
        ("spots: [{x: 0.6}]", "spot 0 needs exactly the keys ['x', 'y']"),
    ],
)
def test_a_malformed_layout_is_refused_at_load(tmp_path: Path, section: str, needle: str) -> None:
    path = write(tmp_path, f"types: {DEFAULT_TYPES}\nlayout:\n  {section}\n")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    assert str(path) in str(info.value) and needle in str(info.value), str(info.value)


def test_with_changes_validates() -> None:
    scenario = load_scenario()
    assert scenario.with_changes(tables=2).tables == 2
    with pytest.raises(ScenarioError, match="tables"):
        scenario.with_changes(tables=0)


def test_scenario_pickles_for_worker_processes() -> None:
    import pickle

    scenario = load_scenario()
    assert pickle.loads(pickle.dumps(scenario)) == scenario


def test_the_shipped_assembly_is_the_default_one() -> None:
    # scenarios/assembly.yaml spells out the paper's test; a file without the keys gets the same
    scenario = load_scenario(DEFAULT_SCENARIO)
    assert {key: getattr(scenario, key) for key in ASSEMBLY_DEFAULTS} == ASSEMBLY_DEFAULTS
    assert set(ASSEMBLY) == set(ASSEMBLY_DEFAULTS)  # every setting has a spec and a default
