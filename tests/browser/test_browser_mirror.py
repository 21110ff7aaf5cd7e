"""The full chain in Chromium: the real thumb-up footage on the page's camera drives the
simulated person's hand, and Robin's own eye cameras read that hand.

Chromium's fake camera plays ``tests/data/hands/thumb_up.mp4`` (Apache-2.0 footage, see its
README); the page's tracker sends its landmarks to a real ``live --webcam --detector vision``
session; the server retargets each reading onto the articulated hand on the physics thread
(:mod:`robin_sim.live.mirror`) and Robin's eyes look at the hand after it
(:mod:`robin_sim.live.eye_watch`): a "give me" by key first has the person hold the palm out
where Robin's eyes see it while it acts, and there they read the camera's thumb up. The test
waits on what the session and the page record, never on time.
"""

from __future__ import annotations

import time
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from page_driver import wait_status
from webcam_rig import HANDS, camera_browser, write_y4m

pytestmark = [pytest.mark.slow, pytest.mark.timeout(600)]
# looks after the give me, one per reading applied (the tracker reads about one frame a
# second). Robin's eyes read the mirrored thumb up at the handover point badly since the person
# stands upright (issue 41, open: bench/bench_mirror_eyes.py reads the stored thumb-up readings
# right in 56 % at rest, 11 % at the handover point (format 3); this test's looks with the
# shipped model: 2-6 of 6 thumb up, the rest release or grasp, which are not offered while the
# landmarks read a thumb). What must hold: the hand follows the camera and is looked at, no look
# is offered as a gesture, and no look reads it as a thumb down (that would flip the verdict).
READINGS = 6
WAIT_S = 240.0  # s at most for them on a busy machine
# mm, the mean fingertip error of one reading against the landmarks scaled to the model's hand:
# the bound of the worst thumb-up reading in tests/test_live_mirror.py (the same tracker read
# the same frames in chromium to make the stored readings)
WORST_MM = 45.0
FOLLOW_MM = 1.0  # the scene's fingertips against the fit's own pose


def test_the_camera_thumb_drives_the_hand_robin_looks_at(tmp_path: Path, live_server) -> None:
    y4m = write_y4m(HANDS / "thumb_up.mp4", tmp_path / "thumb.y4m")
    served = live_server(
        seed=3,
        scenario="one_handover",
        webcam=True,
        calibrate=False,
        detector="vision",
        speed=1.0,
        feedback_window=60.0,
        video=False,
    )
    session = served.conductor.session
    with camera_browser(y4m) as browser:
        page = browser.new_page(viewport={"width": 1100, "height": 1000})
        requests: list[str] = []
        page.on("request", lambda request: requests.append(request.url))
        page.goto(served.url("/"))
        # "give me" by key: the person holds the palm out at the handover point, where Robin's
        # eyes see the hand whole while it acts; the camera's thumb up is then shown there
        wait_status(page, "s.phase === 'waiting_for_gesture'", timeout_s=WAIT_S)
        page.keyboard.press("g")
        wait_status(page, "s.phase !== 'waiting_for_gesture'", timeout_s=WAIT_S)
        run = session._run_parts
        assert run is not None and run.eyes is not None
        start = len(run.eyes.looks)
        deadline = time.monotonic() + WAIT_S
        looks: list[Any] = []
        while time.monotonic() < deadline:
            mirror = run.mirror
            looks = list(run.eyes.looks)[start:]
            if mirror is not None and len(looks) >= READINGS:
                break
            time.sleep(0.2)
        assert mirror is not None, "the session has no mirror"
        errors, follow = np.array(mirror.errors_mm), np.array(mirror.follow_mm)
        page.evaluate("() => window.robinLive.send({type: 'end'})")
        served.wait_over(120)
        page.close()
    own = (f"http://127.0.0.1:{served.port}/", f"ws://127.0.0.1:{served.port}/")
    assert requests and all(url.startswith(own) for url in requests), requests
    print(
        f"chromium mirror: {len(errors)} readings, fingertips {errors.mean():.1f} mm mean, "
        f"{errors.max():.1f} worst; eyes read {dict(Counter(look.label for look in looks))}"
    )
    assert len(errors) >= READINGS, "the camera's readings did not reach the hand"
    # all readings but at most one within the bound: on a busy machine the page's tracker
    # samples the fake camera's frames at other moments than the stored readings (the suite
    # on 2 cores once gave one reading of 78 mm among six of 24-31 mm)
    assert np.sort(errors)[:-1].max() <= WORST_MM, errors
    # every reading follows the fit. The eyes read the thumb up as release or grasp at times,
    # and such a look, once offered, had the body perform that gesture over the mirrored hand
    # (one reading of 7 off by 95 mm in two of three runs); no look is offered while the
    # landmarks read a thumb (robin_sim.live.eye_watch.offer_from), so none is here: three runs
    # withheld 1-3 looks and followed the fit within 1e-12 mm
    assert follow.max() <= FOLLOW_MM, follow
    offered = [look for look in looks if look.offered]
    assert not offered, looks  # the camera's thumb up is feedback, not a gesture
    threshold = run.eyes.gesture_model.threshold
    assert len(looks) >= READINGS, looks
    flipped = [
        look for look in looks if look.label == "thumb_down" and look.confidence >= threshold
    ]
    assert not flipped, looks  # the camera's thumb up never reaches Robin as a thumb down
