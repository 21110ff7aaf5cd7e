"""The participant's messages from the browser, checked before anything acts on them.

:func:`parse_input` turns one raw message (JSON text, bytes or an already decoded dict) into a
:class:`LiveInput`, or raises one :class:`LiveInputError` that names the problem and the valid
choices. Valid messages (the live page's contract)::

    {"type": "point", "x": 312, "y": 207}          a click at a pixel of the scene frame
    {"type": "gesture", "gesture": KEY}            KEY: GESTURE_KEYS, give_me | grasp | release
    {"type": "thumb", "value": "up"}               up | down
    {"type": "take_back"}                          "That was wrong": take back the last action
                                                   that stood (robin_sim.live.take_back)
    {"type": "end"}                                the participant ends the session
    {"type": "start"}                              leave a protocol block's instructions
    {"type": "hand", "landmarks": [[x, y, z] * 21] | null, "handedness": "Left" | "Right" | null,
     "score": s, "aspect": w / h}                  a hand tracker reading (``--webcam``)
    {"type": "calibration", "action": "skip"}      skip | restart the webcam's calibration
    {"type": "consent", "value": "agree"}          agree | decline, on a study's consent screen
    {"type": "finish"}                             leave a study's debrief screen (the end)
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from pil.errors import RobinPilError
from pil.types import SIGN_OF, Feedback, Gesture
from robin_sim.live.hands.landmarks import HandError, HandInput, check_hand

# The fields each kind takes besides "type".
FIELDS: dict[str, tuple[str, ...]] = {
    "point": ("x", "y"),
    "gesture": ("gesture",),
    "thumb": ("value",),
    "take_back": (),
    "end": (),
    "start": (),
    "hand": ("landmarks", "handedness", "score", "aspect"),
    "calibration": ("action",),
    "consent": ("value",),
    "finish": (),
}
GESTURE_BY_KEY: dict[str, Gesture] = {  # the signs' names (pil.types); pointing is the click
    SIGN_OF[gesture]: gesture for gesture in (Gesture.GIVE_ME, Gesture.GRASP, Gesture.RELEASE)
}
THUMBS: dict[str, Feedback] = {"up": Feedback.OK, "down": Feedback.NOT_OK}
INPUT_KINDS: tuple[str, ...] = tuple(FIELDS)
GESTURE_KEYS: tuple[str, ...] = tuple(GESTURE_BY_KEY)
THUMB_VALUES: tuple[str, ...] = tuple(THUMBS)
# The page's keyboard shortcut for each gesture key (the page builds its buttons from these).
GESTURE_SHORTCUTS: dict[str, str] = {
    SIGN_OF[Gesture.GIVE_ME]: "g",
    SIGN_OF[Gesture.GRASP]: "r",
    SIGN_OF[Gesture.RELEASE]: "l",
}
# "That was wrong" (take_back): its button's label and key on the page (no other key uses "w")
TAKE_BACK_LABEL = "That was wrong"
TAKE_BACK_SHORTCUT = "w"
CALIBRATION_ACTIONS: tuple[str, ...] = ("skip", "restart")
CONSENT_VALUES: tuple[str, ...] = ("agree", "decline")
SCREEN_KINDS: tuple[str, ...] = ("consent", "finish")  # a study's screens around the blocks
MAX_MESSAGE_BYTES = 4096  # a valid message is a few dozen bytes (a hand reading about 1 KB)


class LiveInputError(RobinPilError):
    """A message from the participant's page that cannot be acted on (says why and what works)."""


@dataclass(frozen=True, slots=True)
class LiveInput:
    """One checked message; fields a kind does not use are None."""

    kind: str  # one of INPUT_KINDS
    x: float | None = None
    y: float | None = None
    gesture: str | None = None  # one of GESTURE_KEYS
    thumb: str | None = None  # one of THUMB_VALUES
    hand: HandInput | None = None  # a tracker reading (kind "hand")
    action: str | None = None  # one of CALIBRATION_ACTIONS
    consent: str | None = None  # one of CONSENT_VALUES

    def as_dict(self) -> dict[str, Any]:
        """The message as the page sends it."""
        if self.kind == "point":
            return {"type": "point", "x": self.x, "y": self.y}
        if self.kind == "gesture":
            return {"type": "gesture", "gesture": self.gesture}
        if self.kind == "thumb":
            return {"type": "thumb", "value": self.thumb}
        if self.kind == "hand" and self.hand is not None:
            return self.hand.as_dict()
        if self.kind == "calibration":
            return {"type": "calibration", "action": self.action}
        if self.kind == "consent":
            return {"type": "consent", "value": self.consent}
        return {"type": self.kind}


def _choices(values: tuple[str, ...]) -> str:
    return ", ".join(repr(v) for v in values)


