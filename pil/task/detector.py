"""A simulated gesture detector with detection rate d (section IV-A of the paper).

Each gesture the person performs is either read correctly or *missed*. A miss is either
discarded as low-confidence (the detector returns ``None``) or misclassified as another
gesture (uniformly among the other three, or as a given confusion matrix says).

Two models decide which gestures are read correctly:

* ``exact`` (the paper's): of every ``n`` consecutive gestures exactly ``round(d * n)`` are read
  correctly, the positions chosen at random. Implemented as a shuffled deck of ``n`` cards,
  refilled and reshuffled when used up; ``n`` is the run's scripted number of gestures.
* ``independent``: each gesture is read correctly with probability ``d``.

A third kind, :class:`MeasuredDetector` (``measured:FILE``), draws each reading from a measured
confusion row of the true gesture (read as each gesture, or discarded), e.g. the eye cameras'
held-out figures written by ``robin-pil train-gestures``.

The detector owns its seeded RNG, so its draws do not depend on anything else in the run.
"""

from __future__ import annotations

import functools
import random
from collections.abc import Sequence
from typing import Protocol, runtime_checkable

from pil.errors import RobinPilError
from pil.types import GESTURES, Feedback, Gesture

MODELS: tuple[str, ...] = ("exact", "independent")
CAMERAS = "vision"  # Robin reads with its eye cameras: physical runs only (robin_sim.vision)
NO_CAMERAS = (
    f"{CAMERAS!r} reads with Robin's eye cameras, which only physical runs have (robin-pil "
    "episode, robin-pil sweep --kind physical); learner-only runs take the cameras' errors as "
    "measured:FILE, an error model measured by vision episodes or train-gestures (e.g. "
    "robin_sim/vision/data/measured.json)"
)
DEFAULT_DISCARD = 0.5  # share of misses discarded as low-confidence; calibrated, see README
_INDEX = {g: i for i, g in enumerate(GESTURES)}


class GestureReader(Protocol):
    """What the step loop needs of whatever reads the person: the dice :class:`Detector`, a
    :class:`MeasuredDetector`, or Robin's eye cameras (``robin_sim.vision.detector``)."""

    rate: float

    def detect(self, gesture: Gesture) -> Gesture | None:
        """The gesture as read (None: discarded as low-confidence)."""
        ...

    def read_feedback(self, feedback: Feedback) -> Feedback:
        """The thumb as read."""
        ...


@runtime_checkable
class LearnsFromFeedback(Protocol):
    """A reader that learns from the robot's feedback, as the learner does (e.g. Robin's eye
    cameras with ``adapt``): told right after the learner whether the robot took its action as
    approved (its own reading of the thumb, or silence) and, for an approval, the gesture that
    action means by what the learner has learnt (:func:`pil.gesture_evidence.meant_gesture`;
    None: no such evidence yet). The person's own gesture never reaches it."""

    def verdict(self, meant: Gesture | None, approved: bool) -> None:
        """The robot's verdict on its last action, and what the action means if approved."""
        ...


class DetectorError(RobinPilError):
    """Invalid detector settings (rate, model, discard probability, confusion matrix)."""


def check_confusion(matrix: Sequence[Sequence[float]]) -> tuple[tuple[float, ...], ...]:
    """Validate a 4x4 confusion matrix (rows: true gesture, columns: read gesture, G order).

    Rows must sum to 1 and entries lie in [0, 1]. Only the off-diagonal entries matter: on a
    miss the read gesture is drawn from the row without its diagonal, renormalised, so every
    row needs some off-diagonal mass.
    """
    names = ", ".join(g.value for g in GESTURES)
    size = len(GESTURES)
    try:
        rows = tuple(tuple(float(x) for x in row) for row in matrix)
    except (TypeError, ValueError):
        raise DetectorError(f"confusion matrix must be {size}x{size} numbers ({names})") from None
    if len(rows) != size or any(len(row) != size for row in rows):
        raise DetectorError(f"confusion matrix must be {size}x{size} (rows/columns: {names})")
    for gesture, row in zip(GESTURES, rows, strict=True):
        if any(not 0.0 <= x <= 1.0 for x in row):
            raise DetectorError(f"confusion row {gesture.value!r}: entries must lie in [0, 1]")
        if abs(sum(row) - 1.0) > 1e-6:
            raise DetectorError(
                f"confusion row {gesture.value!r} sums to {sum(row):.6g}; each row must sum to 1"
            )
        if sum(row) - row[_INDEX[gesture]] <= 0.0:
            raise DetectorError(
                f"confusion row {gesture.value!r} has no off-diagonal mass: a miss of it "
                "could not be misread as another gesture"
            )
    return rows


