"""``live --webcam`` in Debian's headless chromium with a fake camera playing real footage.

Each test launches chromium with its own camera clip (``tests/data/hands``, Apache-2.0: a
thumb up, the same flipped upside down, a palm held out), runs a real session (physics, the
learner) and waits on what the page and the server record, never on time: the hand tracker
manages about one reading a second (fewer under load) in headless software rendering. Every
request the page makes is checked to go to the loopback server: nothing leaves the machine.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import pytest
from page_driver import click_frame_pixel, leg_pixels, read_jsonl, wait_status
from webcam_rig import HANDS, camera_browser, readings, write_y4m

from robin_sim.live.hands.reader import THRESHOLD

# slow: the tracker reads about one frame a second on 2 busy cores; each test waits on readings
# (bounded), so the whole test may take many minutes under load
pytestmark = [pytest.mark.slow, pytest.mark.timeout(2400)]
READ_TIMEOUT_S = 900  # a bound, not a measure: a busy 2-core machine reads a frame in 1-33 s
SCENARIO = "one_handover"


def session_options() -> dict[str, Any]:
    # a quarter of real time and the longest feedback window (60 s simulated: 240 s of wall
    # time) so that the thumb is read however slow the tracker is (issue 39: under a load of
    # 5-13 it read once in 33 s, and at real time the window closed before a reading);
    # seed 3: the learner's first try for a pointing at a leg is `object`, a move with a
    # feedback window after it (seed 0 tries `close`, which closes on nothing and ends at once
    # with no window, so silence approves it and the next pointings get `close` again)
    return {
        "seed": 3,
        "scenario": SCENARIO,
        "webcam": True,
        "calibrate": False,
        "speed": 0.25,
        "feedback_window": 60.0,
        "video": False,
    }


def open_camera_page(browser: Any, served: Any) -> tuple[Any, list[str]]:
    page = browser.new_page(viewport={"width": 1100, "height": 1000})
    page.on("dialog", lambda dialog: dialog.accept())
    requests: list[str] = []
    page.on("request", lambda request: requests.append(request.url))
    page.goto(served.url("/"))
    return page, requests


def wait_reading(page: Any, condition: str) -> list[dict[str, Any]]:
    """Wait until a reading the server answered satisfies ``condition`` (JS, on ``r``)."""
    page.wait_for_function(
        f"() => (window.robinLive.webcam?.replies || []).some((r) => {condition})",
        timeout=READ_TIMEOUT_S * 1000,
        polling=200,
    )
    return readings(page)


def assert_loopback_only(requests: list[str], served: Any) -> None:
    own = (f"http://127.0.0.1:{served.port}/", f"ws://127.0.0.1:{served.port}/")
    assert requests, "the page made no request at all"
    foreign = [url for url in requests if not url.startswith(own)]
    assert not foreign, f"requests left the machine: {foreign}"
    assert any("/static/vendor/hand_landmark_full.tflite" in url for url in requests)


def hand_lines(folder: Path) -> list[dict[str, Any]]:
    return [e for e in read_jsonl(folder / "inputs.jsonl") if e["raw"].get("type") == "hand"]


def end_session(page: Any, served: Any) -> dict[str, Any]:
    page.evaluate("() => window.robinLive.send({type: 'end'})")
    served.wait_over(120)
    return json.loads((served.conductor.session.out_dir / "summary.json").read_text())


def wait_log(folder: Path, feedback: str) -> list[dict[str, Any]]:
    """Wait until ``log.jsonl`` has a step with ``feedback`` (the learner received it)."""
    deadline = time.monotonic() + READ_TIMEOUT_S
    while time.monotonic() < deadline:
        path = folder / "log.jsonl"
        log = read_jsonl(path) if path.exists() else []
        if any(entry["feedback"] == feedback for entry in log):
            return log
        time.sleep(0.5)
    raise AssertionError(f"no step with feedback {feedback!r} logged in {READ_TIMEOUT_S} s")


def judged_by_camera(tmp_path: Path, live_server: Any, vflip: bool) -> tuple[Any, ...]:
    """Point at a leg with a click, again whenever it is the participant's turn, until the
    camera's thumb has judged one of the robot's actions (an action that ends at once, such as
    closing on nothing, leaves no time to judge it; the next one does)."""
    y4m = write_y4m(HANDS / "thumb_up.mp4", tmp_path / "thumb.y4m", vflip=vflip)
    served = live_server(**session_options())
    thumb = "down" if vflip else "up"
    judged = f"(window.robinLive.webcam?.replies || []).some((r) => r.acted === 'thumb {thumb}')"
    with camera_browser(y4m) as browser:
        page, requests = open_camera_page(browser, served)
        for _ in range(8):
            wait_status(page, f"s.phase === 'waiting_for_gesture' || {judged}", timeout_s=180)
            if page.evaluate(f"() => {judged}"):
                break
            done = page.evaluate("() => window.robinLive.status.actions")
            click_frame_pixel(page, *leg_pixels(SCENARIO)[0])
            wait_status(page, f"s.actions > {done} || {judged}", timeout_s=READ_TIMEOUT_S)
        wait_reading(page, f"r.acted === 'thumb {thumb}'")
        folder = served.conductor.session.out_dir
        log = wait_log(folder, "ok" if thumb == "up" else "not ok")
        summary = end_session(page, served)
        page.close()
    assert_loopback_only(requests, served)
    return served, summary, log


def test_a_thumb_up_on_the_camera_approves_the_move(tmp_path, live_server) -> None:
    served, summary, log = judged_by_camera(tmp_path, live_server, vflip=False)
    folder = served.conductor.session.out_dir
    judged = [e for e in log if e["feedback"] == "ok"]
    assert judged[0]["true_gesture"] == "pointing" and judged[0]["feedback_read"] == "ok"
    assert not judged[0]["interrupted"]
    assert not any(e["feedback"] == "not ok" for e in log)
    acted = [e for e in hand_lines(folder) if e["reading"]["acted"] == "thumb up"]
    assert len(acted) == len(judged) == 1, (acted, log)
    reading = acted[0]["reading"]
    assert reading["label"] == "thumb_up" and reading["confidence"] >= THRESHOLD
    assert summary["vision"]["source"] == "webcam"
    assert summary["vision"]["decisions"].get("thumb_up") == 1
    assert summary["vision"]["hand_found"] >= 2


def test_a_thumb_down_on_the_camera_stops_the_move(tmp_path, live_server) -> None:
    served, summary, log = judged_by_camera(tmp_path, live_server, vflip=True)
    folder = served.conductor.session.out_dir
    judged = [e for e in log if e["feedback"] == "not ok"]
    assert judged[0]["feedback_read"] == "not ok" and judged[0]["true_gesture"] == "pointing"
    acted = [e for e in hand_lines(folder) if e["reading"]["acted"] == "thumb down"]
    assert len(acted) == len(judged) == 1, (acted, log)
    assert acted[0]["reading"]["label"] == "thumb_down"
    assert acted[0]["reading"]["confidence"] >= THRESHOLD
    assert summary["rejected"] == 1
    assert summary["vision"]["decisions"].get("thumb_down") == 1


def test_a_palm_on_the_camera_is_give_me_and_the_learner_gets_it(tmp_path, live_server) -> None:
    y4m = write_y4m(HANDS / "palm.mp4", tmp_path / "palm.y4m")
    served = live_server(**session_options())
    with camera_browser(y4m) as browser:
        page, requests = open_camera_page(browser, served)
        wait_status(page, "s.phase === 'waiting_for_gesture'", timeout_s=180)
        found = wait_reading(page, "r.acted === 'gesture give_me'")
        # Robin acts on it: the move itself, its feedback window, or (an action that ends at
        # once, seen between two status messages) the step already logged by silence
        acting = "(s.phase === 'robot_acting' && !!s.action) || s.phase === 'waiting_for_thumb'"
        seen = wait_status(page, f"{acting} || s.actions >= 1", timeout_s=READ_TIMEOUT_S)
        if seen["actions"] < 1:
            page.keyboard.press("ArrowUp")  # the participant approves whatever Robin does
        wait_status(page, "s.actions >= 1", timeout_s=READ_TIMEOUT_S)
        assert page.locator("#webcam").is_visible()
        assert "give me" in page.locator("#reading").inner_text() or found
        summary = end_session(page, served)
        page.close()
    assert_loopback_only(requests, served)
    folder = served.conductor.session.out_dir
    log = read_jsonl(folder / "log.jsonl")
    assert log[0]["true_gesture"] == "give me" and log[0]["detected_gesture"] == "give me"
    assert log[0]["state"].startswith("give me|"), log[0]
    lines = hand_lines(folder)
    acted = [e for e in lines if e["reading"]["acted"] == "gesture give_me"]
    assert len(acted) == 1 and acted[0]["accepted"]
    assert acted[0]["reading"]["confidence"] >= THRESHOLD
    assert all(e["reading"]["confidence"] >= 0 for e in lines)
    vision = summary["vision"]
    assert vision["decisions"] == {"give_me": 1}
    assert vision["confirmed"] == 1 and vision["examples"] == 1  # the approval taught it
    assert vision["readings"] == len(lines) == summary["live"]["hand_readings"]


def test_no_camera_falls_back_to_buttons_and_keys(live_server) -> None:
    served = live_server(**{**session_options(), "speed": 3.0})
    with camera_browser(None) as browser:
        page, requests = open_camera_page(browser, served)
        page.wait_for_function(
            "() => window.robinLive.webcam && window.robinLive.webcam.state === 'fallback'",
            timeout=120_000,
        )
        shown = page.locator("#camera-state").inner_text()
        assert "Use the buttons and keys instead" in shown, shown
        wait_status(page, "s.phase === 'waiting_for_gesture'", timeout_s=180)
        page.keyboard.press("g")  # give me by key
        wait_status(page, "s.gestures >= 1 || s.phase !== 'waiting_for_gesture'", timeout_s=60)
        page.close()
    own = f"http://127.0.0.1:{served.port}/"
    assert all(url.startswith((own, own.replace("http", "ws"))) for url in requests), requests
    inputs = read_jsonl(served.conductor.session.out_dir / "inputs.jsonl")
    assert any(e["raw"] == {"type": "gesture", "gesture": "give_me"} for e in inputs)