def _decode(raw: str | bytes | Mapping[str, Any]) -> Mapping[str, Any]:
    """The message as a JSON object, or the error saying what it is instead."""
    if isinstance(raw, Mapping):
        message: Any = raw
    elif isinstance(raw, str | bytes | bytearray):
        if len(raw) > MAX_MESSAGE_BYTES:
            raise LiveInputError(
                f"message of {len(raw)} bytes is too long (at most {MAX_MESSAGE_BYTES}); send "
                'one JSON object such as {"type": "thumb", "value": "up"}'
            )
        try:
            message = json.loads(raw)
        except RecursionError:
            raise LiveInputError(
                "message is nested too deeply to read; send one flat JSON object such as "
                '{"type": "thumb", "value": "up"}'
            ) from None
        except (ValueError, UnicodeDecodeError):
            raise LiveInputError(
                'message is not JSON; send one JSON object such as {"type": "thumb", '
                f'"value": "up"}} with "type" one of {_choices(INPUT_KINDS)}'
            ) from None
    else:
        raise LiveInputError(f"message must be JSON text, got {type(raw).__name__}")
    if not isinstance(message, Mapping):
        raise LiveInputError(
            f'message must be a JSON object with a "type" ({_choices(INPUT_KINDS)}), '
            f"got a JSON {type(message).__name__}"
        )
    return message


def _coordinate(message: Mapping[str, Any], name: str, size: int) -> float:
    value = message[name]
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise LiveInputError(
            f"point: {name} must be a number of pixels in [0, {size}), got {value!r:.40}"
        )
    if (isinstance(value, float) and not math.isfinite(value)) or not 0 <= value < size:
        raise LiveInputError(
            f"point: {name} = {value!r:.40} lies outside the {size}-pixel frame; valid: "
            f"0 <= {name} < {size}"
        )
    return float(value)


def _choice(message: Mapping[str, Any], kind: str, name: str, valid: tuple[str, ...]) -> str:
    value = message[name]
    if not isinstance(value, str) or value not in valid:
        raise LiveInputError(
            f"{kind}: unknown {name} {value!r:.40}; valid choices: {_choices(valid)}"
        )
    return value


def parse_input(raw: str | bytes | Mapping[str, Any], width: int, height: int) -> LiveInput:
    """Check one message against the contract; ``width`` x ``height`` is the scene frame.
    Whatever goes wrong reading it is a :class:`LiveInputError` (never another exception)."""
    try:
        return _checked(raw, width, height)
    except LiveInputError:
        raise
    except Exception as problem:  # a message must never end the session
        raise LiveInputError(
            f"message could not be read ({type(problem).__name__}); send one JSON object such "
            f'as {{"type": "thumb", "value": "up"}} with "type" one of {_choices(INPUT_KINDS)}'
        ) from None


def _checked(raw: str | bytes | Mapping[str, Any], width: int, height: int) -> LiveInput:
    message = _decode(raw)
    kind = message.get("type")
    if not isinstance(kind, str) or kind not in FIELDS:
        shown = "missing" if "type" not in message else f"{kind!r:.40}"
        raise LiveInputError(
            f"message type {shown} is unknown; valid choices: {_choices(INPUT_KINDS)}"
        )
    wanted = FIELDS[kind]
    keys = [str(k) for k in message if k != "type"]
    extra = [k for k in keys if k not in wanted]
    missing = [k for k in wanted if k not in message]
    if extra or missing:
        what = "; ".join(
            part
            for part in (
                f"unknown field(s) {', '.join(repr(k[:40]) for k in extra)}" if extra else "",
                f"missing field(s) {', '.join(repr(k) for k in missing)}" if missing else "",
            )
            if part
        )
        takes = _choices(wanted) if wanted else "no fields besides 'type'"
        raise LiveInputError(f"{kind}: {what}; the {kind} message takes {takes}")
    if kind == "point":
        return LiveInput(
            kind, x=_coordinate(message, "x", width), y=_coordinate(message, "y", height)
        )
    if kind == "gesture":
        return LiveInput(kind, gesture=_choice(message, kind, "gesture", GESTURE_KEYS))
    if kind == "thumb":
        return LiveInput(kind, thumb=_choice(message, kind, "value", THUMB_VALUES))
    if kind == "hand":
        try:
            return LiveInput(kind, hand=check_hand(message))
        except HandError as problem:
            raise LiveInputError(str(problem)) from None
    if kind == "calibration":
        return LiveInput(kind, action=_choice(message, kind, "action", CALIBRATION_ACTIONS))
    if kind == "consent":
        return LiveInput(kind, consent=_choice(message, kind, "value", CONSENT_VALUES))
    return LiveInput(kind)
