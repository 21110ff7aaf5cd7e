"""From hand readings to the session's inputs: confidence, holding, dwell, calibration, counts.

:class:`HandReader` reads each :class:`~.landmarks.HandInput`: its gesture (the person's own
:class:`~.appearance.Appearance` once calibrated, else the hand's shape, :mod:`.shape`) and a
confidence (the tracker's handedness score times the classifier's). Below
:data:`THRESHOLD` the reading is discarded: the robot does nothing and the person makes the
gesture again (PIL's correction path). A gesture is **decided** once it has been read, above
the threshold, in :data:`HOLD` readings in a row; a decision acted on is latched until the
hand changes (a held palm is one "give me", not one per reading). Pointing moves a cursor over
the scene (the index fingertip, mirrored as the self-view is); held within
:data:`DWELL_RADIUS` pixels for :data:`DWELL_S` seconds it selects what is under it.

Calibration (:meth:`HandReader.start_calibration`) asks for each gesture of
:data:`CALIBRATION_ORDER` once and seeds the appearance model with the reading held for it
(refused while it looks like a gesture already taken: the hand has not changed yet).
After each step the learner receives, :meth:`HandReader.settled` confirms the reading it
acted on (approved or silent) or keeps it aside when corrected (thumb down); the gesture the
person makes instead, once approved in the same step of the handover, relabels it.
"""

from __future__ import annotations

import statistics
from collections import Counter, deque
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from robin_sim.live.hands.appearance import Appearance
from robin_sim.live.hands.landmarks import INDEX_TIP, HandInput, features, normalised
from robin_sim.live.hands.shape import GESTURE_NAMES, POINTING_SIGN, memberships, read_shape

THRESHOLD = 0.5  # confidence below which a reading is discarded
HOLD = 2  # readings in a row that decide a gesture
DWELL_S = 1.2  # s the pointing cursor is held still to select
DWELL_RADIUS = 40.0  # frame pixels the cursor may wander while held still
CURSOR_MARGIN = 0.15  # of the camera image on each side left out of the cursor's range
CALIBRATION_ORDER = GESTURE_NAMES  # pointing last: its example moves the cursor
CALIBRATION_GAP_S = 1.0  # s after an example is taken before the next is looked for
# An example this close to one already taken for another gesture is refused: the hand did not
# change (features in palm sizes; on the footage the same gesture lies 0.2-1.7 apart, two
# gestures at least 1.6)
SAME_HAND = 1.0
# A calibration example is stored only when the hand held looks like the gesture asked for
# (robin_sim.live.hands.shape): its membership at least RESEMBLES on average over the held
# readings, or the asked gesture ahead of every other by CLEAR_LEAD. On the real footage each
# gesture scores 0.84-1.00 for itself and at most 0.07 for any other (tests/data/hands).
RESEMBLES = 0.5
CLEAR_LEAD = 0.2
KEEP = 4000  # readings kept for the summary's figures


@dataclass
class HandReading:
    """One reading and what became of it (a line of ``inputs.jsonl`` holds :meth:`as_dict`)."""

    seq: int
    found: bool
    label: str | None = None
    confidence: float = 0.0
    source: str = ""  # "shape" | "appearance" | "calibration"
    discarded: bool = False
    decided: str | None = None  # the gesture decided with this reading (HOLD in a row)
    cursor: tuple[float, float] | None = None
    dwell: float = 0.0  # 0..1: how far the pointing cursor's dwell has come
    acted: str = ""  # what the session did with it ("" nothing; else e.g. "gesture give_me")
    key: tuple[int, int] | None = None  # (handover, step) it acted in
    features: np.ndarray | None = field(default=None, repr=False)
    shape_scores: dict[str, float] | None = field(default=None, repr=False)  # calibrating
    latency_ms: float = 0.0

    def as_dict(self) -> dict[str, Any]:
        cursor = None if self.cursor is None else [round(v, 1) for v in self.cursor]
        return {
            "seq": self.seq,
            "found": self.found,
            "label": self.label,
            "confidence": round(self.confidence, 4),
            "source": self.source,
            "discarded": self.discarded,
            "decided": self.decided,
            "cursor": cursor,
            "dwell": round(self.dwell, 3),
            "acted": self.acted,
        }


