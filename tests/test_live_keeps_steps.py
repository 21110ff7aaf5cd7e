"""Ending a live session at any moment keeps every step the learner has received.

Real physics and rendering at 3x real time: a type-A handover of the first of four legs, the
closing open approved with a thumb up, then End while the simulated hand still carries the
delivered leg to the bin.
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from live_driver import Driver

from robin_sim.episode.log import read_step_log
from robin_sim.live.config import LiveConfig
from robin_sim.live.session import LiveSession

pytestmark = pytest.mark.slow
TYPE_A = (("point", "object"), ("grasp", "close"), ("give_me", "human"), ("release", "open"))


def test_end_during_the_carry_to_the_bin_keeps_the_approved_open(tmp_path: Path) -> None:
    config = LiveConfig(
        handover_types=("A",),
        out_root=tmp_path,
        session="s1",
        speed=3.0,
        fps=10,
        # 2 s of wall time at speed 3 for the test thread's thumbs, also on a busy machine
        feedback_window=6.0,
        video=False,
    )
    session = LiveSession(config)
    session.start()
    driver = Driver(session)
    try:
        for gesture, wanted in TYPE_A:
            driver.my_turn()
            if gesture == "point":
                driver.point_at_leg(0)
            else:
                driver.gesture(gesture)
            driver.judge(wanted)  # a thumb up for each wanted action
        # the counter moved when the leg reached the person's hand, before the carry ends
        status = session.status()
        body = session.body
        assert body is not None
        assert status["legs_delivered"] == 1 and status["legs_total"] == 4, status
        assert body.leg_on_palm() is not None, "the leg should still be on the palm"
        assert status["phase"] == "robot_acting" and not session.done.is_set()
        session.receive({"type": "end"})
        assert session.done.wait(60), session.status()
    finally:
        summary = session.stop()
    assert summary["status"] == "ended", summary
    assert summary["legs_delivered"] == 1, summary
    steps = read_step_log(session.out_dir / "log.jsonl")
    approved = [s["action"] for s in steps if s["feedback"] != "not ok"]
    assert approved == [a for _, a in TYPE_A]
    last = steps[-1]
    assert last["action"] == "open" and last["delivered"] and last["feedback"] == "ok"
    assert summary["actions"] == len(steps)


def test_a_paused_session_holds_physics_and_still_ends_on_end(tmp_path: Path) -> None:
    config = LiveConfig(
        scenario="one_handover", out_root=tmp_path, session="s1", speed=3.0, fps=10, video=False
    )
    session = LiveSession(config)
    session.start()
    driver = Driver(session)
    try:
        driver.my_turn()
        session.pause(True)
        time.sleep(0.5)  # the tick under way ends
        held = session.status()
        time.sleep(2.0)
        assert session.status()["sim_time"] == held["sim_time"] and held["paused"]
        assert held["message"] == "Paused by the experimenter: please wait."
        session.pause(False)
        driver.wait(lambda s: s["sim_time"] > held["sim_time"] + 0.3, "physics to run on")
        # the 2.5 s pause is not counted as pace lost (a busy machine may lose a little)
        assert session.status()["behind_s"] - held["behind_s"] < 1.5
        session.pause(True)
        session.receive({"type": "end"})
        assert session.done.wait(20), "End should end a paused session"
    finally:
        summary = session.stop()
    assert summary["status"] == "ended"