class Detector:
    """Reads the person's gestures at detection rate ``rate``.

    ``rate``, ``model``, ``discard`` and ``confusion`` are run parameters, checked once where
    they enter (:func:`pil.task.spec.parse_run_spec`, the specs of :mod:`pil.task.params`) and
    taken here as given: build a checked one with ``assemble(parse_run_spec(...))``.
    """

    def __init__(
        self,
        rate: float,
        seed: int,
        *,
        model: str = "exact",
        deck_size: int = 100,
        discard: float = DEFAULT_DISCARD,
        confusion: Sequence[Sequence[float]] | None = None,
    ) -> None:
        self.rate = float(rate)
        self.model = model
        if isinstance(deck_size, bool) or not isinstance(deck_size, int) or deck_size < 1:
            raise DetectorError(f"deck size must be a whole number >= 1, got {deck_size!r}")
        self.deck_size = deck_size
        self.discard = float(discard)
        self._rng = random.Random(seed)
        self._deck: list[bool] = []
        self._misread: dict[Gesture, tuple[tuple[Gesture, ...], tuple[float, ...]]] = {}
        rows = None if confusion is None else tuple(tuple(row) for row in confusion)
        for i, gesture in enumerate(GESTURES):
            others = tuple(g for g in GESTURES if g is not gesture)
            if rows is None:
                weights = (1.0,) * len(others)
            else:
                weights = tuple(rows[i][_INDEX[g]] for g in others)
            self._misread[gesture] = (others, tuple(_cumulative(weights)))
        self.detected = 0  # gestures read correctly so far
        self.discarded = 0
        self.misread = 0

    def correct_next(self) -> bool:
        """Whether the next gesture is read correctly (consumes one card or one draw)."""
        if self.model == "independent":
            return self._rng.random() < self.rate
        if not self._deck:
            hits = round(self.rate * self.deck_size)
            self._deck = [True] * hits + [False] * (self.deck_size - hits)
            self._rng.shuffle(self._deck)
        return self._deck.pop()

    def read_feedback(self, feedback: Feedback) -> Feedback:
        """The thumb as the robot reads it: the study's detectors read thumbs right (the
        paper's feedback is never misread; a camera detector may misread it)."""
        return feedback

    def detect(self, gesture: Gesture) -> Gesture | None:
        """What the detector reads when the person performs ``gesture`` (None: discarded)."""
        if self.correct_next():
            self.detected += 1
            return gesture
        if self.discard and self._rng.random() < self.discard:
            self.discarded += 1
            return None
        self.misread += 1
        others, cumulative = self._misread[gesture]
        return self._rng.choices(others, cum_weights=cumulative)[0]


def _cumulative(weights: Sequence[float]) -> list[float]:
    total, out = 0.0, []
    for w in weights:
        total += w
        out.append(total)
    return out


# --- a detector with a measured error model (``--detector measured:FILE``) ---------------------
MEASURED_PREFIX = "measured:"


class MeasuredErrors:
    """A measured error model: per true gesture, the share read as each gesture or discarded.

    Read from the JSON file ``robin-pil train-gestures`` writes (``measured.json``): keys
    ``gestures`` (the four gesture names, in any order) and ``confusion`` (rows: true gesture;
    columns: read as each of ``gestures``, then discarded; each row sums to 1).
    """

    def __init__(self, rows: Sequence[Sequence[float]], order: Sequence[Gesture], source: str):
        by_gesture = dict(zip(order, rows, strict=True))
        self.rows = tuple(
            (*(float(by_gesture[g][order.index(h)]) for h in GESTURES), float(by_gesture[g][-1]))
            for g in GESTURES
        )  # G order; last column discarded
        self.source = source

    @property
    def rate(self) -> float:
        """Mean share of gestures read right (the detection rate d this model stands for)."""
        return sum(row[i] for i, row in enumerate(self.rows)) / len(GESTURES)

    @property
    def discard(self) -> float:
        """Mean share discarded."""
        return sum(row[-1] for row in self.rows) / len(GESTURES)


MAX_MEASURED_BYTES = 1_000_000  # a measured error model is a few hundred bytes


