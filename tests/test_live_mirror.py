"""``live --webcam``: the footage's landmark readings drive the person's hand in a real session.

The tracker's readings of the real thumb-up footage (``tests/data/hands``, :mod:`hand_data`) go
into a running :class:`~robin_sim.live.session.LiveSession` as the page's hand messages; after
each one the fingertips physics shows (sites, hand frame) are compared with the landmarks'
fingertips scaled to the model's hand (:mod:`robin_sim.live.mirror`).
"""

from __future__ import annotations

import json
import time
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from hand_data import footage, message, usable
from live_driver import Driver

from pil.errors import RobinPilError
from robin_sim.live.config import LiveConfig
from robin_sim.live.session import LiveSession

pytestmark = pytest.mark.slow
# mm (mean over the five fingertips per reading): the scene's fingertips against the landmarks'
# scaled to the model's hand, per footage sequence (mean over its readings, worst reading).
# Measured with the refined fit: thumb up 25.5 / 33.6 (27 readings), palm 2.4 / 4.9 (32); the
# closed-form guess alone gave 56.2 / 65.3 and 11.1 / 19.1. The curled fingers of the thumb up
# carry the rest: the model's finger curls in one plane, the tracked one where its depth says.
BOUNDS_MM = {"thumb_up": (35.0, 45.0), "palm": (5.0, 8.0)}
FOLLOW_MM = 1.0  # the scene's fingertips against the fit's pose: the fit is what is shown
TURN_DEG = 1.0  # the hand's rotation against the landmarks' palm frame


def read_lines(path: Path) -> list[dict]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def footage_messages(sequence: str) -> list[dict]:
    """The page's hand messages of the tracker's readings of one footage sequence."""
    reads = footage()
    return [
        message(
            reads["landmarks"][i], str(reads["handedness"][i]), aspect=float(reads["aspect"][i])
        )
        for i in usable(reads, sequence)
    ]


def webcam_config(tmp_path: Path, session: str, **changes: object) -> LiveConfig:
    """A one-handover ``--webcam`` session without calibration, video or eye inset."""
    base: dict[str, object] = dict(
        scenario="one_handover", out_root=tmp_path, session=session, speed=3.0, fps=5
    )
    base.update(webcam=True, calibrate=False, video=False, eye_inset=False)
    return LiveConfig(**{**base, **changes})  # type: ignore[arg-type]


def test_the_footage_drives_the_persons_fingertips(tmp_path: Path) -> None:
    config = webcam_config(tmp_path, "m1")
    session = LiveSession(config)
    driver = Driver(session)
    session.start()
    try:
        driver.my_turn()
        mirror = session.mirror
        assert mirror is not None
        world = session.body.world
        legs = world.legs.positions()
        turn_before = mirror.data.userdata[mirror.turn_q : mirror.turn_q + 4].copy()
        errors: dict[str, np.ndarray] = {}
        for sequence in BOUNDS_MM:
            messages = footage_messages(sequence)
            before = len(mirror.errors_mm)
            for k, raw in enumerate(messages):
                session.receive(raw)
                deadline = time.monotonic() + 30
                while len(mirror.errors_mm) <= before + k and time.monotonic() < deadline:
                    time.sleep(0.01)
                assert len(mirror.errors_mm) == before + k + 1, "the reading was not applied"
                time.sleep(1 / 14)  # the page sends at most 15 a second
            errors[sequence] = np.array(mirror.errors_mm[before:])
            assert len(errors[sequence]) == len(messages) >= 20
        follow, turn = np.array(mirror.follow_mm), np.array(mirror.turn_deg)
        turned = np.abs(mirror.data.userdata[mirror.turn_q : mirror.turn_q + 4] - turn_before).max()
        still = np.abs(world.legs.positions() - legs).max()
        for sequence, e in errors.items():
            print(f"mirror {sequence}: fingertips {e.mean():.1f} mm mean, {e.max():.1f} worst")
        print(f"mirror: follow {follow.max():.3f} mm worst; turn {turn.max():.3f} deg worst")
    finally:
        session.stop("ended")
    for sequence, (mean_bound, worst_bound) in BOUNDS_MM.items():
        e = errors[sequence]
        assert e.mean() <= mean_bound and e.max() <= worst_bound, (sequence, e)
    assert follow.max() <= FOLLOW_MM and turn.max() <= TURN_DEG, (follow, turn)
    assert turned > 0.1  # the hand turned to the footage's palm
    assert still < 1e-3  # no leg moved


