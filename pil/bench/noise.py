"""The detector and teacher suite: how a condition of the suite file reads gestures and thumbs.

* ``independent``: each gesture read right with probability d (:class:`pil.task.detector.Detector`);
  a miss is discarded with the study's share (0.5), else misread as one of the other three.
* ``measured``: each reading drawn from the eye cameras' measured confusion row
  (:class:`pil.task.detector.MeasuredDetector`).
* ``markov``: :class:`MarkovReader`, a two-state chain per person (Gilbert-Elliott): in the
  good state a gesture is read right with probability ``good``, in the bad state ``bad``; the
  chain enters the bad state with probability ``enter_bad`` and leaves it with ``leave_bad``
  per gesture, so errors come in bursts and each person's bursts are their own.

:class:`FeedbackChannel` wraps any reader and changes the thumbs between the person and the
robot: ``silence`` (the person gives no thumb; the robot takes silence as OK, eq. 1),
``misread`` (the opposite thumb), ``missed`` (a thumb given but not seen: silence),
``late`` (the thumb comes after the robot moved on: it is silent now and lands on the next
action instead), or ``measured`` (each thumb read by the eye cameras' measured thumb confusion;
a discarded thumb is silence). The thumb down that stops a wrong action passes through the
same noise (:meth:`FeedbackChannel.read_stop`): a stop the robot does not get lets the action
run on, taken as approved. Every draw comes from the condition's own seeded generator.

When the robot asks for a thumb on an action (:meth:`FeedbackChannel.confirm_requested`, a
robust learner's ``confirm``), the person answers and the robot waits for the answer: for that
action's thumb ``silence`` and ``late`` do not apply (their draws are still made, so asking
changes no other draw); ``misread``, ``missed`` and ``measured`` do (the reading can still
fail). A stop the robot did not get is then answered after the action (drawn again).
"""

from __future__ import annotations

import functools
import random
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pil.regular_files import UnreadableFileError, read_json_file
from pil.task.detector import (
    DEFAULT_DISCARD,
    Detector,
    GestureReader,
    MeasuredDetector,
    load_measured,
)
from pil.types import GESTURES, Feedback, Gesture

_OTHERS = {g: tuple(h for h in GESTURES if h is not g) for g in GESTURES}


class MarkovReader:
    """Bursty, per-person correlated misreadings (see the module docstring)."""

    def __init__(self, params: Mapping[str, float], seed: int) -> None:
        self.good, self.bad = float(params["good"]), float(params["bad"])
        self.enter, self.leave = float(params["enter_bad"]), float(params["leave_bad"])
        self._rng = random.Random(seed)
        self._bad: dict[int, bool] = {}
        self.person = 0
        share = self.enter / (self.enter + self.leave) if self.enter + self.leave else 0.0
        self.rate = (1 - share) * self.good + share * self.bad  # the stationary detection rate

    def set_person(self, person: int) -> None:
        """The person now gesturing (each has a chain of their own)."""
        self.person = person

    def detect(self, gesture: Gesture) -> Gesture | None:
        """Advance this person's chain one gesture and read ``gesture`` in its state."""
        bad = self._bad.get(self.person, False)
        bad = self._rng.random() >= self.leave if bad else self._rng.random() < self.enter
        self._bad[self.person] = bad
        if self._rng.random() < (self.bad if bad else self.good):
            return gesture
        if self._rng.random() < DEFAULT_DISCARD:
            return None
        return self._rng.choice(_OTHERS[gesture])

    def read_feedback(self, feedback: Feedback) -> Feedback:
        """Thumbs are read right (a :class:`FeedbackChannel` changes them)."""
        return feedback


def thumb_rows(path: str) -> dict[Feedback, tuple[float, float, float]]:
    """The measured thumb confusion of ``path`` (a ``measured.json``): true OK / not-OK ->
    (read OK, read not-OK, discarded), read once per version of the file through the guarded
    reader; :class:`~pil.regular_files.UnreadableFileError` naming it when it is not one."""
    import os

    try:
        found = os.stat(path)
    except OSError:
        return _thumb_rows(path, 0, -1, 0)  # the reader says what is wrong
    return _thumb_rows(path, found.st_mtime_ns, found.st_size, found.st_ino)


