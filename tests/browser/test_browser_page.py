"""The live page in a real headless chromium against a real server, engine and physics.

Every input goes through the page: real key presses and clicks on the displayed canvas (shown
scaled, not at 640x480, so the page's pixel mapping is exercised). Sessions run at ``SPEED``
(sim seconds per wall second) so the suite stays short; the pacing is the engine's and keeps up
on the 2-core CI machine at that speed (bench/bench_live.py measures 1x).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from page_driver import (
    TYPE_A,
    canvas_pixels,
    click_frame_pixel,
    leg_pixels,
    play_steps,
    read_jsonl,
    status,
    wait_status,
)

from robin_sim.model.robot_spec import POINT_OFFSET

pytestmark = pytest.mark.slow
SPEED = 3.0
VIEWPORT = {"width": 1100, "height": 820}  # the canvas is shown at about 700x525, not 640x480
HAND_TOLERANCE = 0.03  # m: the hand's xy from the leg's xy + the pointing offset


def open_page(browser, served, **options):
    page = browser.new_page(viewport=VIEWPORT, **options)
    page.on("dialog", lambda dialog: dialog.accept())  # the End button asks to confirm
    page.goto(served.url("/"))
    return page


def hand_position(served) -> np.ndarray:
    """The person's hand in physics (the running session's simulated body)."""
    body = served.conductor.session.body
    return np.asarray(body.hand.pose().translation(), float)


def test_frames_arrive_and_a_click_points_the_hand_at_the_leg(browser, live_server) -> None:
    served = live_server(scenario="one_handover", speed=SPEED, video=False)
    page = open_page(browser, served)
    page.wait_for_function("() => window.robinLive.drawn >= 15", timeout=60_000)
    assert page.evaluate("() => window.robinLive.role") == "control"
    box = page.locator("#scene").bounding_box()
    assert abs(box["width"] - 640) > 20, "the canvas should be shown scaled"
    assert canvas_pixels(page).shape == (480, 640, 3)
    pixels = canvas_pixels(page).astype(float)
    grey = pixels.mean(axis=2)
    assert grey.std() > 15.0, f"the frame looks blank (std {grey.std():.1f})"
    assert len(np.unique(pixels.reshape(-1, 3), axis=0)) > 500  # a rendered scene, not a fill
    assert pixels[..., 0].mean() != pytest.approx(pixels[..., 2].mean(), abs=0.5)  # colour

    wait_status(page, "s.phase === 'waiting_for_gesture'")
    legs = leg_pixels("one_handover")
    x, y = legs[0]
    click_frame_pixel(page, x, y)
    leg = served.conductor.session.body.world.legs.position(0)
    goal = np.asarray(leg, float) + POINT_OFFSET
    page.wait_for_function(
        "() => window.robinLive.status.phase !== 'waiting_for_gesture'", timeout=20_000
    )
    for _ in range(200):  # the hand moves over about a second of sim time
        hand = hand_position(served)
        if np.linalg.norm(hand[:2] - goal[:2]) <= HAND_TOLERANCE:
            break
        page.wait_for_timeout(50)
    assert np.linalg.norm(hand[:2] - goal[:2]) <= HAND_TOLERANCE, (hand, goal)
    inputs = read_jsonl(served.conductor.session.out_dir / "inputs.jsonl")
    points = [entry for entry in inputs if entry["raw"].get("type") == "point"]
    assert points and points[0]["accepted"], inputs
    assert points[0]["raw"]["x"] == pytest.approx(x, abs=1.0)
    assert points[0]["raw"]["y"] == pytest.approx(y, abs=1.0)
    page.close()


def test_keys_perform_a_type_a_handover_with_thumbs(browser, live_server) -> None:
    served = live_server(scenario="one_handover", speed=SPEED, video=False)
    page = open_page(browser, served)
    legs = leg_pixels("one_handover")
    step, downs = play_steps(page, TYPE_A, legs[0])
    final = wait_status(page, "s.phase === 'done'")
    assert final["status"] == "finished", final
    assert step == len(TYPE_A)
    served.wait_over(60)

    out = served.conductor.results[-1]
    folder = served.conductor.session.out_dir
    summary = json.loads((folder / "summary.json").read_text())
    log = read_jsonl(folder / "log.jsonl")
    assert summary["status"] == "finished"
    assert summary["legs_delivered"] == summary["legs_total"] == 1
    approved = [e["action"] for e in log if e["action"] and e["feedback"] != "not ok"]
    assert approved == [meant for _, meant in TYPE_A]
    assert sum(e["feedback"] == "not ok" for e in log) == downs == summary["rejected"]
    assert summary["actions"] == len([e for e in log if e["action"]]) == len(TYPE_A) + downs
    assert summary["gestures"] == max(e["gesture_count"] for e in log)
    assert [e["true_gesture"] for e in log if e["feedback"] != "not ok"] == [
        "pointing",
        "grasp",
        "give me",
        "release",
    ]
    assert log[-1]["delivered"] and log[-1]["legs_delivered"] == 1
    assert summary["live"]["participant"] == "P01" and summary["live"]["inputs"] >= 4 + downs
    assert out["status"] == "finished"
    page.close()


def test_thumb_down_key_interrupts_a_move(browser, live_server) -> None:
    served = live_server(scenario="one_handover", speed=SPEED, video=False)
    page = open_page(browser, served)
    wait_status(page, "s.phase === 'waiting_for_gesture'")
    click_frame_pixel(page, *leg_pixels("one_handover")[0])
    moving = wait_status(page, "s.phase === 'robot_acting' && !!s.action")
    page.keyboard.press("ArrowDown")
    wait_status(page, "s.rejected >= 1", timeout_s=60)
    page.keyboard.press("e")  # End (the confirm dialog is accepted)
    assert wait_status(page, "s.phase === 'done'")["status"] == "ended"
    served.wait_over(60)
    log = read_jsonl(served.conductor.session.out_dir / "log.jsonl")
    first = log[0]
    assert first["action"] == moving["action"]
    assert first["interrupted"] is True and first["feedback"] == "not ok", first
    summary = json.loads((served.conductor.session.out_dir / "summary.json").read_text())
    assert summary["status"] == "ended"
    assert summary["interrupted_actions"] >= 1
    page.close()


def test_second_tab_watches_read_only(browser, live_server) -> None:
    served = live_server(scenario="one_handover", speed=SPEED, video=False)
    control = open_page(browser, served)
    control.wait_for_function("() => window.robinLive.drawn >= 3", timeout=60_000)
    watcher = open_page(browser, served)
    watcher.wait_for_function("() => window.robinLive.drawn >= 3", timeout=30_000)
    assert watcher.evaluate("() => window.robinLive.role") == "watch"
    assert watcher.locator("button[data-send='up']").is_disabled()
    wait_status(watcher, "s.phase === 'waiting_for_gesture'")
    before = status(control)["gestures"]
    watcher.evaluate("() => window.robinLive.send({type: 'gesture', gesture: 'give_me'})")
    watcher.wait_for_function("() => window.robinLive.errors.length >= 1", timeout=10_000)
    assert "read-only" in watcher.evaluate("() => window.robinLive.errors[0]")
    watcher.wait_for_timeout(500)
    assert status(control)["phase"] == "waiting_for_gesture"
    assert status(control)["gestures"] == before
    inputs = read_jsonl(served.conductor.session.out_dir / "inputs.jsonl")
    assert not [e for e in inputs if e["raw"].get("gesture") == "give_me"]
    control.close()  # the controlling tab, not back within the grace: saved closed, server stops
    told = wait_status(watcher, "s.phase === 'done'", timeout_s=60)  # and the watcher is told
    assert told["status"] == "closed"
    assert "closed" in watcher.locator("#screen-title").inner_text()
    watcher.close()
    assert served.wait_over(60) == "closed"
    summary = json.loads((served.conductor.session.out_dir / "summary.json").read_text())
    assert summary["status"] == "closed"


PROTOCOL = """\
name: two_short_blocks
scenario: one_handover
conditions:
  - system: pil
    label: Robot A
  - system: proactive
    label: Robot B
