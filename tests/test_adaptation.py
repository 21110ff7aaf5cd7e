"""The adaptation study (robin-pil adapt): the change file, the remapped script, the costs."""

from __future__ import annotations

import statistics
from pathlib import Path

import pytest

from pil.experiments.adaptation import (
    changed_script,
    load_change,
    remap,
    run_adaptation_study,
)
from pil.task.parts import derive_seeds
from pil.task.scenario import ScenarioError
from pil.types import Action, Gesture
from robin_sim.cli.main import main


def test_the_shipped_change_and_its_script() -> None:
    change = load_change()
    assert (change.from_table, change.gesture, change.action) == (
        6,
        Gesture.GIVE_ME,
        Action.LOCATION,
    )
    scenario = change.scenario
    script = changed_script(scenario, change, derive_seeds(0)["test_draw"])
    first_changed = (change.from_table - 1) * scenario.legs_per_table
    for item in script:
        if item.intent.gesture is Gesture.GIVE_ME:
            wanted = Action.LOCATION if item.intent.handover >= first_changed else Action.HUMAN
            assert item.intent.action is wanted
    a = scenario.type_named("A")
    remapped = remap(a, Gesture.GIVE_ME, Action.LOCATION)
    assert [s.action for s in remapped.steps] == [
        Action.OBJECT,
        Action.CLOSE,
        Action.LOCATION,
        Action.OPEN,
    ]
    assert remapped.steps[3].state.previous_action is Action.LOCATION  # states recomputed


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("change: {from_table: 6, gesture: wave, action: location}\n", "unknown gesture 'wave'"),
        ("change: {from_table: 11, gesture: give me, action: location}\n", "from 2 to 10"),
        ("change: {from_table: 6, gesture: give me}\n", "expected the keys"),
        ("colour: red\n", "unknown key 'colour'"),
    ],
)
def test_bad_change_files_give_one_clear_error(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "change.yaml"
    path.write_text("scenario: " + str(Path(load_change().scenario.source)) + "\n" + text)
    with pytest.raises(ScenarioError, match=message) as raised:
        load_change(path)
    assert str(path) in str(raised.value)


def test_halving_adapts_sooner_and_pre_training_makes_a_stronger_habit() -> None:
    rows = run_adaptation_study(load_change(), ("pil", "pil-halve", "c4"), rates=(1.0,), reps=6)
    by = {s: [r for r in rows if r["system"] == s] for s in ("pil", "pil-halve", "c4")}
    lost = {s: statistics.fmean(r["lost_rejections"] for r in v) for s, v in by.items()}
    habit = {s: statistics.fmean(r["habit"] for r in v) for s, v in by.items()}
    assert lost["pil-halve"] < lost["pil"] <= lost["c4"]
    assert habit["c4"] > 1.5 * habit["pil"]
    assert all(r["adapted"] for r in by["pil-halve"])
    # eq. 2: counts only grow. At 100 % each instruction in the habit state refuses the old
    # action once and approves the new one, which is exploited once it has one approval more
    # than the habit: at the habit + 2nd instruction, exactly.
    for r in by["pil"]:
        assert r["habit_state"] == "give me|close|occupied"
        if r["adapted"]:
            assert r["instructions_to_adapt"] == r["habit"] + 2


def test_adapt_command_writes_csv_summary_and_figure(tmp_path: Path, capsys) -> None:  # type: ignore[no-untyped-def]
    argv = [
        "adapt",
        "--systems",
        "pil,pil-halve",
        "--reps",
        "2",
        "--rates",
        "1.0",
        "--out",
        str(tmp_path),
        "--no-progress",
    ]
    assert main(argv) == 0
    assert {p.name for p in tmp_path.iterdir()} == {
        "adaptation.csv",
        "adaptation.md",
        "adaptation.png",
        "tests.csv",
    }
    text = (tmp_path / "adaptation.md").read_text()
    assert "| lost_rejections | - | 1.0 | pil | pil-halve | paired t | 2 | rep+seed |" in text
    assert main(["adapt", "--systems", "pil,robot", "--out", str(tmp_path / "x")]) == 2
    assert (
        main(["adapt", "--change", str(tmp_path / "none.yaml"), "--out", str(tmp_path / "x")]) == 2
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert err[0].startswith("robin-pil adapt: error: unknown --systems: system 'robot'")
    assert err[1].startswith("robin-pil adapt: error:") and "none.yaml" in err[1]
    assert not (tmp_path / "x").exists()
