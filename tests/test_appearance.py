"""The appearance study (``robin-pil people --appearance``) and the person's looks as vision
parameters: bad input refused before anything runs; a real (small) study run, resumed, and
its files; an adapting eye-camera episode learning only from approvals."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from pil.task.scenario import ScenarioError
from robin_sim.appearance.people import DEFAULT_APPEARANCE, load_appearance
from robin_sim.cli.main import main


def test_the_shipped_people_file() -> None:
    people = load_appearance()
    names = [p.name for p in people.people]
    assert names == ["usual", "lightest_bright", "darkest_dim"] and people.tables == 3
    hardest = people.people[1].settings
    assert (hardest.skin, hardest.pose_jitter, hardest.lighting) == (0.0, 2.0, 1.3)
    assert not hardest.adapt  # the study sets it per run
    assert people.only(["darkest_dim"]).people[0].name == "darkest_dim"
    with pytest.raises(ScenarioError, match=r"'nobody'.*valid choices: usual, lightest_bright"):
        people.only(["nobody"])


@pytest.mark.parametrize(
    ("text", "problem"),
    [
        ("people: {a: {skin: 5}}\n", r"people.a: parameter 'skin' must be a number in \[0, 4\]"),
        ("people: {a: {hair: 1}}\n", "unknown key 'hair'; valid choices: lighting, camera_noise"),
        ("people: {a: {adapt: true}}\n", "unknown key 'adapt'"),
        ("people: {a: [1]}\n", "people.a: expected a mapping"),
        ("people: []\n", "expected 1 to 12 people"),
        ("people: {a: {}}\ntables: 0\n", "tables"),
        ("people: {a: {}}\ncolour: red\n", "unknown key 'colour'"),
    ],
)
def test_a_bad_people_file_is_refused_naming_the_problem(
    tmp_path: Path, text: str, problem: str
) -> None:
    path = tmp_path / "people.yaml"
    path.write_text(text)
    with pytest.raises(ScenarioError, match=problem):
        load_appearance(path)


def test_bad_appearance_options_exit_2_before_anything_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    never = tmp_path / "never"
    base = ["people", "--appearance", "--out", str(never), "--no-progress"]
    bad = tmp_path / "bad.yaml"
    bad.write_text("people: {a: {skin: -1}}\n")
    cases = [
        (["--person", "nobody"], "valid choices: usual, lightest_bright, darkest_dim"),
        (["--people", str(bad)], "'skin' must be a number in [0, 4]"),
        (["--seeds", "2"], "give more with --reps"),
        (["--workers", "99"], "--workers must be 0 to 16"),
        (["--reps", "0"], "--reps"),
        (["--tables", "0"], "--tables"),
    ]
    for extra, message in cases:
        assert main([*base, *extra]) == 2, extra
        assert message in capsys.readouterr().err, extra
    assert main(["people", "--person", "usual", "--out", str(never)]) == 2
    assert "add --appearance" in capsys.readouterr().err
    assert not never.exists()


def test_looks_and_adapt_need_the_eye_cameras(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = ["--out", str(tmp_path / "never"), "--no-video", "--no-progress"]
    assert main(["episode", "--param", "adapt=true", *out]) == 2
    assert "need --detector vision" in capsys.readouterr().err
    assert main(["episode", "--detector", "vision", "--param", "skin=4.5", *out]) == 2
    assert "'skin' must be a number in [0, 4]" in capsys.readouterr().err
    assert main(["episode", "--detector", "vision", "--param", "pose_jitter=3", *out]) == 2
    assert "[0, 2.5]" in capsys.readouterr().err
    assert not (tmp_path / "never").exists()


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open() as handle:
        return list(csv.DictReader(handle))


SMALL_TABLE = """name: two_legs
description: a table of two legs, a test's size (the shipped four-leg table took 133 s here)
types: {types}
tables: 1
legs_per_table: 2
training_tables: 0
draw: balanced
spots: 4
"""
SMALL_PEOPLE = """name: people_appearance_small
description: the appearance study's darkest person on a two-leg table
scenario: two_legs.yaml
tables: 1
people:
  darkest_dim: {skin: 4, pose_jitter: 2, lighting: 0.4}
