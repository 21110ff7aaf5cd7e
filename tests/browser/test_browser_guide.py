"""The participant's page guides, keeps every approved step, and the experimenter's view.

Real server, engine, physics and headless chromium (tests/browser/conftest.py); every input
goes through the page as in test_browser_page.py.
"""

from __future__ import annotations

import json
import urllib.request
from urllib.error import HTTPError

import pytest
from page_driver import TYPE_A, click_frame_pixel, leg_pixels, play_steps, status, wait_status

pytestmark = pytest.mark.slow
SPEED = 3.0
VIEWPORT = {"width": 1100, "height": 900}


def open_page(browser, url: str):
    page = browser.new_page(viewport=VIEWPORT)
    page.on("dialog", lambda dialog: dialog.accept())  # End asks to confirm
    page.goto(url)
    return page


def test_end_during_the_carry_to_the_bin_keeps_the_open_and_counts_the_leg(
    browser, live_server
) -> None:
    served = live_server(handover_types=["A"], speed=SPEED, video=False, feedback_window=3.0)
    page = open_page(browser, served.url("/"))
    approved, _ = play_steps(page, TYPE_A, leg_pixels(None)[0], until=3)
    assert approved == 3
    # release: Robin's wrong tries are stopped; its open into the person's hand approved
    assert play_steps(page, TYPE_A[3:], leg_pixels(None)[0])[0] == 1
    # the counter moves when the leg reaches the hand, while the hand still carries it
    wait_status(page, "s.legs_delivered === 1", timeout_s=30)
    assert page.locator("#legs").inner_text() == "1 / 4"
    body = served.conductor.session.body
    assert body.leg_on_palm() is not None, "the carry to the bin should still be under way"
    page.keyboard.press("e")  # End, during the carry
    assert served.wait_over(60) == "ended"
    out = served.conductor.session.out_dir
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "ended" and summary["legs_delivered"] == 1, summary
    steps = [json.loads(line) for line in (out / "log.jsonl").read_text().splitlines()]
    assert [s["action"] for s in steps if s["feedback"] != "not ok"] == [a for _, a in TYPE_A]
    assert steps[-1]["delivered"] and steps[-1]["feedback"] == "ok"
    # a normal end is calm: no red "disconnected", no error
    page.wait_for_function("() => window.robinLive.closed !== null", timeout=20_000)
    assert page.locator("#role").inner_text() == "session finished"
    assert page.locator("#screen-title").inner_text() == "Session finished"
    assert page.locator("#error").inner_text() == ""
    page.close()


def test_a_type_d_handover_is_explained_in_plain_words(browser, live_server) -> None:
    served = live_server(handover_types=["D"], speed=SPEED, video=False)
    page = open_page(browser, served.url("/"))
    wait_status(page, "s.phase === 'waiting_for_gesture'")
    page.wait_for_function("() => document.getElementById('goal').textContent !== ''")
    goal = page.locator("#goal").inner_text()
    assert "Ask Robin to give you the red leg (leg 1)" in goal and "spot" in goal, goal
    assert page.locator("#instruction").inner_text() == (
        "Point at the red leg (leg 1): click it in the image."
    )
    items = page.locator("#checklist li")
    assert items.count() == 5 and "give-me" in items.nth(3).inner_text()
    assert "red" in page.locator("#legend").inner_text()
    assert not page.locator("#webcam").is_visible()  # no camera box without --webcam
    assert page.locator("#fps-in").count() == 0 and page.locator("#latency").count() == 0
    # a click beside everything: a plain error next to the image, which a valid click clears
    click_frame_pixel(page, 5, 5)
    page.wait_for_function("() => document.getElementById('error').textContent !== ''")
    error = page.locator("#error").inner_text()
    assert error.startswith("That click was on the floor") and "(of " not in error, error
    assert page.locator("#stage #error").count() == 1  # next to the image
    click_frame_pixel(page, *leg_pixels(None)[0])
    page.wait_for_function(
        "() => document.getElementById('error').textContent === ''", timeout=20_000
    )
    ring = page.locator("#target-ring")
    assert ring.is_visible() and ring.get_attribute("data-target") == "leg 1"
    # be the participant for this step (a wrong move gets thumb down) until it is approved
    approved, _ = play_steps(page, [("point", "object")], leg_pixels(None)[0], until=1)
    assert approved == 1
    page.wait_for_function(
        "() => document.querySelectorAll('#checklist li.done').length === 1", timeout=30_000
    )
    assert "grasp" in page.locator("#instruction").inner_text()
    page.close()


def test_the_experimenter_view_needs_its_token_and_controls_the_run(browser, live_server) -> None:
    served = live_server(handover_types=["A"], speed=SPEED, video=False)
    token = served.server.experimenter_token
    base = f"http://127.0.0.1:{served.port}/experimenter"
    for url in (base, f"{base}?token=wrong"):
        with pytest.raises(HTTPError) as refused:
            urllib.request.urlopen(url, timeout=10)
        assert refused.value.code == 403 and b"needs its own" in refused.value.read()
    page = open_page(browser, served.url("/"))  # the participant starts the session
    wait_status(page, "s.phase === 'waiting_for_gesture'")
    guest = open_page(browser, f"{base}?token=wrong")  # refused in the browser too
    assert "403" in guest.content() and guest.locator("#pause").count() == 0
    guest.close()
    boss = open_page(browser, f"{base}?token={token}")
    boss.wait_for_function(
        "() => window.robinLive.role === 'experimenter' && !!window.robinLive.experimenter.last"
    )
    assert boss.evaluate("() => window.robinLive.experimenter.last.pacing.frames") > 0
    assert status(boss)["guide"]["goal"].startswith("Ask Robin to give you")
    boss.click("#pause")
    wait_status(boss, "s.paused === true")
    boss.wait_for_timeout(500)  # the tick under way when the pause came ends
    paused_at = status(boss)["sim_time"]
    boss.wait_for_timeout(1500)
    assert status(boss)["sim_time"] == paused_at  # physics holds
    assert "Paused" in status(page)["message"]
    boss.click("#resume")
    wait_status(boss, f"s.paused === false && s.sim_time > {paused_at}")
    boss.wait_for_function("() => document.getElementById('reply').textContent === 'resume: done'")
    assert boss.locator("#reply").get_attribute("class") == "reply done"  # not styled an error
    assert boss.locator("#page-state").inner_text() == "connected"
    boss.fill("#note-text", "participant asked about the bin")
    boss.click("#note-save")
    boss.wait_for_function(
        "() => window.robinLive.experimenter.replies.map((r) => r.command)"
        ".join() === 'pause,resume,note'"
    )
    assert boss.locator("#note-saved").inner_text().startswith("note saved at 20")
    notes = (served.conductor.session.out_dir / "notes.jsonl").read_text().splitlines()
    assert json.loads(notes[0])["text"] == "participant asked about the bin"
    assert json.loads(notes[0])["utc"].startswith("20")
    # the participant's first step; the log grows on the experimenter's view
    approved, downs = play_steps(page, [("point", "object")], leg_pixels(None)[0], until=1)
    assert approved == 1
    boss.wait_for_function(
        f"() => window.robinLive.experimenter.last.log.length === {downs + 1}", timeout=30_000
    )
    rows = boss.locator("#log tbody tr")
    assert rows.count() == downs + 1
    assert rows.nth(downs).inner_text().split("\t")[3] == "object"
    boss.click("#end-run")
    assert served.wait_over(60) == "ended"
    boss.close()
    page.close()
