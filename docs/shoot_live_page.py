"""Take docs/live_page.png: the live page in headless chromium during a real session.

Run: ``python docs/shoot_live_page.py [docs/live_page.png]``. A session of the default scenario
at 1x real time; the participant (driven through the page as in tests/browser) hands over leg 1
as type A (pointing, grasp, give me, release; thumb down on every wrong move, thumb up on the
meant one) and points at leg 2; the shot is taken while Robin acts on what it has learnt.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "browser"))

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()

from conftest import CHROMIUM, start_server  # noqa: E402
from page_driver import TYPE_A, click_frame_pixel, leg_pixels, play_steps, wait_status  # noqa: E402
from playwright.sync_api import sync_playwright  # noqa: E402

from robin_sim.live.session import LiveConfig  # noqa: E402


def main() -> int:
    target = Path(sys.argv[1] if len(sys.argv) > 1 else "docs/live_page.png")
    with tempfile.TemporaryDirectory() as folder, sync_playwright() as playwright:
        served = start_server([LiveConfig(out_root=Path(folder), video=False)])
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), headless=True,
                                             args=["--no-sandbox"])  # fmt: skip
        page = browser.new_page(viewport={"width": 1200, "height": 900})
        try:
            page.goto(served.url("/"))
            legs = leg_pixels(None)
            play_steps(page, TYPE_A, legs[1])  # hand over leg 1 as type A, teaching Robin
            wait_status(page, "s.legs_delivered === 1 && s.phase === 'waiting_for_gesture'")
            click_frame_pixel(page, *legs[2])  # point at the next leg: learnt, not guessed
            wait_status(page, "s.phase === 'robot_acting' && !!s.action")
            page.wait_for_timeout(1200)
            page.screenshot(path=str(target))
        finally:
            page.close()
            browser.close()
            served.server.stop_soon()
            served.thread.join(60)
    print(f"wrote {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
