"""The webcam's hand readings on the server: checked, normalised, read, held, dwelt, learnt.

Fast (no MuJoCo, no browser): made-up hands (:func:`hand_data.synthetic_hand`) for the logic,
the tracker's own readings of real footage (``tests/data/hands/landmarks.npz``) for accuracy.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hand_data import footage, message, synthetic_hand

from robin_sim.live.hands.landmarks import HandInput, features, normalised
from robin_sim.live.hands.reader import CALIBRATION_ORDER, DWELL_S, HandReader
from robin_sim.live.hands.shape import read_shape
from robin_sim.live.inputs import LiveInputError, parse_input

POINTING = ((True, False, False, False), "in")
FIST = ((False,) * 4, "in")
OPEN = ((True,) * 4, "in")
THUMB_UP = ((False,) * 4, "up")
THUMB_DOWN = ((False,) * 4, "down")


def hand(kind: tuple, at=(0.5, 0.7), handedness="Right", score=0.95) -> HandInput:
    item = parse_input(
        message(synthetic_hand(kind[0], kind[1], at), handedness, score, 1.0), 640, 480
    )
    assert item.hand is not None
    return item.hand


# --- the message ---------------------------------------------------------------------------
def test_a_hand_message_is_checked_part_by_part() -> None:
    good = message(synthetic_hand(*FIST))
    assert parse_input(json.dumps(good), 640, 480).hand.found
    assert not parse_input(json.dumps(message(None)), 640, 480).hand.found
    bad = {
        "landmarks must be a list of 21": {**good, "landmarks": good["landmarks"][:20]},
        "landmark 3 must be [x, y, z]": {
            **good,
            "landmarks": [*good["landmarks"][:3], [0.1, 0.2], *good["landmarks"][4:]],
        },
        "landmark 0 x = nan is outside": {
            **good,
            "landmarks": [[math.nan, 0.5, 0.0], *good["landmarks"][1:]],
        },
        "landmark 0 y = 5 is outside": {
            **good,
            "landmarks": [[0.5, 5, 0.0], *good["landmarks"][1:]],
        },
        "landmark 0 z must be a number": {
            **good,
            "landmarks": [[0.5, 0.5, "deep"], *good["landmarks"][1:]],
        },
        "score = 1.5 is outside [0.0, 1.0]": {**good, "score": 1.5},
        "score must be a number": {**good, "score": True},
        "aspect = 0 is outside": {**good, "aspect": 0},
        "handedness 'Both' is unknown; valid: 'Left', 'Right'": {**good, "handedness": "Both"},
        "handedness must be null when landmarks is null": {**message(None), "handedness": "Left"},
        "unknown field(s) 'frame'": {**good, "frame": "data:image/jpeg;base64,..."},
    }
    for expected, raw in bad.items():
        with pytest.raises(
            LiveInputError,
            match=expected.replace("(", r"\(")
            .replace(")", r"\)")
            .replace("[", r"\[")
            .replace("]", r"\]"),
        ):
            parse_input(json.dumps(raw), 640, 480)
    assert len(json.dumps(good)) < 1200  # well under the 4 KiB a message may have


def test_normalised_shapes_ignore_place_size_and_which_hand() -> None:
    points = synthetic_hand(*POINTING)
    base = features(normalised(points, "Right", 1.0))
    moved = points.copy()
    moved[:, :2] = (points[:, :2] - 0.5) * 0.5 + [0.3, 0.4]  # half the size, elsewhere
    assert np.allclose(features(normalised(moved, "Right", 1.0)), base, atol=1e-9)
    mirrored = points.copy()
    mirrored[:, 0] = 1.0 - points[:, 0]  # the other hand, as the camera sees it
    assert np.allclose(features(normalised(mirrored, "Left", 1.0)), base, atol=1e-9)
    upside = points.copy()
    upside[:, 1] = 1.0 - points[:, 1]
    assert not np.allclose(features(normalised(upside, "Right", 1.0)), base, atol=0.1)


def test_the_shape_reads_each_made_up_gesture() -> None:
    for kind, gesture in (
        (POINTING, "pointing"),
        (FIST, "grasp"),
        (OPEN, "release"),
        (THUMB_UP, "thumb_up"),
        (THUMB_DOWN, "thumb_down"),
    ):
        label, certainty = read_shape(normalised(synthetic_hand(*kind), "Right", 1.0))
        assert label == gesture and certainty > 0.8, (gesture, label, certainty)
    palm = synthetic_hand(*OPEN)
    palm[:, 1] = 2 * palm[0, 1] - palm[:, 1]  # fingers down: held out
    assert read_shape(normalised(palm, "Right", 1.0))[0] == "give_me"


# --- holding, latching, discarding -----------------------------------------------------------
def test_a_gesture_is_decided_when_held_and_once_until_the_hand_changes() -> None:
    reader = HandReader(640, 480)
    first = reader.read(hand(THUMB_UP), 0.0)
    assert first.label == "thumb_up" and first.decided is None and first.confidence > 0.5
    second = reader.read(hand(THUMB_UP), 0.1)
    assert second.decided == "thumb_up"
    still = reader.read(hand(THUMB_UP), 0.2)
    assert still.decided == "thumb_up"  # not acted on yet: stays armed
    reader.acted(still, "thumb up", (0, 0))
    assert reader.read(hand(THUMB_UP), 0.3).decided is None  # latched
    assert reader.read(hand(THUMB_UP), 0.4).decided is None
    assert not reader.read(HandInput(None, None, 0.0, 1.0), 0.5).found  # the hand goes
    reader.read(hand(THUMB_UP), 0.6)
    assert reader.read(hand(THUMB_UP), 0.7).decided == "thumb_up"  # shown again
    summary = reader.summary()
    assert summary["readings"] == 8 and summary["hand_found"] == 7
    assert summary["decisions"] == {"thumb_up": 1}


def test_an_unsure_reading_is_discarded_and_breaks_the_hold() -> None:
    reader = HandReader(640, 480)
    reader.read(hand(FIST), 0.0)
    unsure = reader.read(hand(FIST, score=0.3), 0.1)  # the tracker doubts its hand
    assert unsure.discarded and unsure.decided is None and unsure.confidence < 0.5
    assert reader.read(hand(FIST), 0.2).decided is None  # the run starts again
    assert reader.read(hand(FIST), 0.3).decided == "grasp"
    assert reader.summary()["discarded"] == 1


def test_pointing_held_still_selects_after_the_dwell_time() -> None:
    reader = HandReader(640, 480)
    at = (0.4, 0.6)
    first = reader.read(hand(POINTING, at), 10.0)
    assert first.label == "pointing" and first.cursor is not None and first.dwell == 0.0
    half = reader.read(hand(POINTING, (at[0] + 0.005, at[1])), 10.0 + DWELL_S / 2)
    assert half.dwell == pytest.approx(0.5) and half.decided is None
    done = reader.read(hand(POINTING, at), 10.0 + DWELL_S)
    assert done.decided == "pointing" and done.cursor == first.cursor
    x_tip = synthetic_hand(*POINTING, at)[8, 0]
    assert first.cursor[0] > 320 if x_tip < 0.5 else first.cursor[0] < 320  # mirrored
    moved = reader.read(hand(POINTING, (at[0] + 0.3, at[1])), 10.0 + DWELL_S + 0.1)
    assert moved.dwell == 0.0 and moved.decided is None  # moved away: the dwell restarts


# --- calibration and learning from feedback --------------------------------------------------
def test_calibration_takes_one_held_example_of_each_gesture() -> None:
    shapes = {
        "give_me": None,
        "grasp": FIST,
        "release": OPEN,
        "thumb_up": THUMB_UP,
        "thumb_down": THUMB_DOWN,
        "pointing": POINTING,
    }
    palm = synthetic_hand(*OPEN)
    palm[:, 1] = 2 * palm[0, 1] - palm[:, 1]
    reader = HandReader(640, 480)
    reader.start_calibration(0.0)
    now = 0.0
    for gesture in CALIBRATION_ORDER:
        assert reader.asking == gesture
        kind = shapes[gesture]
        shown = (
            parse_input(message(palm, aspect=1.0), 640, 480).hand if kind is None else hand(kind)
        )
        now += 1.5
        assert reader.read(shown, now).source == "calibration"
        taken = reader.read(shown, now + 0.1)
        assert taken.acted == f"calibration {gesture}"
    assert not reader.calibrating and reader.calibrated
    assert reader.calibration_status()["note"] == ""
    reading = reader.read(hand(THUMB_DOWN), now + 5)
    assert reading.source == "appearance" and reading.label == "thumb_down"
    assert reading.confidence > 0.5


def footage_hands(sequence: str) -> list[HandInput]:
    """The tracker's readings of one sequence of the real footage, as the page sends them."""
    data = footage()
    hands = []
    for i in np.where(data["sequence"] == sequence)[0]:
        points = data["landmarks"][i]
        if np.isnan(points).any():
            continue
        raw = message(points, str(data["handedness"][i]), float(data["score"][i]))
        raw["aspect"] = float(data["aspect"][i])
        item = parse_input(raw, 640, 480)
        assert item.hand is not None
        hands.append(item.hand)
    return hands