"""


@pytest.mark.slow
def test_a_small_study_runs_pairs_and_resumes(tmp_path: Path) -> None:
    from pil.task.scenario import SCENARIOS_DIR

    (tmp_path / "two_legs.yaml").write_text(
        SMALL_TABLE.format(types=SCENARIOS_DIR / "handover_types.yaml")
    )
    people = tmp_path / "people.yaml"
    people.write_text(SMALL_PEOPLE)
    out = tmp_path / "study"
    argv = ["people", "--appearance", "--people", str(people), "--person", "darkest_dim"]
    argv += ["--reps", "2", "--tables", "1", "--out", str(out), "--no-progress", "--workers", "2"]
    assert main(argv) == 0
    names = {p.name for p in out.iterdir()}
    assert {"appearance_runs.csv", "appearance_tables.csv", "tests.csv", "appearance.md"} <= names
    assert "appearance.png" in names
    runs = _rows(out / "appearance_runs.csv")
    assert sorted((r["classifier"], r["rep"]) for r in runs) == [
        ("adapted", "0"),
        ("adapted", "1"),
        ("fixed", "0"),
        ("fixed", "1"),
    ]
    by_rep = {}
    for r in runs:
        assert r["status"] == "finished" and r["skin"] == "4.0" and r["lighting"] == "0.4"
        assert 0.5 <= float(r["detection_rate"]) <= 1.0
        by_rep.setdefault(r["rep"], set()).add(r["seed"])
    assert all(len(seeds) == 1 for seeds in by_rep.values())  # fixed and adapted share a seed
    assert by_rep["0"] != by_rep["1"]  # repetitions do not
    adapted = [r for r in runs if r["classifier"] == "adapted"]
    assert all(int(r["examples"]) > 0 for r in adapted)
    assert all(int(r["examples"]) == 0 for r in runs if r["classifier"] == "fixed")
    tables = _rows(out / "appearance_tables.csv")
    assert len(tables) == 4 and all(t["table"] == "1" for t in tables)
    for t in tables:
        assert int(t["readings"]) >= int(t["read_right"]) > 0
        if t["classifier"] == "fixed":  # read by the shipped model itself
            assert t["shipped_detection_rate"] == t["detection_rate"]
    tests = _rows(out / "tests.csv")
    assert {t["measure"] for t in tests} == {"detection_rate", "gestures", "actions"}
    assert all(t["pairing"] == "rep+seed" and t["n"] == "2" for t in tests)
    # adapted runs against fixed runs; and the adapted model against the shipped one reading
    # the same views (the detection rate only)
    pairs = {(t["system_a"], t["system_b"], t["measure"]) for t in tests}
    assert ("fixed", "adapted", "actions") in pairs
    assert ("shipped_same_views", "adapted", "detection_rate") in pairs
    assert ("shipped_same_views", "adapted", "actions") not in pairs
    report = (out / "appearance.md").read_text()
    assert "| darkest_dim | shipped_same_views |" in report
    # resumed: finished runs are read back, not run again; a damaged one runs again
    files = sorted((out / "runs").glob("*.json"))
    stamps = {p: p.stat().st_mtime_ns for p in files}
    damaged = files[0]
    damaged.write_text('{"row": ')
    assert main(argv) == 0
    for path in files:
        if path == damaged:
            assert json.loads(path.read_text())["row"]["status"] == "finished"
        else:
            assert path.stat().st_mtime_ns == stamps[path], path
    assert _rows(out / "appearance_runs.csv") == runs


@pytest.mark.slow
def test_an_adapting_episode_learns_only_from_what_it_took_as_approved(tmp_path: Path) -> None:
    out = tmp_path / "episode"
    argv = ["episode", "--detector", "vision", "--no-video", "--no-verify", "--no-progress"]
    argv += ["--param", "adapt=true", "--param", "skin=0", "--param", "pose_jitter=2"]
    argv += ["--param", "lighting=1.3", "--out", str(out)]
    assert main(argv) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "finished"
    vision = summary["vision"]
    assert (vision["skin"], vision["pose_jitter"], vision["lighting"]) == (0.0, 2.0, 1.3)
    adapt = vision["adapt"]
    log = [json.loads(line) for line in (out / "episode.jsonl").read_text().splitlines()]
    approved = [e for e in log if e["action"] is not None and e["feedback_read"] != "not ok"]
    # each approval labels the readings made for its instruction (or drops them without
    # evidence of the gesture): never more approvals than the robot took, never more readings
    # than were made (no hand found: none to learn from)
    assert 0 < adapt["approvals_learnt_from"] <= len(approved)
    assert adapt["approvals_learnt_from"] <= adapt["readings_confirmed"]
    labelled_or_not = adapt["readings_confirmed"] + adapt["readings_unlabelled"]
    assert labelled_or_not <= vision["gestures_read"] - vision["no_hand"]
    assert adapt["refits"] == adapt["approvals_learnt_from"]
    assert adapt["examples"] >= adapt["readings_confirmed"]  # one row per eye that saw the hand
    # every reading also records what the shipped model reads in the same views
    readings = [v for e in log for v in e.get("vision") or [] if v["kind"] == "gesture"]
    assert readings and all("shipped" in v for v in readings)
    right = sum(v["shipped"] == v["shown"] for v in readings) / len(readings)
    assert vision["shipped_detection_rate"] == pytest.approx(right)
    assert DEFAULT_APPEARANCE.exists()