order: counterbalanced
blocks:
  - types: [A]
instructions: "Block {block} of {blocks}: you work with {label}."
"""


def test_protocol_blocks_behind_instruction_screens(browser, tmp_path) -> None:
    from conftest import start_server

    from robin_sim.cli.live import session_configs
    from robin_sim.cli.main import build_parser

    path = tmp_path / "protocol.yaml"
    path.write_text(PROTOCOL)
    args = build_parser("live").parse_args(
        [
            "live",
            "--protocol",
            str(path),
            "--participant",
            "P02",
            "--out",
            str(tmp_path / "o"),
            "--speed",
            str(SPEED),
            "--no-video",
        ]
    )
    served = start_server(session_configs(args))
    try:
        page = open_page(browser, served)
        first = wait_status(page, "s.phase === 'instructions'")
        assert first["block_number"] == 1 and first["blocks"] == 2
        assert page.locator("#screen-text").inner_text() == "Block 1 of 2: you work with Robot B."
        assert page.locator("#start").is_visible()
        page.locator("#start").click()  # P02 (even): proactive first
        running = wait_status(page, "s.phase === 'waiting_for_gesture'")
        assert running["system"] == "proactive" and running["block"] == 0
        assert not page.locator("#screen").is_visible()
        page.wait_for_function("() => window.robinLive.lastSeq >= 5")  # block 1's frames
        page.keyboard.press("e")  # end block 1
        wait_status(page, "s.phase === 'instructions' && s.block_number === 2")
        assert "Robot A" in page.locator("#screen-text").inner_text()
        page.keyboard.press("Enter")  # Start by key
        assert wait_status(page, "s.phase === 'waiting_for_gesture'")["system"] == "pil"
        # block 2's own frames are drawn (numbered from 1 again: they were dropped as older)
        page.wait_for_function(
            "() => window.robinLive.frameBlock === 2 && window.robinLive.lastSeq >= 1"
        )
        page.close()
        assert served.wait_over(60) == "closed"
    finally:
        served.server.stop_soon()
        served.thread.join(60)
    first_block = tmp_path / "o" / "P02" / "block1-proactive" / "summary.json"
    second_block = tmp_path / "o" / "P02" / "block2-pil" / "summary.json"
    summaries = [json.loads(p.read_text()) for p in (first_block, second_block)]
    assert [s["status"] for s in summaries] == ["ended", "closed"]
    assert [s["live"]["block"] for s in summaries] == [0, 1]
    assert [s["live"]["condition"] for s in summaries] == ["proactive", "pil"]
    assert summaries[0]["live"]["protocol"] == str(path)


def test_that_was_wrong_by_key_and_button(browser, live_server) -> None:
    """The take-back's key (W, from the page's constants) takes back the action that stood;
    its button then, with nothing left to take back, is refused with a plain message."""
    served = live_server(scenario="one_handover", speed=SPEED, video=False, feedback_window=1.0)
    page = open_page(browser, served)
    wait_status(page, "s.phase === 'waiting_for_gesture'")
    button = page.locator("#take-back")
    assert (
        button.inner_text().startswith("That was wrong")
        and button.locator("kbd").inner_text() == "W"
    )
    click_frame_pixel(page, *leg_pixels("one_handover")[0])
    wait_status(page, "s.phase === 'waiting_for_thumb' || !!s.action")
    page.keyboard.press("ArrowUp")  # the first try stands, whatever it is
    wait_status(page, "s.phase === 'waiting_for_gesture' && s.take_back_left_s > 0")
    page.keyboard.press("w")
    taken = wait_status(page, "s.notice.startsWith('Robin took back its')")
    assert taken["guide"]["step"] == 0, taken["guide"]  # the point is asked for again
    button.click()
    page.wait_for_function(
        "() => document.getElementById('error').textContent.includes('no action of Robin')"
    )
    folder = served.conductor.session.out_dir
    page.keyboard.press("e")  # End (the confirm dialog is accepted)
    wait_status(page, "s.phase === 'done'")
    served.wait_over(60)
    inputs = [e for e in read_jsonl(folder / "inputs.jsonl") if e["raw"] == {"type": "take_back"}]
    assert [e["accepted"] for e in inputs] == [True, False], inputs
    events = [e for e in read_jsonl(folder / "events.jsonl") if e["event"] == "take_back"]
    assert len(events) == 1 and events[0]["done"] is True, events
    page.close()
