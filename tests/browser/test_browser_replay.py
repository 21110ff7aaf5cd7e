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


def test_a_step_between_sparse_frames_shows_the_nearest_and_says_how_far(browser, tmp_path) -> None:
    """Issue 39: a lowered live stream kept few states; "go to step" showed a frame seconds
    after the step and said nothing of it."""
    path = recorded_run(tmp_path, frames=6, spacing=1.0)  # states at 0, 1, ..., 5 s
    steps = {"markers": [], "steps": [{"step": 1, "time": 2.3}, {"step": 2, "time": 4.0}]}
    with serving(path, steps) as port:
        page = browser.new_page()
        page.goto(f"http://127.0.0.1:{port}/")
        page.wait_for_function("() => window.robinReplay && window.robinReplay.shown === 0")
        page.evaluate("() => window.robinReplay.jumpToStep(1)")
        page.wait_for_function("() => window.robinReplay.shown === 2")  # 2 s, not 3 s
        said = page.locator("#shown-step").inner_text()
        assert said == (
            "step 1 at 2.30 s (no frame recorded then: the nearest, 2.00 s, is 0.30 s earlier)"
        )
        page.evaluate("() => window.robinReplay.jumpToStep(2)")
        page.wait_for_function("() => window.robinReplay.shown === 4")
        assert page.locator("#shown-step").inner_text() == "step 2 at 4.00 s"
        page.close()
