"""A live session's webcam channel (``--webcam``): hand readings acted on as the participant's.

:class:`Webcam` holds the session's :class:`~robin_sim.live.hands.reader.HandReader` (behind a
lock: readings come on the server's event loop, the learner's feedback on the physics thread),
checks the readings' rate, and turns a decided gesture into the same input a button, key or
click makes: give me / grasp / release while the participant's gesture is awaited, a thumb while
an action is judged, pointing (the dwell of the fingertip cursor) as a click at the cursor,
picked as a click is. A decision that fits no moment (a thumb while nothing is judged) does
nothing and stays armed.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from pil.types import SIGN_OF, Feedback, Gesture
from robin_sim.live.hands.landmarks import HandInput
from robin_sim.live.hands.reader import HandReader, HandReading
from robin_sim.live.hands.shape import POINTING_SIGN
from robin_sim.live.inputs import GESTURE_BY_KEY, LiveInputError
from robin_sim.live.participant import Gesturing

if TYPE_CHECKING:
    from pil.task.world import Target
    from robin_sim.live.participant import LiveParticipant

MAX_READINGS_PER_S = 15  # the page sends at most this many; more are refused
THUMB_OF = {SIGN_OF[thumb]: thumb for thumb in (Feedback.OK, Feedback.NOT_OK)}
INSTRUCTIONS = {
    SIGN_OF[Gesture.GIVE_ME]: "Hold out your open palm, as for 'give me'.",
    SIGN_OF[Gesture.GRASP]: "Make a fist (grasp).",
    SIGN_OF[Gesture.RELEASE]: "Open your hand, fingers up (release).",
    SIGN_OF[Feedback.OK]: "Show a thumb up.",
    SIGN_OF[Feedback.NOT_OK]: "Show a thumb down.",
    SIGN_OF[Gesture.POINTING]: "Point with your index finger.",
}


class Webcam:
    """The webcam channel of one session (see the module doc)."""

    def __init__(
        self, width: int, height: int, *, calibrate: bool = True, eyes_read: bool = False
    ) -> None:
        self.reader = HandReader(width, height)
        self.calibrate = calibrate
        # --detector vision: Robin's eyes read give me, grasp and release from the mirrored
        # hand (robin_sim.live.eye_watch); the landmarks' decision of them is not acted on
        self.eyes_read = eyes_read
        self._lock = threading.Lock()
        self._recent: deque[float] = deque()
        self.last: HandReading | None = None
        self._hand_label: str | None = None  # the label of the newest reading with a hand
        self.problem = ""  # why the last decision could not be acted on ("" none)

    def start(self) -> None:
        """The session runs: calibration begins (unless turned off)."""
        if self.calibrate:
            with self._lock:
                self.reader.start_calibration(time.monotonic())

    def calibration(self, action: str) -> None:
        with self._lock:
            if action == "skip":
                self.reader.skip_calibration()
            else:
                self.reader.start_calibration(time.monotonic())

    def read(
        self,
        hand: HandInput,
        participant: LiveParticipant,
        pick: Callable[[float, float], Target],
        on_pick: Callable[[Target, float, float], None],
    ) -> HandReading:
        """Read one message and act on its decision; :class:`LiveInputError` over the rate."""
        started = time.perf_counter()
        now = time.monotonic()
        with self._lock:
            while self._recent and now - self._recent[0] >= 1.0:
                self._recent.popleft()
            if len(self._recent) >= MAX_READINGS_PER_S:
                raise LiveInputError(
                    f"hand: more than {MAX_READINGS_PER_S} readings a second; this one was dropped"
                )
            self._recent.append(now)
            reading = self.reader.read(hand, now)
            if reading.decided is not None:
                self._act(reading, participant, pick, on_pick)
            reading.latency_ms = (time.perf_counter() - started) * 1000.0
            self.last = reading
            if reading.found:  # as the mirror, which keeps the last hand's pose
                self._hand_label = reading.label
        return reading

    def _act(
        self,
        reading: HandReading,
        participant: LiveParticipant,
        pick: Callable[[float, float], Target],
        on_pick: Callable[[Target, float, float], None],
    ) -> None:
        decided = str(reading.decided)
        key = participant.instruction
        if decided in THUMB_OF:
            if participant.judging:
                participant.offer(THUMB_OF[decided])
                self.reader.acted(reading, f"thumb {decided[6:]}", key)
            return
        if participant.phase not in ("waiting_for_gesture", "waiting_for_thumb"):
            return
        if self.eyes_read and decided != POINTING_SIGN:
            return  # Robin's eyes read it from the mirrored hand
        if decided == POINTING_SIGN:
            assert reading.cursor is not None
            x, y = reading.cursor
            try:
                target = pick(x, y)
            except LiveInputError as problem:
                self.problem = str(problem)
                self.reader.missed(reading)
                return
            on_pick(target, x, y)
            participant.offer(Gesturing(Gesture.POINTING, target, reading.seq))
        else:
            participant.offer(Gesturing(GESTURE_BY_KEY[decided], None, reading.seq))
        self.problem = ""
        self.reader.acted(reading, f"gesture {decided}", key)

    def settled(self, participant: LiveParticipant, feedback: Feedback | None) -> None:
        """The learner received the participant's step (physics thread): adapt."""
        gesture: Gesture | None = participant.step_gesture
        if gesture is None:
            return
        with self._lock:
            self.reader.settled(
                participant.step_reading,
                gesture.value,
                participant.step_key,
                approved=feedback is not Feedback.NOT_OK,
            )

    def hand_label(self) -> str | None:
        """The label of the newest reading that found a hand (None: none yet, or unsure of
        its class): what the mirrored hand shows, which keeps the last hand's pose."""
        with self._lock:
            return self._hand_label

    def reply(self, reading: HandReading) -> dict[str, Any]:
        """What the page is told of a reading (its cursor, dwell ring and calibration)."""
        with self._lock:
            return {"type": "reading", **reading.as_dict(), "problem": self.problem, **self._cal()}

    def _cal(self) -> dict[str, Any]:
        status = self.reader.calibration_status()
        asking = status["asking"]
        status["instruction"] = INSTRUCTIONS.get(asking, "") if asking else ""
        return {"calibration": status}

    def status(self) -> dict[str, Any]:
        with self._lock:
            reader = self.reader
            return {
                "readings": reader.count,
                "hand_found": reader.found,
                "discarded": reader.discards,
                "examples": reader.appearance.size,
                **self._cal(),
            }

    def summary(self) -> dict[str, Any]:
        with self._lock:
            return self.reader.summary()
