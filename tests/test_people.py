"""The personal-mappings study (robin-pil people): two people, shared vs per-person tables."""

from __future__ import annotations

import statistics
from pathlib import Path

import pytest

from pil.experiments.people import People, load_people, person_types, run_people_study
from pil.task.scenario import ScenarioError
from pil.types import Action, Gesture
from robin_sim.cli.main import main


def test_people_file_and_their_types() -> None:
    people = load_people()
    assert list(people.overrides) == ["A", "B"]
    a = people.scenario.type_named("A")
    (mine,) = person_types(people, "B", [a])
    assert [s.action for s in mine.steps if s.gesture is Gesture.GIVE_ME] == [Action.LOCATION]
    assert person_types(people, "A", [a]) == [a]


def test_bad_people_file(tmp_path: Path) -> None:
    path = tmp_path / "p.yaml"
    path.write_text("people: {A: [], B: [wave -> open]}\n")
    with pytest.raises(ScenarioError, match="unknown gesture 'wave'"):
        load_people(path)
    path.write_text("people: {A: []}\n")
    with pytest.raises(ScenarioError, match="at least two people"):
        load_people(path)


def _actions(rows: list[dict], mode: str) -> float:
    return statistics.fmean(r["actions"] for r in rows if r["mode"] == mode)


def test_a_table_per_person_pays_off_only_in_the_long_run() -> None:
    people = load_people()
    short = run_people_study(people, ("pil",), rates=(1.0,), reps=6)
    assert all(r["legs"] == 40 for r in short)
    long = People(people.scenario.with_changes(tables=40), people.overrides)
    rows = run_people_study(long, ("pil",), rates=(1.0,), reps=6)
    # shared: the give me counts of A and B keep competing, a refusal per instruction of
    # the one behind; per person: each learner explores its states once, then never errs
    assert _actions(rows, "per-person") < _actions(rows, "shared") - 20
    assert _actions(short, "per-person") > _actions(short, "shared") - 20


def test_people_command(tmp_path: Path) -> None:
    argv = [
        "people",
        "--systems",
        "pil",
        "--reps",
        "2",
        "--rates",
        "1.0",
        "--tables",
        "4",
        "--out",
        str(tmp_path),
        "--no-progress",
    ]
    assert main(argv) == 0
    assert {p.name for p in tmp_path.iterdir()} == {
        "people.csv",
        "people.md",
        "people.png",
        "tests.csv",
        "reps.jsonl",  # the finished repetitions (a rerun resumes from them)
    }
    tests = (tmp_path / "tests.csv").read_text().splitlines()
    assert tests[0].startswith("measure,reading,rate,system,system_a,system_b,test,n,pairing,")
    assert ",shared,per-person,paired t,2,rep+seed," in tests[1]
    assert main([*argv[:2], "bandit", "--out", str(tmp_path / "never")]) == 2
    assert main(["people", "--tables", "0", "--out", str(tmp_path / "never")]) == 2
    assert not (tmp_path / "never").exists()
