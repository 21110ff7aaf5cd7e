"""A live session has no state without a way out (real sessions: physics, the learner, files).

The lock-up of seed 0 replayed step by step: the participant points at leg 1, Robin closes its
hand on nothing and opens it again at once; that action gets its feedback window like any other,
so a thumb down 3.5 s after it is taken. A gesture Robin cannot act on is handed back to the
participant (never performed again by itself), the guide never asks for one, and the step's
watchdog hands a step back after its attempts; within one step no refused action is tried again
until all five were (the within-step memory, on in live sessions).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from live_driver import read_jsonl
from live_driver import start_session as session

from robin_sim.live.session import LiveSession

pytestmark = pytest.mark.slow


def sim_time(live: LiveSession) -> float:
    body = live.body
    assert body is not None
    return body.world.time


def test_the_thumb_down_after_a_close_on_nothing_is_taken(tmp_path: Path) -> None:
    live, driver = session(tmp_path, seed=0)  # the seed: the first try is a close
    try:
        driver.my_turn()
        driver.point_at_leg(0)
        shown = driver.wait(
            lambda s: s["phase"] == "waiting_for_thumb", "the close's feedback window"
        )
        assert shown["last_action"] == "close" and shown["feedback_left_s"] > 3.0, shown
        assert "took that back by itself" in shown["message"], shown["message"]
        opened = sim_time(live)
        driver.wait(lambda s: sim_time(live) >= opened + 3.5, "3.5 s of the window")
        live.receive({"type": "thumb", "value": "down"})  # refused before: no window
        driver.wait(lambda s: s["actions"] >= 1, "the close logged")
        nxt = driver.wait(lambda s: s["action"] is not None, "Robin's next try")
        assert nxt["action"] != "close", nxt  # refused in this step: not tried again
    finally:
        summary = live.stop("ended")
    steps = read_jsonl(live.out_dir / "log.jsonl")
    assert steps[0]["action"] == "close" and steps[0]["feedback"] == "not ok", steps[0]
    assert steps[0]["detail"] == "closed on nothing; opened again"
    assert summary["live"]["seed"] == 0


def test_a_gesture_robin_cannot_act_on_is_handed_back_never_looped(tmp_path: Path) -> None:
    live, driver = session(tmp_path, seed=0, feedback_window=1.0)
    try:
        driver.my_turn()
        driver.point_at_leg(0)
        driver.wait(lambda s: s["phase"] == "waiting_for_thumb", "the close's window")
        # silence: the close on nothing stands; the page says so
        turn = driver.my_turn()
        assert turn["notice"].startswith("No thumb: Robin takes 'close' as OK"), turn
        # the guide asks for the leg again, not for the grasp (invalid away from a leg)
        assert turn["guide"]["instruction"].startswith("Point at the red leg"), turn["guide"]
        gestures = turn["gestures"]
        driver.gesture("grasp")  # made anyway
        driver.wait(lambda s: s["gestures"] > gestures, "the grasp taken")
        back = driver.wait(
            lambda s: s["phase"] == "waiting_for_gesture" and "grasp" in s["notice"],
            "the step handed back",
        )
        assert "hand is not at a leg" in back["notice"], back["notice"]
        asked = sim_time(live)
        driver.wait(lambda s: sim_time(live) >= asked + 5.0, "5 s of waiting")
        after = live.status()
        assert after["phase"] == "waiting_for_gesture"
        assert after["gestures"] == gestures + 1  # the one made, never repeated by itself
    finally:
        live.stop("ended")
    events = read_jsonl(live.out_dir / "events.jsonl")
    kinds = [e["event"] for e in events]
    assert kinds.count("handed_back") == 1 and "silence" in kinds, kinds
    repeats = [s for s in read_jsonl(live.out_dir / "log.jsonl") if s["action"] is None]
    assert len(repeats) == 1 and repeats[0]["true_gesture"] == "grasp", repeats


def test_the_watchdog_hands_back_and_no_refused_action_is_tried_twice(tmp_path: Path) -> None:
    """Thumb down on every try: the first five tries are five different actions (the memory),
    and after ``max_attempts`` the robot stops and the step goes back to the participant."""
    live, driver = session(tmp_path, seed=1, max_attempts=6)
    tried: list[str] = []
    try:
        driver.my_turn()
        driver.point_at_leg(0)
        driver.wait(lambda s: s["phase"] != "waiting_for_gesture", "the pointing taken")
        while True:
            s = driver.wait(
                lambda s: (
                    s["action"] is not None
                    or s["phase"] == "waiting_for_thumb"
                    or (s["phase"] == "waiting_for_gesture" and s["actions"] == len(tried))
                ),
                "a try or the hand-back",
            )
            if s["phase"] == "waiting_for_gesture":
                break
            tried.append(s["action"] or s["last_action"])
            live.receive({"type": "thumb", "value": "down"})
            logged = len(tried)
            driver.wait(lambda s, n=logged: s["actions"] >= n, "the try logged")
        assert "Robin stopped trying (6 actions since your last gesture)" in s["notice"], s
    finally:
        live.stop("ended")
    assert len(tried) == 6 and len(set(tried[:5])) == 5, tried
    watchdog = [e for e in read_jsonl(live.out_dir / "events.jsonl") if e["event"] == "watchdog"]
    assert len(watchdog) == 1 and watchdog[0]["reason"].startswith("6 actions"), watchdog


def test_a_thumb_is_taken_from_the_moment_the_page_shows_the_action(tmp_path: Path) -> None:
    """The status shows a robot action as the view hears of it (``decided``); from then on a
    thumb is accepted. CI once saw the test participant's thumb down refused ("There is no
    robot action to judge now") because the view showed the action before the person watched."""
    live, driver = session(tmp_path, seed=1)
    judging_when_shown: list[bool] = []
    shown = live.view.decided

    def decided(record: Any) -> None:  # in the physics thread, as the page learns the action
        participant = live._participant
        judging_when_shown.append(participant is not None and participant.judging)
        shown(record)

    live.view.decided = decided  # type: ignore[method-assign]
    try:
        driver.my_turn()
        driver.point_at_leg(0)
        driver.wait(lambda s: s["action"] is not None, "Robin's first try")
        live.receive({"type": "thumb", "value": "down"})
        driver.wait(lambda s: s["actions"] >= 1 and s["rejected"] >= 1, "the try refused")
    finally:
        live.stop()
    assert judging_when_shown and all(judging_when_shown), judging_when_shown
