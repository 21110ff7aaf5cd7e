"""The replay page in headless chromium: the timeline scrubs to a frame, Play runs to the end."""

from __future__ import annotations

import pytest
from replay_rig import recorded_run, serving  # tests/replay_rig.py (tests/ is on the path)

pytestmark = pytest.mark.slow


def test_the_timeline_scrubs_and_play_runs_to_the_last_frame(browser, tmp_path) -> None:
    path = recorded_run(tmp_path, frames=8)
    with serving(path) as port:
        page = browser.new_page()
        page.goto(f"http://127.0.0.1:{port}/")
        page.wait_for_function("() => window.robinReplay && window.robinReplay.shown === 0")
        first = page.locator("#frame").screenshot()
        page.locator("#timeline").fill("5")  # a range input: sets the value, fires input
        page.wait_for_function("() => window.robinReplay.shown === 5")
        assert page.locator("#time").inner_text() == "0.50 s"
        assert page.locator("#frame").screenshot() != first  # another picture is shown
        page.locator("#play").click()
        page.wait_for_function(
            "() => window.robinReplay.shown === 7 && !window.robinReplay.playing", timeout=60_000
        )
        assert page.locator("#timeline").input_value() == "7"
        page.close()