class HandReader:
    """Reads a session's hand messages (see the module doc); ``width`` x ``height``: the scene
    frame the pointing cursor moves over."""

    def __init__(
        self,
        width: int,
        height: int,
        *,
        threshold: float = THRESHOLD,
        hold: int = HOLD,
        dwell_s: float = DWELL_S,
    ) -> None:
        self.width, self.height = width, height
        self.threshold, self.hold, self.dwell_s = threshold, hold, dwell_s
        self.appearance = Appearance()
        self.readings: deque[HandReading] = deque(maxlen=KEEP)
        self.count = self.found = self.discards = 0
        self.decisions = Counter[str]()
        self.confusion: dict[str, Counter[str]] = {}
        self.confirmed = self.corrected = self.relabelled = 0
        self.asking: str | None = None  # the gesture calibration asks for now
        self.calibrated = False
        self._calibration: list[str] = []
        self.calibration_note = ""  # why the last held hand was not taken ("" none)
        self._gap_until = 0.0
        self._run: list[HandReading] = []  # the current run of the same confident label
        self._latched: str | None = None  # decided and acted on; waits for the hand to change
        self._anchor: tuple[float, float, float] | None = None  # dwell: x, y, since
        self._pending: list[HandReading] = []  # corrected readings waiting for their right label
        self._by_seq: dict[int, HandReading] = {}

    # --- calibration ---------------------------------------------------------------------------
    def start_calibration(self, now: float) -> None:
        self._calibration = list(CALIBRATION_ORDER)
        self.asking, self._gap_until, self._run = self._calibration[0], now, []

    def skip_calibration(self) -> None:
        self._calibration, self.asking = [], None

    @property
    def calibrating(self) -> bool:
        return self.asking is not None

    def calibration_status(self) -> dict[str, Any]:
        done = [g for g in CALIBRATION_ORDER if g in self.appearance.seeded]
        return {
            "calibrating": self.calibrating,
            "asking": self.asking,
            "done": done,
            "calibrated": self.calibrated,
            "order": list(CALIBRATION_ORDER),
            "note": self.calibration_note,
        }

    def _calibrate(self, reading: HandReading, now: float) -> None:
        reading.source = "calibration"
        if now < self._gap_until or not reading.found or reading.features is None:
            self._run = []
            return
        self._run.append(reading)
        if len(self._run) < self.hold:
            return
        asked = self.asking
        assert asked is not None
        example = np.mean([r.features for r in self._run if r.features is not None], axis=0)
        for name, examples in self.appearance.examples.items():
            if name != asked and np.linalg.norm(examples[0] - example) < SAME_HAND:
                self.calibration_note = (
                    f"That looks like your {name.replace('_', ' ')}: show the "
                    f"{asked.replace('_', ' ')} instead."
                )
                self._run = []
                return
        seen = _looks_like(self._run, asked)
        if seen is not None:  # not the gesture asked for: ask again, saying what it was
            self.calibration_note = (
                f"That looks like a {_words(seen)}, not a {_words(asked)}: "
                f"show the {_words(asked)}, please."
            )
            self._run = []
            return
        self.calibration_note = ""
        self.appearance.seed(asked, example)
        reading.label, reading.acted = asked, f"calibration {asked}"
        self._calibration.pop(0)
        self._run, self._gap_until = [], now + CALIBRATION_GAP_S
        self.asking = self._calibration[0] if self._calibration else None
        self.calibrated = self.asking is None and len(self.appearance.seeded) >= 2

    # --- reading -------------------------------------------------------------------------------
    def read(self, hand: HandInput, now: float) -> HandReading:
        """Read one message received at ``now`` (monotonic s)."""
        self.count += 1
        reading = HandReading(self.count, hand.found)
        self._by_seq[reading.seq] = reading
        self.readings.append(reading)
        if len(self._by_seq) > KEEP:
            self._by_seq.pop(min(self._by_seq))
        if hand.points is None:
            self._run, self._anchor, self._latched = [], None, None
            if self.calibrating:
                reading.source = "calibration"
            return reading
        self.found += 1
        shape = normalised(hand.points, hand.handedness, hand.aspect)
        reading.features = features(shape)
        if self.calibrating:
            reading.shape_scores = memberships(shape)
            self._calibrate(reading, now)
            return reading
        if self.calibrated:
            label, certainty = self.appearance.predict(reading.features)
            reading.source = "appearance"
        else:
            label, certainty = read_shape(shape)
            reading.source = "shape"
        reading.label, reading.confidence = label, float(hand.score) * certainty
        if label is None or reading.confidence < self.threshold:
            reading.discarded = True
            self.discards += 1
            self._run, self._anchor = [], None
            return reading
        if self._run and self._run[-1].label != label:
            self._run = []
        if self._latched is not None and self._latched != label:
            self._latched = None
        self._run.append(reading)
        if label == POINTING_SIGN:
            self._point(reading, hand, now)
        elif len(self._run) >= self.hold and self._latched != label:
            reading.decided = label
        return reading

    def _point(self, reading: HandReading, hand: HandInput, now: float) -> None:
        assert hand.points is not None
        x, y = float(hand.points[INDEX_TIP, 0]), float(hand.points[INDEX_TIP, 1])
        span = 1.0 - 2 * CURSOR_MARGIN
        u = float(np.clip((1.0 - x - CURSOR_MARGIN) / span, 0.0, 1.0))  # mirrored: a self-view
        v = float(np.clip((y - CURSOR_MARGIN) / span, 0.0, 1.0))
        cursor = (min(u * self.width, self.width - 1.0), min(v * self.height, self.height - 1.0))
        reading.cursor = cursor
        anchor = self._anchor
        if anchor is None or np.hypot(cursor[0] - anchor[0], cursor[1] - anchor[1]) > DWELL_RADIUS:
            self._anchor = (cursor[0], cursor[1], now)
            return
        held = now - anchor[2]
        reading.dwell = min(1.0, held / self.dwell_s)
        if held >= self.dwell_s - 1e-6 and self._latched != POINTING_SIGN:
            reading.decided = POINTING_SIGN
            reading.cursor = (anchor[0], anchor[1])

    def acted(self, reading: HandReading, what: str, key: tuple[int, int] | None) -> None:
        """The session acted on ``reading``'s decision (``what``, e.g. "gesture give_me")."""
        reading.acted, reading.key = what, key
        assert reading.decided is not None
        self.decisions[reading.decided] += 1
        self._latched, self._run, self._anchor = reading.decided, [], None

    def missed(self, reading: HandReading) -> None:
        """The decision could not be acted on (pointing at nothing): start the dwell again."""
        self._anchor, self._run = None, []

    # --- learning from the participant's feedback ----------------------------------------------
    def settled(self, seq: int | None, gesture: str, key: tuple[int, int], approved: bool) -> None:
        """The learner has received the step made with ``gesture`` (by the reading ``seq``, or
        None for a click or key) in handover step ``key``: approved (thumb up or silence)
        confirms the reading; a correction keeps it until the right gesture is known."""
        reading = None if seq is None else self._by_seq.get(seq)
        self._pending = [r for r in self._pending if r.key == key]
        if not approved:
            if reading is not None and reading.features is not None:
                self._pending.append(reading)
                self.corrected += 1
            return
        for wrong in self._pending:  # the gesture the person made instead of the corrected one
            assert wrong.label is not None and wrong.features is not None
            self.confusion.setdefault(wrong.label, Counter())[gesture] += 1
            self.appearance.add(gesture, wrong.features)
            self.relabelled += wrong.label != gesture
        self._pending = []
        if reading is not None and reading.features is not None and reading.label is not None:
            self.confirmed += 1
            self.confusion.setdefault(reading.label, Counter())[gesture] += 1
            self.appearance.add(gesture, reading.features)

    # --- figures -------------------------------------------------------------------------------
    def summary(self) -> dict[str, Any]:
        """The summary's ``vision`` block for the webcam (see docs/webcam.md)."""
        latencies = [r.latency_ms for r in self.readings if r.found]
        judged = self.confirmed + self.corrected
        return {
            "source": "webcam",
            "readings": self.count,
            "hand_found": self.found,
            "hand_found_rate": self.found / self.count if self.count else None,
            "discarded": self.discards,
            "threshold": self.threshold,
            "decisions": dict(self.decisions),
            "confirmed": self.confirmed,
            "corrected": self.corrected,
            "relabelled": self.relabelled,
            "detection_rate": self.confirmed / judged if judged else None,
            "confusion": {k: dict(v) for k, v in self.confusion.items()},
            "calibrated": self.calibrated,
            "calibration": [g for g in CALIBRATION_ORDER if g in self.appearance.seeded],
            "examples": self.appearance.size,
            "latency_ms": None
            if not latencies
            else {
                "median": round(statistics.median(latencies), 3),
                "p95": round(float(np.percentile(latencies, 95)), 3),
            },
            "gestures": list(GESTURE_NAMES),
        }


def _words(gesture: str) -> str:
    return gesture.replace("_", " ")


def _looks_like(run: list[HandReading], asked: str) -> str | None:
    """None when the held readings look like ``asked`` (:data:`RESEMBLES`, :data:`CLEAR_LEAD`);
    else the gesture they look most like."""
    scores = [r.shape_scores for r in run if r.shape_scores is not None]
    if not scores:
        return None
    mean = {name: float(np.mean([s[name] for s in scores])) for name in scores[0]}
    others = max(v for k, v in mean.items() if k != asked)
    if mean[asked] >= RESEMBLES or mean[asked] - others >= CLEAR_LEAD:
        return None
    return max(mean, key=mean.__getitem__)
