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

import numpy as np
import pytest
from scipy import stats

from pil.experiments.people_fit import FittedPerson, Latency, Rate, read_person
from pil.task.records import StepRecord
from pil.types import Action, Feedback, Gesture
from robin_sim.cli.main import main
from robin_sim.episode.assemble import layout_of
from robin_sim.fitted.player import FittedPlayer
from robin_sim.fitted.session import Setting, simulate
from robin_sim.live.config import LiveConfig
from robin_sim.live.run import live_parts
from robin_sim.robot.world import PhysicalWorld

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
        Setting.of(json.loads((TINY / source["session"] / "summary.json").read_text())).as_json()
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
    simulate(person, Setting.from_json(person.settings[0]), summary["live"]["seed"], again)
    assert (again / "log.jsonl").read_text() == (sim / "log.jsonl").read_text()
    assert (again / "inputs.jsonl").read_text() == (sim / "inputs.jsonl").read_text()


def test_the_players_thumbs_follow_the_fitted_rates() -> None:
    config = LiveConfig(scenario="one_handover", video=False).checked()
    world = PhysicalWorld(layout_of(config.run_spec().scenario))
    _, participant = live_parts(config, world)
    latency = Latency(1.0, 0.3, 10, 0.9, 1.1)
    person = FittedPerson(
        participant="X",
        gesture_latency=latency,
        down_latency=latency,
        up_latency=Latency(2.0, 0.3, 10, 1.8, 2.2),
        down_on_wrong_move=Rate(9, 10, 0.9, 0.5, 1.0),
        down_on_wrong_fingers=Rate(6, 10, 0.6, 0.3, 0.9),
        down_on_right=Rate(1, 10, 0.1, 0.0, 0.4),
        up_on_right=Rate(5, 10, 0.5, 0.2, 0.8),
        late_thumbs=0,
    )
    player = FittedPlayer(person, participant, np.random.default_rng(1), lambda *a: None)
    base = StepRecord(0, 1, 0, 0, "A", 0, Gesture.POINTING, Gesture.POINTING, Action.OBJECT, 0)
    cases = {  # action -> (wanted, P(thumb down), P(thumb up))
        Action.LOCATION: (Action.OBJECT, 0.9, 0.0),
        Action.CLOSE: (Action.OBJECT, 0.6, 0.0),
        Action.OBJECT: (Action.OBJECT, 0.1, 0.5),  # shares of all right actions
    }
    n = 1000
    for action, (wanted, p_down, p_up) in cases.items():
        thumbs = []
        for _ in range(n):
            player.decided(base._replace(action=action, intended_action=wanted))
            thumbs.append(None if player.thumb is None else player.thumb[0])
        downs = sum(t is Feedback.NOT_OK for t in thumbs)
        ups = sum(t is Feedback.OK for t in thumbs)
        assert stats.binomtest(downs, n, p_down).pvalue > 0.001, (action, downs)
        assert stats.binomtest(ups, n, p_up).pvalue > 0.001 if p_up else ups == 0
