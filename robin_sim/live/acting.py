"""What a participant's message (other than a hand reading) does to a running live session.

:func:`apply_input` takes one parsed :class:`~robin_sim.live.inputs.LiveInput`: ``end`` ends
the session at the next safe moment, ``take_back`` takes back the action that stood last
(within its window, :mod:`robin_sim.live.take_back`), a thumb judges the action Robin runs or
just ran, a
gesture (a key, a button or a click on the scene) is offered when it is the participant's
turn, ``calibration`` drives the webcam's calibration. Anything that fits no moment raises
:class:`~robin_sim.live.inputs.LiveInputError` with a plain message for the page.
"""

from __future__ import annotations

from typing import Any

from pil.types import Gesture
from robin_sim.live.inputs import (
    GESTURE_BY_KEY,
    SCREEN_KINDS,
    THUMBS,
    LiveInput,
    LiveInputError,
)
from robin_sim.live.participant import Gesturing, LiveParticipant
from robin_sim.live.picking import Picker
from robin_sim.live.status import LiveStatus
from robin_sim.live.webcam import Webcam


def apply_input(
    item: LiveInput,
    participant: LiveParticipant | None,
    picker: Picker | None,
    webcam: Webcam | None,
    view: LiveStatus,
) -> None:
    """Act on ``item`` in a session that has not ended (see the module doc)."""
    if item.kind == "calibration" and webcam is None:
        raise LiveInputError(
            "calibration: this session has no webcam; start it with robin-pil live --webcam"
        )
    if participant is None:
        raise LiveInputError("the session is still starting; wait for the first frame")
    phase = participant.phase
    if item.kind == "end":
        participant.offer("end")
    elif item.kind == "take_back":
        your_turn = phase == "waiting_for_gesture"
        why = participant.take_backs.refusal(participant.body.world.time, your_turn)
        if why:
            raise LiveInputError(why)
        participant.take_backs.request()
        participant.offer("take_back")
    elif item.kind == "start":
        raise LiveInputError(
            "start: this session runs already; 'start' leaves a protocol block's instructions"
        )
    elif item.kind in SCREEN_KINDS:
        raise LiveInputError(f"{item.kind}: a block is running; there is no {item.kind} screen")
    elif item.kind == "calibration":
        assert webcam is not None
        webcam.calibration(str(item.action))
    elif item.kind == "thumb":
        if not participant.judging:
            raise LiveInputError(
                "There is no robot action to judge now: give a thumb "
                "while Robin moves or just after."
            )
        participant.offer(THUMBS[str(item.thumb)])
    else:
        if phase not in ("waiting_for_gesture", "waiting_for_thumb"):
            raise LiveInputError(
                "It is not your turn yet: Robin is still acting. Wait until it asks for "
                "your gesture, or give thumb down to stop it."
            )
        if item.kind == "point":
            # a point always has x and y (parse_input); the picker comes with the participant
            x, y = item.x, item.y
            assert x is not None and y is not None and picker is not None
            target = picker.pick(float(x), float(y))
            view.clicked(target, float(x), float(y))
            participant.offer(Gesturing(Gesture.POINTING, target))
        else:
            participant.offer(Gesturing(GESTURE_BY_KEY[str(item.gesture)]))


def apply_reading(
    item: LiveInput,
    webcam: Webcam | None,
    participant: LiveParticipant | None,
    picker: Picker | None,
    view: LiveStatus,
    ended: bool,
) -> dict[str, Any]:
    """A webcam reading: read, acted on if it decides a gesture; what it was read as (never
    "not your turn": a reading that fits no moment does nothing). :class:`LiveInputError`
    when it cannot be read now (no webcam, the session over or still starting, a bad one)."""
    if webcam is None:
        raise LiveInputError(
            "hand: this session has no webcam; start it with robin-pil live --webcam"
        )
    if ended:
        raise LiveInputError("the session has ended; nothing more is taken")
    if participant is None or picker is None:
        raise LiveInputError("the session is still starting; wait for the first frame")
    assert item.hand is not None
    try:
        reading = webcam.read(item.hand, participant, picker.pick, view.clicked)
    except LiveInputError:
        raise
    except Exception as problem:  # refused: the session goes on
        raise LiveInputError(f"hand: could not be read ({problem!r:.200})") from None
    return reading.as_dict()