def load_measured(path: str) -> MeasuredErrors:
    """A measured error model file, read and checked once (by the parameter's parse, at the
    edge): the model of an unchanged file is reused (the study's runs, its measured rate).
    Any problem raises one :class:`DetectorError`."""
    import os

    try:
        stat = os.stat(path)
    except (OSError, ValueError):
        return read_measured(path)  # the file's problem, said once by its reader
    return _read_unchanged(str(path), stat.st_mtime_ns, stat.st_size, stat.st_ino)


@functools.lru_cache(maxsize=16)
def _read_unchanged(path: str, mtime_ns: int, size: int, inode: int) -> MeasuredErrors:
    """:func:`read_measured` of ``path`` as it is now (its size and times as given)."""
    return read_measured(path)


def read_measured(path: str) -> MeasuredErrors:
    """Read and check a measured error model file; any problem raises one
    :class:`DetectorError`."""
    import json
    from pathlib import Path

    from pil.regular_files import read_regular_text

    what = f"measured error model {path!r}"
    try:
        data = json.loads(read_regular_text(Path(path), MAX_MEASURED_BYTES))
    except FileNotFoundError:
        raise DetectorError(
            f"{what}: no such file (robin-pil train-gestures writes one: measured.json)"
        ) from None
    except (OSError, ValueError) as error:  # FileTooLargeError, UnicodeDecodeError: ValueErrors
        raise DetectorError(f"{what}: not readable JSON ({error})") from None
    valid = ", ".join(g.value for g in GESTURES)
    try:
        order = [Gesture(name) for name in data["gestures"]]
        rows = [[float(x) for x in row] for row in data["confusion"]]
    except (KeyError, TypeError, ValueError):
        raise DetectorError(
            f"{what}: needs 'gestures' (the four of {valid}) and 'confusion' (4 rows of 5 "
            "numbers: read as each gesture, then discarded)"
        ) from None
    if sorted(order, key=GESTURES.index) != list(GESTURES):
        raise DetectorError(f"{what}: 'gestures' must name each of {valid} once")
    if len(rows) != len(GESTURES) or any(len(row) != len(GESTURES) + 1 for row in rows):
        raise DetectorError(f"{what}: 'confusion' must be 4 rows of 5 numbers")
    for gesture, row in zip(order, rows, strict=True):
        if any(not 0.0 <= x <= 1.0 for x in row) or abs(sum(row) - 1.0) > 1e-3:
            raise DetectorError(
                f"{what}: row {gesture.value!r} must hold shares in [0, 1] summing to 1"
            )
    return MeasuredErrors(rows, order, str(path))


class MeasuredDetector:
    """Reads gestures as a measured error model says: each reading drawn from its true row."""

    def __init__(self, errors: MeasuredErrors, seed: int) -> None:
        self.errors = errors
        self.rate = errors.rate
        self._rng = random.Random(seed)
        self._cumulative = dict(zip(GESTURES, map(_cumulative, errors.rows), strict=True))
        self.detected = self.discarded = self.misread = 0

    def read_feedback(self, feedback: Feedback) -> Feedback:
        """Thumbs are read right (the measured file describes gestures only)."""
        return feedback

    def detect(self, gesture: Gesture) -> Gesture | None:
        """What the detector reads when the person performs ``gesture`` (None: discarded)."""
        choices = (*GESTURES, None)
        read = self._rng.choices(choices, cum_weights=self._cumulative[gesture])[0]
        if read is None:
            self.discarded += 1
        elif read is gesture:
            self.detected += 1
        else:
            self.misread += 1
        return read


def make_detector(
    model: str, rate: float, seed: int, **options: object
) -> Detector | MeasuredDetector:
    """A :class:`Detector` of ``model``, or for ``measured:FILE`` a :class:`MeasuredDetector`
    (the other options are then the file's business and ignored).

    With ``measured:FILE`` a ``rate`` of 1 still means perfect detection (the study's
    systems pre-trained at 100 %); any other rate stands for the file's measured one.
    """
    if isinstance(model, str) and model.startswith(MEASURED_PREFIX) and rate != 1.0:
        return MeasuredDetector(load_measured(model[len(MEASURED_PREFIX) :]), seed)
    if isinstance(model, str) and model.startswith(MEASURED_PREFIX):
        load_measured(model[len(MEASURED_PREFIX) :])  # a bad file fails here too
        model = "exact"
    return Detector(rate, seed, model=model, **options)  # type: ignore[arg-type]