def test_calibration_stores_only_what_looks_like_the_gesture_asked_for() -> None:
    """Asked for the open palm (give me), the real fist and thumb-up footage is refused,
    reading after reading, with a note naming what it looked like; the real palm is taken."""
    reader = HandReader(640, 480)
    reader.start_calibration(0.0)
    assert reader.asking == "give_me"
    now = 0.0
    for sequence, seen in (("fist", "grasp"), ("thumb_up", "thumb up")):
        shown = footage_hands(sequence)
        assert len(shown) >= 20
        for held in shown:
            now += 0.1
            assert reader.read(held, now).acted == ""
        assert reader.asking == "give_me" and "give_me" not in reader.appearance.seeded
        note = reader.calibration_status()["note"]
        assert note.startswith(f"That looks like a {seen}, not a give me"), note
    for held in footage_hands("palm")[:3]:
        now += 0.1
        taken = reader.read(held, now)
    assert taken.acted == "calibration give_me", reader.calibration_status()
    assert reader.asking == "grasp" and reader.calibration_status()["note"] == ""


def test_calibration_refuses_a_hand_that_did_not_change() -> None:
    reader = HandReader(640, 480)
    reader.start_calibration(0.0)
    palm = synthetic_hand(*OPEN)
    palm[:, 1] = 2 * palm[0, 1] - palm[:, 1]
    held = parse_input(message(palm, aspect=1.0), 640, 480).hand
    reader.read(held, 0.0)
    assert reader.read(held, 0.1).acted == "calibration give_me"
    assert reader.asking == "grasp"
    reader.read(held, 1.5)  # still the palm when the fist is asked for
    assert reader.read(held, 1.6).acted == ""
    assert reader.asking == "grasp"
    assert reader.calibration_status()["note"] == (
        "That looks like your give me: show the grasp instead."
    )
    reader.read(hand(FIST), 1.7)
    assert reader.read(hand(FIST), 1.8).acted == "calibration grasp"