def test_vision_needs_the_webcam(tmp_path: Path) -> None:
    with pytest.raises(RobinPilError, match=r"--detector vision .* add --webcam"):
        LiveConfig(out_root=tmp_path, detector="vision").checked()
    with pytest.raises(RobinPilError, match="detector"):
        LiveConfig(out_root=tmp_path, webcam=True, detector="eyes").checked()


def test_robins_eyes_read_the_mirrored_hand(tmp_path: Path) -> None:
    """``--detector vision``: Robin's eyes look at the mirrored hand after the readings; the
    landmarks' own give me is not acted on; what the eyes offer is the participant's gesture.

    The shipped eye-camera model (issue 41: held-leg samples, the table-top cut) reads the
    mirrored palm, raised from rest, as give me in 31 of 32 readings
    (bench/bench_mirror_eyes.py, tests/test_mirror_looks.py; at rest, before the raise, also
    31; the format-4 model before it 21, the rest as pointing, which is never offered; format 3
    read 1 of 32): the eyes must offer give me for the palm themselves, and no other gesture
    (the landmarks' own reading is never acted on)."""
    config = webcam_config(tmp_path, "v1", speed=1.0, detector="vision", feedback_window=30.0)
    session = LiveSession(config)
    driver = Driver(session)
    session.start()
    read: dict[str, list[str]] = {}
    try:
        driver.my_turn()
        run = session._run_parts
        assert run is not None and run.eyes is not None
        eyes = run.eyes
        for raw in footage_messages("palm"):  # the palm held out, until Robin's eyes take it
            session.receive(raw)
            time.sleep(0.3)  # a look at most every LOOK_GAP_S of sim time
            if any(look.offered for look in eyes.looks):
                break
        read["palm"] = [look.label for look in eyes.looks]
        offered_palm = [look.offered for look in eyes.looks if look.offered]
        assert offered_palm, f"the eyes offered no gesture for the palm: {read}"
        taken = driver.wait(
            lambda s: s["phase"] != "waiting_for_gesture", "the eyes' gesture to be taken"
        )
        before = len(eyes.looks)
        for raw in footage_messages("thumb_up")[::2]:  # looked at, not acted on: Robin acts
            session.receive(raw)
            time.sleep(0.3)
        read["thumb_up"] = [look.label for look in eyes.looks[before:]]
        offered = [look.offered for look in eyes.looks if look.offered]
        acted = session.webcam.last
        landmarks_now = eyes.landmarks()  # the session wired the eyes to the webcam's label
        print("eyes read:", {k: dict(Counter(v)) for k, v in read.items()}, "offered", offered)
    finally:
        summary = session.stop("ended")
    assert set(offered_palm) <= {"give_me"}, (offered_palm, read)
    assert taken["phase"] != "waiting_for_gesture", (offered, read)
    assert len(read["thumb_up"]) >= 5, read
    assert summary["vision"]["eyes"]["looks"] >= sum(len(v) for v in read.values())
    assert acted is not None
    assert acted.found and landmarks_now == acted.label == "thumb_up", (landmarks_now, acted)
    assert "withheld" in summary["vision"]["eyes"]
    lines = [e for e in read_lines(session.out_dir / "inputs.jsonl") if e["raw"]["type"] == "hand"]
    assert not any(str(e["reading"]["acted"]).startswith("gesture give_me") for e in lines)
