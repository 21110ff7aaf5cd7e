"""The live page's take-back, "That was wrong" (issue 38, item 3): real sessions (physics,
the learner, the files), the input sent as the page sends it.

Seed 0's first try on a click at the red leg is a close (on nothing): the participant lets it
stand with a thumb up, then takes it back. The learner's count for that close is withdrawn
(without the take-back the loop would only re-ground the hand, and the count would stay), the
guide asks for the point again, and ``inputs.jsonl``, ``events.jsonl``, the step log and the
summary say so. Outside its window, before anything stood and while Robin acts, the take-back
is refused with a plain message.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from live_driver import Driver, read_jsonl
from live_driver import start_session as _start

from pil.table import state_id
from pil.types import Action, State
from robin_sim.live.inputs import LiveInputError
from robin_sim.live.session import LiveSession
from robin_sim.live.take_back import TAKE_BACK_WINDOW_S

pytestmark = pytest.mark.slow
TAKE_BACK = {"type": "take_back"}
POINT_AT_START = State.from_key("pointing|open|free")


def close_count(live: LiveSession) -> int:
    row = live.view.table.row(state_id(POINT_AT_START))
    return 0 if row is None else row[list(Action).index(Action.CLOSE)]


def approve_the_first_try(live: LiveSession, driver: Driver) -> dict[str, Any]:
    """Point at the red leg and give the first try (seed 0: a close) a thumb up; the turn."""
    driver.my_turn()
    driver.point_at_leg(0)
    shown = driver.wait(lambda s: s["phase"] == "waiting_for_thumb", "the close's window")
    assert shown["last_action"] == "close", shown
    live.receive({"type": "thumb", "value": "up"})
    driver.wait(lambda s: s["actions"] >= 1, "the close logged")
    return driver.my_turn()


def test_that_was_wrong_takes_back_the_approved_close(tmp_path: Path) -> None:
    live, driver = session(tmp_path)
    try:
        turn = approve_the_first_try(live, driver)
        assert turn["take_back_left_s"] is not None and turn["take_back_left_s"] > 0, turn
        assert close_count(live) == 1
        live.receive(TAKE_BACK)
        back = driver.wait(lambda s: "took back" in s["notice"], "the take-back")
        assert back["notice"].startswith("Robin took back its 'close'"), back["notice"]
        assert close_count(live) == 0  # the learner's count withdrawn
        assert back["guide"]["step"] == 0, back["guide"]  # the point is asked for again
        assert back["guide"]["instruction"].startswith("Point at the red leg")
        assert back["take_back_left_s"] is None  # once
        with pytest.raises(LiveInputError, match="no action of Robin's to take back"):
            live.receive(TAKE_BACK)
        gestures = back["gestures"]
        driver.point_at_leg(0)  # Robin acts on the point again
        driver.wait(lambda s: s["gestures"] > gestures and s["actions"] >= 2, "a new try")
        tail = list(live.log_tail)
    finally:
        summary = live.stop("ended")
    folder = live.out_dir
    inputs = [e for e in read_jsonl(folder / "inputs.jsonl") if e["raw"] == TAKE_BACK]
    assert [e["accepted"] for e in inputs] == [True, False], inputs
    events = [e for e in read_jsonl(folder / "events.jsonl") if e["event"] == "take_back"]
    assert len(events) == 1 and events[0]["done"] is True, events
    assert (events[0]["t"], events[0]["action"]) == (1, "close")
    assert events[0]["loop"].startswith("close taken back (its approval in pointing|open|free")
    steps = read_jsonl(folder / "log.jsonl")
    assert steps[0]["action"] == "close" and steps[0]["feedback"] == "ok"
    assert steps[1]["reason"].startswith("taken back: close taken back"), steps[1]["reason"]
    assert steps[1]["state"] == "pointing|open|free"  # the state before the close, again
    assert [s["t"] for s in steps] == list(range(1, len(steps) + 1))  # none lost or doubled
    assert tail[0]["t"] == 1 and tail[0]["taken_back"] is True  # the experimenter's view
    assert summary["live"]["taken_back"] == 1
    assert summary["live"]["take_back_window_s"] == TAKE_BACK_WINDOW_S


def test_a_take_back_is_refused_outside_its_window(tmp_path: Path) -> None:
    live, driver = session(tmp_path)
    try:
        driver.my_turn()
        with pytest.raises(LiveInputError, match="no action of Robin's to take back"):
            live.receive(TAKE_BACK)  # nothing stood yet
        driver.point_at_leg(0)
        driver.wait(lambda s: s["action"] is not None, "Robin acting")
        with pytest.raises(LiveInputError, match="Robin is acting now"):
            live.receive(TAKE_BACK)
        driver.wait(lambda s: s["phase"] == "waiting_for_thumb", "the close's window")
        live.receive({"type": "thumb", "value": "up"})
        driver.wait(lambda s: s["actions"] >= 1, "the close logged")
        driver.my_turn()
        body = live.body
        assert body is not None
        stood = body.world.time
        driver.wait(
            lambda s: body.world.time > stood + TAKE_BACK_WINDOW_S + 0.5, "the window to pass"
        )
        assert live.status()["take_back_left_s"] is None
        with pytest.raises(LiveInputError, match="Too late to take back Robin's 'close'"):
            live.receive(TAKE_BACK)
        assert close_count(live) == 1  # nothing withdrawn
    finally:
        live.stop("ended")
    inputs = [e for e in read_jsonl(live.out_dir / "inputs.jsonl") if e["raw"] == TAKE_BACK]
    assert [e["accepted"] for e in inputs] == [False, False, False], inputs
    assert "works for 10 s after an action stands" in inputs[-1]["error"]
    events = read_jsonl(live.out_dir / "events.jsonl")
    assert not [e for e in events if e["event"] == "take_back"], events


def session(tmp_path: Path) -> tuple[LiveSession, Driver]:
    return _start(tmp_path, seed=0, feedback_window=1.0)
