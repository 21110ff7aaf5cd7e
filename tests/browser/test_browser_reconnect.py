"""A page whose connection dies mid-step comes back by itself, and the session goes on.

Real server, engine, physics and headless chromium. The test kills the controlling page's TCP
connection from the server's side while Robin acts (as a network failure, or a heartbeat the
page could not answer, would: the page sees code 1006); the page reconnects on its own, takes
its place again, and the participant finishes the handover. No step is lost or doubled: the
log's steps are numbered 1, 2, 3, ... once each; the session held while the page was away, and
``events.jsonl`` records both moments.
"""

from __future__ import annotations

import json

import pytest
from page_driver import TYPE_A, click_frame_pixel, leg_pixels, play_steps, read_jsonl, wait_status

pytestmark = pytest.mark.slow
SPEED = 3.0


def test_a_killed_connection_comes_back_and_no_step_is_lost_or_doubled(
    browser, live_server
) -> None:
    served = live_server(scenario="one_handover", speed=SPEED, video=False, reconnect_grace_s=60)
    page = browser.new_page(viewport={"width": 1100, "height": 900})
    page.on("dialog", lambda dialog: dialog.accept())
    page.goto(served.url())
    leg = leg_pixels("one_handover")[0]
    wait_status(page, "s.phase === 'waiting_for_gesture'")
    click_frame_pixel(page, *leg)
    moving = wait_status(page, "s.phase === 'robot_acting' && !!s.action")  # mid-step
    server = served.server
    control = next(tab for tab in server.tabs if tab.role == "control")
    assert server._loop is not None and control.transport is not None
    server._loop.call_soon_threadsafe(control.transport.abort)  # the connection dies
    page.wait_for_function("() => !!window.robinLive.lastClose", timeout=20_000)
    assert page.evaluate("() => window.robinLive.lastClose.code") == 1006
    page.wait_for_function(
        "() => window.robinLive.connected && window.robinLive.reconnects >= 1", timeout=30_000
    )
    assert page.evaluate("() => window.robinLive.role") == "control"  # its place again
    back = wait_status(page, "s.participant_page && s.participant_page.connected")
    assert back["participant_page"]["returns"] == 1
    # the step it was in goes on: Robin's try is judged, the handover finished by the page
    approved, _ = play_steps(page, TYPE_A, leg)
    assert approved == len(TYPE_A)
    assert served.wait_over(90) == "finished"
    out = served.conductor.session.out_dir
    steps = read_jsonl(out / "log.jsonl")
    assert [s["t"] for s in steps] == list(range(1, len(steps) + 1))  # none lost, none twice
    assert [s["action"] for s in steps if s["feedback"] != "not ok"] == [a for _, a in TYPE_A]
    assert steps[0]["action"] == moving["action"]  # the try the connection died in: logged once
    events = read_jsonl(out / "events.jsonl")
    kinds = [e["event"] for e in events if e["event"] in ("disconnected", "reconnected")]
    assert kinds == ["disconnected", "reconnected"], kinds
    events = [e for e in events if e["event"] in kinds]
    assert events[0]["code"] == 1006
    held = events[1]["sim_time"] - events[0]["sim_time"]
    assert held < 0.5, f"the session ran on {held:.2f} s of sim time while the page was away"
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "finished" and summary["legs_delivered"] == 1
    assert summary["person_contacts"] == 0  # the quick live hand never met the robot
    page.close()
