"""What a run's step records cost: actions, gestures, the per-table curve, failure and stall.

:func:`count` walks the step loop's records (:func:`pil.task.runner.steps`) and stops the run
as failed when actions or gestures pass the cap, or when the loop gives up on a gesture. Apart
from failure it measures the longest wait: the most gestures of the person in a row that got
no action of the robot (records with ``action`` None are repeat requests). A run is *stalled*
when that wait reaches ``stall_after`` (the suite's ``stalled``, K): the robot stopped acting
for K gestures, whether or not the run later finished. :func:`curve_of`, :func:`curve_area`
and :func:`recovery` turn a :class:`Played` into the tracks' own measures.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

from pil.task.records import StepRecord
from pil.task.runner import RunnerError
from pil.types import Feedback


class _CappedError(Exception):
    """The run passed its cap of actions."""


@dataclass
class Played:
    """What one script cost: totals, per-table actions, the longest wait, the records' key
    facts."""

    actions: int = 0
    gestures: int = 0
    rejected: int = 0
    failed: str = ""
    longest_wait: int = 0  # the most gestures in a row without a robot action
    stalled: bool = False  # longest_wait reached the stall threshold K
    per_table: dict[int, int] = field(default_factory=dict)
    # (table, handover, step, gesture, first action of the instruction approved?) per action
    events: list[tuple[int, int, int, str, bool, int]] = field(default_factory=list)


def count(records: Iterable[StepRecord], limit: float, stall_after: int | None = None) -> Played:
    """What a run's records cost; stop (failed) when actions or gestures pass ``limit``.
    ``stall_after``: K, the gestures in a row without an action that make the run stalled
    (None: the longest wait is measured, no run is called stalled)."""
    out = Played()
    seen: set[tuple[int, int, bool]] = set()
    acted_at = 0  # the gesture count when the robot last acted
    try:
        for record in records:
            out.gestures = record.gesture_count
            if record.action is None:
                out.longest_wait = max(out.longest_wait, record.gesture_count - acted_at)
            else:
                acted_at = record.gesture_count
            if record.gesture_count > limit:
                raise _CappedError
            if record.action is None:
                continue
            out.actions = record.t
            out.per_table[record.table] = out.per_table.get(record.table, 0) + 1
            out.rejected += record.feedback is Feedback.NOT_OK
            key = (record.handover, record.step, record.recovery)
            first = key not in seen
            seen.add(key)
            ok = record.feedback is not Feedback.NOT_OK
            out.events.append(
                (
                    record.table,
                    record.handover,
                    record.step,
                    record.true_gesture.value,
                    first and ok,
                    record.t,
                )
            )
            if record.t > limit:
                raise _CappedError
    except _CappedError:
        out.failed = f"passed the cap of {limit:g} actions or gestures"
    except RunnerError as error:
        out.failed = str(error)
    out.stalled = stall_after is not None and out.longest_wait >= stall_after
    return out


def curve_of(played: Played, tables: int) -> list[int]:
    """Actions per table (0 for a table the run never reached)."""
    return [played.per_table.get(k, 0) for k in range(tables)]


def curve_area(curve: Sequence[float]) -> float:
    """The trapezoid area under the per-table actions curve over the unit interval (its mean
    height, in actions per table, whatever the number of tables)."""
    if len(curve) < 2:
        return float(curve[0]) if curve else math.nan
    return sum((a + b) / 2 for a, b in itertools.pairwise(curve)) / (len(curve) - 1)


def recovery(played: Played, from_table: int, gesture: str, criterion: int) -> float:
    """Actions from the change until ``criterion`` instructions with ``gesture`` in a row had
    their first action approved (NaN: never)."""
    start, streak, done = None, 0, set()
    for table, handover, step, true, first_ok, t in played.events:
        if table < from_table:
            continue
        if start is None:
            start = t - 1
        if true != gesture or (handover, step) in done:
            continue
        done.add((handover, step))
        streak = streak + 1 if first_ok else 0
        if streak >= criterion:
            return float(t - start)
    return math.nan
