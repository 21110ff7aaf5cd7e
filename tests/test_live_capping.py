"""A study block's caps and the participant's inactivity, in real sessions (live.capping).

Real physics and rendering at 5x real time: a block capped at two robot actions ends
``capped`` with two judged (a third that begins is stopped at once, unlogged), and a
participant who leaves their turn unanswered makes the session hold until their next input;
each is an event of the session and shown on the experimenter's view.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest
from live_driver import Driver

from robin_sim.episode.log import read_step_log
from robin_sim.live.capping import INACTIVE_NOTICE
from robin_sim.live.conductor import Conductor
from robin_sim.live.config import LiveConfig
from robin_sim.live.experimenter import experimenter_view
from robin_sim.live.session import LiveSession

pytestmark = pytest.mark.slow
FAST = dict(handover_types=("A",), speed=5.0, fps=5, eye_inset=False, video=False)


def events(session: LiveSession) -> list[str]:
    path = session.out_dir / "events.jsonl"
    return [json.loads(x)["event"] for x in path.read_text().splitlines()] if path.exists() else []


def test_a_block_capped_at_two_actions_ends_capped_after_the_second(tmp_path: Path) -> None:
    session = LiveSession(LiveConfig(out_root=tmp_path, session="b1", block_actions=2, **FAST))
    session.start()
    driver = Driver(session)
    try:
        driver.my_turn()
        driver.point_at_leg(0)
        while not session.done.is_set():
            status = session.status()
            if status["phase"] == "waiting_for_thumb":
                session.receive({"type": "thumb", "value": "down"})
                driver.wait(lambda s: s["phase"] != "waiting_for_thumb", "the thumb taken")
            elif status["phase"] == "waiting_for_gesture":
                driver.point_at_leg(0)
            time.sleep(0.05)
    finally:
        summary = session.stop("ended")
    assert summary["status"] == "capped"
    limits = summary["live"]["limits"]
    assert (limits["reached"], limits["block_actions"]) == ("actions", 2)
    # two thumbs down: Robin went on to a third action at once, stopped as it began (unlogged)
    assert len(read_step_log(session.out_dir / "log.jsonl")) == 2 <= limits["actions"] <= 3
    assert "limit" in events(session)


def test_an_inactive_participant_holds_the_session_until_their_next_input(tmp_path: Path) -> None:
    config = LiveConfig(out_root=tmp_path, session="b1", inactivity_seconds=5.0, **FAST).checked()
    conductor = Conductor([config])
    session = conductor.sessions[0]
    session.start()
    conductor.phase = "running"  # as the conductor's own start leaves it (no server here)
    driver = Driver(session)
    try:
        driver.my_turn()
        held = driver.wait(lambda s: s["paused"], "the inactivity hold")
        assert held["message"] == INACTIVE_NOTICE and held["notice"] == INACTIVE_NOTICE
        time.sleep(0.3)  # the tick under way when the hold came ends
        sim = session.status()["sim_time"]
        time.sleep(0.5)
        assert session.status()["sim_time"] == sim  # physics holds meanwhile
        view = experimenter_view(conductor, [])
        assert view["limits"]["inactive"] and view["events"][-1]["event"] == "inactive"
        driver.point_at_leg(0)  # they are back: the session runs on and Robin acts
        driver.wait(lambda s: not s["paused"] and s["phase"] == "robot_acting", "Robin acting")
        assert "active" in events(session)
    finally:
        session.stop("ended")
    assert experimenter_view(conductor, [])["limits"]["inactive_times"] == 1
