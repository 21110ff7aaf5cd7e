"""``--webcam`` sessions with real physics, fed the page's hand messages from the test thread.

The hands are made up (:func:`hand_data.synthetic_hand`), so the test knows each reading's
gesture; what the browser's tracker reads from real footage is tested in
``tests/browser/test_browser_webcam.py`` and ``tests/test_webcam_accuracy.py``.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pytest
from hand_data import message, synthetic_hand
from live_driver import Driver

from robin_sim.live.config import LiveConfig
from robin_sim.live.hands.reader import CALIBRATION_GAP_S, CALIBRATION_ORDER, CURSOR_MARGIN, DWELL_S
from robin_sim.live.inputs import LiveInputError
from robin_sim.live.session import LiveSession
from robin_sim.live.webcam import MAX_READINGS_PER_S

pytestmark = pytest.mark.slow
WIDTH, HEIGHT = 640, 480
SHAPES = {
    "grasp": ((False,) * 4, "in"),
    "release": ((True,) * 4, "in"),
    "thumb_up": ((False,) * 4, "up"),
    "thumb_down": ((False,) * 4, "down"),
    "pointing": ((True, False, False, False), "in"),
}


def shown(gesture: str, at: tuple[float, float] = (0.5, 0.7)) -> dict:
    """The page's message for a made-up hand making ``gesture`` (camera aspect 1)."""
    if gesture == "give_me":  # an open hand, fingers down: held out
        points = synthetic_hand((True,) * 4, "in", at)
        points[:, 1] = 2 * points[0, 1] - points[:, 1]
    else:
        points = synthetic_hand(*SHAPES[gesture], at)
    return message(points, aspect=1.0)


def pointing_at(x: float, y: float) -> dict:
    """A pointing hand whose index fingertip puts the page's cursor on frame pixel (x, y)."""
    span = 1 - 2 * CURSOR_MARGIN
    tip_x = 1 - (CURSOR_MARGIN + x / WIDTH * span)  # the self-view is mirrored
    tip_y = CURSOR_MARGIN + y / HEIGHT * span
    offset = synthetic_hand(*SHAPES["pointing"], (0.0, 0.0))[8, :2]
    return shown("pointing", (tip_x - offset[0], tip_y - offset[1]))


def read_lines(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def test_calibrate_then_point_by_dwell_and_approve_by_thumb(tmp_path: Path) -> None:
    config = LiveConfig(
        scenario="one_handover",
        out_root=tmp_path,
        session="w1",
        speed=3.0,
        fps=10,
        feedback_window=30.0,
        webcam=True,
        video=False,
    )
    session = LiveSession(config)
    driver = Driver(session)
    session.start()
    try:
        driver.my_turn()
        assert session.status()["webcam"]["calibration"]["asking"] == "give_me"
        for gesture in CALIBRATION_ORDER:  # the page asks for each gesture once
            asked = session.status()["webcam"]["calibration"]["asking"]
            assert asked == gesture
            session.receive(shown(gesture))
            session.receive(shown(gesture))
            time.sleep(CALIBRATION_GAP_S + 0.05)
        calibration = session.status()["webcam"]["calibration"]
        assert calibration["calibrated"] and not calibration["calibrating"]
        assert calibration["done"] == list(CALIBRATION_ORDER)
        assert session.status()["phase"] == "waiting_for_gesture"  # nothing acted meanwhile

        x, y = driver.pixel_of_leg(0)
        for _ in range(40):  # the fingertip held still over leg 1 until the dwell selects it
            session.receive(pointing_at(x, y))
            if session.status()["phase"] != "waiting_for_gesture":
                break
            time.sleep(DWELL_S / 4)
        moving = driver.wait(lambda s: s["action"] is not None, "the robot to act")
        assert session.status()["clicked"]["kind"] == "leg"
        assert session.status()["clicked"]["number"] == 1
        for _ in range(40):  # a thumb up, held, until it is taken as the verdict
            session.receive(shown("thumb_up"))
            if session.status()["actions"] >= 1:
                break
            time.sleep(0.2)
        driver.wait(lambda s: s["actions"] >= 1, "the step to be logged")
        with pytest.raises(LiveInputError, match=f"more than {MAX_READINGS_PER_S} readings"):
            for _ in range(MAX_READINGS_PER_S + 1):
                session.receive(message(None))
    finally:
        summary = session.stop("ended")
    log = read_lines(session.out_dir / "log.jsonl")
    assert log[0]["true_gesture"] == "pointing" and log[0]["action"] == moving["action"]
    assert log[0]["feedback"] == "ok" and log[0]["target"] == {"kind": "leg", "index": 0}
    lines = [e for e in read_lines(session.out_dir / "inputs.jsonl") if e["raw"]["type"] == "hand"]
    acted = [e["reading"]["acted"] for e in lines if e.get("reading", {}).get("acted")]
    assert acted == [
        *(f"calibration {g}" for g in CALIBRATION_ORDER),
        "gesture pointing",
        "thumb up",
    ]
    refused = [e for e in lines if not e["accepted"]]
    assert len(refused) == 1 and "readings a second" in refused[0]["error"]
    pointed = next(e["reading"] for e in lines if e["reading"]["acted"] == "gesture pointing")
    assert pointed["source"] == "appearance" and pointed["confidence"] >= 0.5
    assert np.hypot(pointed["cursor"][0] - x, pointed["cursor"][1] - y) < 3.0
    vision = summary["vision"]
    assert vision["calibrated"] and vision["calibration"] == list(CALIBRATION_ORDER)
    assert vision["decisions"] == {"pointing": 1, "thumb_up": 1}
    assert vision["confirmed"] == 1 and vision["detection_rate"] == 1.0
    assert vision["examples"] == len(CALIBRATION_ORDER) + 1  # the approved reading taught it
    assert vision["confusion"] == {"pointing": {"pointing": 1}}
    assert vision["readings"] == summary["live"]["hand_readings"] == len(lines) - 1
    assert vision["latency_ms"]["median"] > 0


def test_a_session_without_webcam_refuses_hand_messages(tmp_path: Path) -> None:
    session = LiveSession(LiveConfig(out_root=tmp_path, session="n1"))
    for raw in (shown("grasp"), {"type": "calibration", "action": "skip"}):
        with pytest.raises(LiveInputError, match="start it with robin-pil live --webcam"):
            session.receive(raw)
    with pytest.raises(LiveInputError, match="valid choices: 'skip', 'restart'"):
        session.receive({"type": "calibration", "action": "again"})
