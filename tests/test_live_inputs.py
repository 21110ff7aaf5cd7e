"""Every junk message from the page gets one clear error naming the valid choices."""

from __future__ import annotations

import json

import pytest

from robin_sim.live.inputs import GESTURE_KEYS, INPUT_KINDS, LiveInput, LiveInputError, parse_input

W, H = 640, 480


@pytest.mark.parametrize(
    ("raw", "expected"),
    [
        ('{"type": "point", "x": 312, "y": 207}', LiveInput("point", x=312.0, y=207.0)),
        ({"type": "point", "x": 0, "y": 479.5}, LiveInput("point", x=0.0, y=479.5)),
        (b'{"type": "gesture", "gesture": "give_me"}', LiveInput("gesture", gesture="give_me")),
        ('{"type": "thumb", "value": "down"}', LiveInput("thumb", thumb="down")),
        ('{"type": "end"}', LiveInput("end")),
        ('{"type": "take_back"}', LiveInput("take_back")),
        ({"type": "start"}, LiveInput("start")),
    ],
)
def test_valid_messages(raw: object, expected: LiveInput) -> None:
    parsed = parse_input(raw, W, H)  # type: ignore[arg-type]
    assert parsed == expected
    assert parse_input(parsed.as_dict(), W, H) == parsed  # as the page sends it


KINDS = (
    "'point', 'gesture', 'thumb', 'take_back', 'end', 'start', 'hand', 'calibration', "
    "'consent', 'finish'"
)
GESTURES = "valid choices: 'give_me', 'grasp', 'release'"


@pytest.mark.parametrize(
    ("raw", "message"),
    [
        ("hello", f'message is not JSON; .* with "type" one of {KINDS}'),
        (b"\xff\xfe", "message is not JSON"),
        ("", "message is not JSON"),
        ("[1, 2]", f'must be a JSON object with a "type" \\({KINDS}\\), got a JSON list'),
        ('"point"', "got a JSON str"),
        ("{}", f"message type missing is unknown; valid choices: {KINDS}"),
        ('{"type": "wave"}', f"message type 'wave' is unknown; valid choices: {KINDS}"),
        ('{"type": 3}', "message type 3 is unknown"),
        ('{"type": "point", "x": 3}', "point: missing field\\(s\\) 'y'; .* takes 'x', 'y'"),
        ('{"type": "point", "x": 3, "y": 4, "z": 1}', "point: unknown field\\(s\\) 'z'"),
        ('{"type": "end", "now": 1}', "end: unknown field\\(s\\) 'now'; .* no fields besides"),
        ('{"type": "take_back", "t": 3}', "take_back: unknown field\\(s\\) 't'"),
        ('{"type": "point", "x": "3", "y": 4}', "x must be a number of pixels in \\[0, 640\\)"),
        ('{"type": "point", "x": true, "y": 4}', "point: x must be a number"),
        ('{"type": "point", "x": 640, "y": 4}', "x = 640 lies outside .*; valid: 0 <= x < 640"),
        ('{"type": "point", "x": 3, "y": -1}', "y = -1 lies outside the 480-pixel frame"),
        ('{"type": "point", "x": NaN, "y": 4}', "x = nan lies outside"),
        ('{"type": "point", "x": 3, "y": Infinity}', "y = inf lies outside"),
        ('{"type": "gesture", "gesture": "pointing"}', f"unknown gesture 'pointing'; {GESTURES}"),
        ('{"type": "gesture", "gesture": null}', "unknown gesture None"),
        ('{"type": "thumb", "value": "side"}', "unknown value 'side'; valid .* 'up', 'down'"),
        ('{"type": "thumb"}', "thumb: missing field\\(s\\) 'value'"),
        ('{"type": "consent", "value": "yes"}', "unknown value 'yes'; valid .* 'agree', 'decline'"),
        ('{"type": "finish", "now": 1}', "unknown field\\(s\\) 'now'"),
        ("x" * 5000, "too long \\(at most 4096\\)"),
        (42, "message must be JSON text, got int"),
    ],
)
def test_junk_messages_get_one_clear_error(raw: object, message: str) -> None:
    with pytest.raises(LiveInputError, match=message):
        parse_input(raw, W, H)  # type: ignore[arg-type]


def test_the_lists_the_page_uses() -> None:
    assert INPUT_KINDS == (
        "point",
        "gesture",
        "thumb",
        "take_back",
        "end",
        "start",
        "hand",
        "calibration",
        "consent",
        "finish",
    )
    assert GESTURE_KEYS == ("give_me", "grasp", "release")
    for kind in INPUT_KINDS:  # every kind is named in the error for an unknown one
        with pytest.raises(LiveInputError, match=repr(kind)):
            parse_input(json.dumps({"type": "?"}), W, H)