def test_a_correction_relabels_the_reading_with_the_gesture_made_instead() -> None:
    reader = HandReader(640, 480)
    reader.read(hand(FIST), 0.0)
    wrong = reader.read(hand(FIST), 0.1)
    reader.acted(wrong, "gesture grasp", (0, 1))
    reader.settled(wrong.seq, "grasp", (0, 1), approved=False)  # thumb down
    assert reader.summary()["corrected"] == 1 and reader.appearance.size == 0
    reader.settled(None, "give_me", (0, 1), approved=True)  # then the give me key, approved
    assert reader.appearance.examples["give_me"][0] == pytest.approx(wrong.features)
    summary = reader.summary()
    assert summary["relabelled"] == 1 and summary["confusion"] == {"grasp": {"give_me": 1}}
    right = reader.read(hand(THUMB_UP), 1.0)
    right = reader.read(hand(THUMB_UP), 1.1)
    reader.acted(right, "thumb up", (0, 2))
    reader.settled(right.seq, "thumb_up", (0, 2), approved=True)
    assert reader.summary()["confirmed"] == 1 and reader.appearance.size == 2


def test_the_live_command_takes_webcam_and_refuses_a_lone_no_calibration() -> None:
    from pil.errors import RobinPilError
    from robin_sim.cli.live import session_configs
    from robin_sim.cli.main import build_parser

    def configs(*argv: str) -> list:
        return session_configs(build_parser("live").parse_args(["live", *argv]))

    assert configs()[0].webcam is False
    config = configs("--webcam")[0]
    assert config.webcam and config.calibrate
    assert configs("--webcam", "--no-calibration")[0].calibrate is False
    with pytest.raises(RobinPilError, match="--no-calibration is for --webcam sessions"):
        configs("--no-calibration")
