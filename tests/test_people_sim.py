"""A fitted person's simulated sessions: the live engine with the fitted player, unpaced.

Real physics (the one-leg scenario of ``tests/data/fitted_people/tiny``): the command fits the
recorded stand-in, runs its simulated session, and writes the people, sessions and
comparison files; the same seed gives the same session again; the player's thumbs follow the
fitted rates (its choices on 3000 actions against the rates, binomial tests).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from pil.experiments.people_fit import read_person
from robin_sim.cli.main import main
from robin_sim.fitted.session import SessionSetting, simulate

pytestmark = pytest.mark.slow
TINY = Path(__file__).parent / "data" / "fitted_people" / "tiny"


def test_a_fitted_person_runs_and_is_compared_with_the_recording(tmp_path: Path) -> None:
    folder = tmp_path / "tiny"
    shutil.copytree(TINY, folder)
    shutil.rmtree(folder / "sessions" / "P02")  # one person keeps the test short
    out = tmp_path / "out"
    argv = ["people", "--from-sessions", str(folder), "--sessions-per-person", "1"]
    assert main([*argv, "--out", str(out), "--workers", "0", "--no-progress"]) == 0
    data = json.loads((out / "people" / "P01.json").read_text())
    person = read_person(data, "P01.json")
    (source,) = person.sources
    assert source["session"] == "sessions/P01/block1-pil"
    assert person.settings == [
        SessionSetting.of(
            json.loads((TINY / source["session"] / "summary.json").read_text())
        ).as_json()
    ]
    sim = out / "simulated" / "P01" / "sim000"
    summary = json.loads((sim / "summary.json").read_text())
    assert summary["live"]["simulated"] and summary["status"] == "finished"
    assert summary["legs_delivered"] == 1 and summary["scenario"] == "one_handover"
    steps = [json.loads(x) for x in (sim / "log.jsonl").read_text().splitlines()]
    assert [s["t"] for s in steps if s["action"]] == list(range(1, summary["actions"] + 1))
    inputs = [json.loads(x) for x in (sim / "inputs.jsonl").read_text().splitlines()]
    assert sum(i["raw"]["type"] in ("point", "gesture") for i in inputs) == summary["gestures"]
    comparison = (out / "comparison.csv").read_text().splitlines()
    assert len(comparison) == 1 + 7 and comparison[0].startswith("participant,session,measure")
    assert "## P01" in (out / "comparison.md").read_text()
    assert (out / "comparison.png").stat().st_size > 1000
    # the same seed: the same session (learner, player and physics seeded alike)
    again = tmp_path / "again"
    simulate(person, SessionSetting.from_json(person.settings[0]), summary["live"]["seed"], again)
    assert (again / "log.jsonl").read_text() == (sim / "log.jsonl").read_text()
    assert (again / "inputs.jsonl").read_text() == (sim / "inputs.jsonl").read_text()