@functools.lru_cache(maxsize=16)
def _thumb_rows(
    path: str, mtime_ns: int, size: int, inode: int
) -> dict[Feedback, tuple[float, float, float]]:
    data = read_json_file(Path(path), "settings", "the measured thumbs", finite=True)
    names = {"OK": Feedback.OK, "not OK": Feedback.NOT_OK}
    rows = data.get("feedback_confusion") if isinstance(data, dict) else None
    order = data.get("feedback") if isinstance(data, dict) else None
    if (
        not isinstance(order, list)
        or sorted(map(str, order)) != sorted(names)
        or not isinstance(rows, list)
        or len(rows) != len(order)
        or not all(_shares(row) for row in rows)
    ):
        raise UnreadableFileError(
            f"{path}: the measured thumbs need 'feedback' (OK and not OK) and "
            "'feedback_confusion' (a row of 3 shares summing to 1 for each: read OK, read not "
            "OK, discarded)"
        )
    return {
        names[n]: (float(r[0]), float(r[1]), float(r[2])) for n, r in zip(order, rows, strict=True)
    }


def _shares(row: Any) -> bool:
    return (
        isinstance(row, list)
        and len(row) == 3
        and all(type(x) in (int, float) and 0.0 <= x <= 1.0 for x in row)
        and abs(sum(row) - 1.0) <= 1e-3
    )


class FeedbackChannel:
    """A gesture reader whose thumbs pass through the teacher's noise (module docstring)."""

    def __init__(self, inner: Any, params: Mapping[str, Any], seed: int) -> None:
        self.inner = inner
        self.rate = inner.rate
        self.silence = float(params.get("silence", 0.0))
        self.misread = float(params.get("misread", 0.0))
        self.missed = float(params.get("missed", 0.0))
        self.late = float(params.get("late", 0.0))
        measured = params.get("measured")
        self._rows = None if measured is None else thumb_rows(str(measured))
        self._rng = random.Random(seed)
        self._pending: Feedback | None = None
        self._held: Feedback | None = None
        self._asked = False  # the robot asked for a thumb on the action now running
        self.counts = {"silenced": 0, "misread": 0, "missed": 0, "late": 0}

    def detect(self, gesture: Gesture) -> Gesture | None:
        """The inner reader's reading."""
        return self.inner.detect(gesture)

    def set_person(self, person: int) -> None:
        """Passed on to a per-person reader."""
        if hasattr(self.inner, "set_person"):
            self.inner.set_person(person)

    def read_stop(self) -> Feedback:
        """The thumb down that stops a running action, as the robot gets it; when the robot
        does not get it, the action runs on and this reading is the action's thumb."""
        heard = self._through(Feedback.NOT_OK)
        if heard is not Feedback.NOT_OK:
            self._held = heard
        return heard

    def confirm_requested(self) -> None:
        """The robot asks for a thumb on the action about to run (module docstring)."""
        self._asked = True

    def read_feedback(self, feedback: Feedback) -> Feedback:
        """The thumb as the robot gets it for this action."""
        asked, self._asked = self._asked, False
        if self._held is not None:  # the stop it did not get: already drawn
            held, self._held = self._held, None
            if not (asked and held is Feedback.NONE):
                return held
        return self._through(feedback, asked)

    def _through(self, feedback: Feedback, asked: bool = False) -> Feedback:
        given = self.inner.read_feedback(feedback)
        rng = self._rng
        if self.silence and rng.random() < self.silence and not asked:
            self.counts["silenced"] += 1
            given = Feedback.NONE
        elif self.misread and given is not Feedback.NONE and rng.random() < self.misread:
            self.counts["misread"] += 1
            given = Feedback.OK if given is Feedback.NOT_OK else Feedback.NOT_OK
        if self._pending is not None:  # a late thumb lands on this action instead
            given, self._pending = self._pending, None
        elif self.late and given is not Feedback.NONE and rng.random() < self.late and not asked:
            self.counts["late"] += 1
            self._pending, given = given, Feedback.NONE
        if self.missed and given is not Feedback.NONE and rng.random() < self.missed:
            self.counts["missed"] += 1
            given = Feedback.NONE
        if self._rows is not None and given is not Feedback.NONE:
            ok, not_ok, _gone = self._rows[given]
            draw = rng.random()
            given = (
                Feedback.OK
                if draw < ok
                else Feedback.NOT_OK
                if draw < ok + not_ok
                else Feedback.NONE
            )
        return given


def make_reader(condition: Any, seed: int, deck_size: int) -> GestureReader:
    """The gesture reader (with its feedback channel) of a suite condition."""
    spec = condition.gestures
    model = spec["model"]
    inner: Any
    if model == "independent":
        inner = Detector(float(spec["rate"]), seed, model="independent", deck_size=deck_size)
    elif model == "measured":
        inner = MeasuredDetector(load_measured(str(spec["file"])), seed)
    elif model == "markov":
        inner = MarkovReader(spec, seed)
    else:
        from pil.bench.suite import SuiteError

        raise SuiteError(f"condition {condition.name!r} reads with the eye cameras: physical only")
    if not condition.feedback:
        return inner
    return FeedbackChannel(inner, condition.feedback, seed ^ 0x5EED)
