"""What a participant did in one recorded session, read from its files (pure Python).

* **Gesture latencies**: for every instruction gesture the session took (a click on a leg or
  spot, a gesture key), the simulated seconds since Robin last gave the turn back: the step
  logged before it (the learner had its feedback), a step handed back (``handed_back``,
  ``watchdog`` in ``events.jsonl``), or the session's start.
* **Judgements**: for every robot action begun (``acts``) that was logged, whether it was the
  one meant (``action`` against ``intended_action``), whether it moved the arm or only the
  fingers (close, open), the participant's first thumb after it began (``inputs.jsonl``) and
  its latency from that beginning, and whether the page refused it as too late (no action to
  judge any more: the feedback window had closed and silence had approved the action).
* **Hand examples**: the webcam's landmarks (21 x 3) of readings it labelled confidently, per
  gesture label, when the session had a webcam.

:func:`session_measures` gives the figures compared between recorded and simulated sessions,
from the same files: a simulated session (:mod:`robin_sim.fitted.session`) writes them
as a live session does.
"""

from __future__ import annotations

import bisect
import statistics
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

GESTURE_INPUTS = ("point", "gesture")
HAND_BACKS = ("handed_back", "watchdog")
FINGER_MOTIONS = ("close", "open")
LATE = "no robot action to judge"  # the page's refusal of a thumb after the window
EXAMPLE_CONFIDENCE = 0.6  # a webcam reading at least this sure is kept as an example
MAX_HAND_EXAMPLES = 12  # hand examples kept per gesture label


@dataclass(frozen=True)
class Judgement:
    """The participant's verdict on one robot action."""

    action: str
    wrong: bool  # not the action the participant meant
    fingers: bool  # a close or an open (no arm motion)
    thumb: str | None  # "up", "down" or None (silence)
    latency: float | None  # s from the action's beginning to the thumb
    late: bool  # the thumb came after the window (refused; silence approved)


@dataclass(frozen=True)
class Observed:
    """One session's behaviour (see the module doc)."""

    gesture_latencies: list[float]
    judgements: list[Judgement]
    hand_examples: dict[str, list[list[list[float]]]] = field(default_factory=dict)


def _time(row: Mapping[str, Any]) -> float | None:
    value = row.get("sim_time")
    return float(value) if isinstance(value, int | float) else None


def _raw(row: Mapping[str, Any]) -> Mapping[str, Any]:
    raw = row.get("raw")
    return raw if isinstance(raw, Mapping) else {}


def gesture_latencies(
    inputs: Sequence[Mapping[str, Any]],
    events: Sequence[Mapping[str, Any]],
    log: Sequence[Mapping[str, Any]],
) -> list[float]:
    """Sim s from Robin giving the turn back to each gesture the session took."""
    marks = [0.0]
    marks += [t for row in log if (t := _time(row)) is not None]
    marks += [t for e in events if e.get("event") in HAND_BACKS and (t := _time(e)) is not None]
    marks.sort()
    latencies = []
    for row in inputs:
        given = _time(row)
        if not row.get("accepted") or _raw(row).get("type") not in GESTURE_INPUTS or given is None:
            continue
        before = marks[bisect.bisect_right(marks, given) - 1]
        latencies.append(round(given - before, 4))
    return latencies


def judgements(
    inputs: Sequence[Mapping[str, Any]],
    events: Sequence[Mapping[str, Any]],
    log: Sequence[Mapping[str, Any]],
) -> list[Judgement]:
    """Each logged robot action with the participant's first thumb after it began."""
    acts = [(t, e) for e in events if e.get("event") == "acts" and (t := _time(e)) is not None]
    acts.sort(key=lambda pair: pair[0])
    starts = [t for t, _ in acts]
    thumbs: dict[int, tuple[str, float, bool]] = {}  # index into acts -> first thumb
    for row in inputs:
        raw, given = _raw(row), _time(row)
        if raw.get("type") != "thumb" or given is None:
            continue
        late = not row.get("accepted")
        if late and LATE not in str(row.get("error", "")).lower():
            continue  # refused for another reason (the session over): no verdict
        index = bisect.bisect_right(starts, given) - 1
        if index >= 0 and index not in thumbs:
            thumbs[index] = (str(raw.get("value")), given - starts[index], late)
    steps = {row.get("t"): row for row in log if row.get("action") is not None}
    found = []
    for index, (_, event) in enumerate(acts):
        step = steps.get(event.get("t"))
        if step is None:
            continue  # begun and never logged (the session ended during it)
        action = str(step["action"])
        thumb = thumbs.get(index)
        found.append(
            Judgement(
                action=action,
                wrong=action != step.get("intended_action"),
                fingers=action in FINGER_MOTIONS,
                thumb=None if thumb is None else thumb[0],
                latency=None if thumb is None else round(thumb[1], 4),
                late=thumb is not None and thumb[2],
            )
        )
    return found


def hand_examples(inputs: Sequence[Mapping[str, Any]]) -> dict[str, list[list[list[float]]]]:
    """The webcam's confident readings' landmarks per gesture label (at most
    :data:`MAX_HAND_EXAMPLES` each)."""
    examples: dict[str, list[list[list[float]]]] = {}
    for row in inputs:
        raw, reading = _raw(row), row.get("reading")
        if raw.get("type") != "hand" or not isinstance(reading, Mapping):
            continue
        label, marks = reading.get("label"), raw.get("landmarks")
        sure = float(reading.get("confidence") or 0.0) >= EXAMPLE_CONFIDENCE
        if not label or not sure or reading.get("discarded") or not isinstance(marks, list):
            continue
        kept = examples.setdefault(str(label), [])
        if len(kept) < MAX_HAND_EXAMPLES:
            kept.append([[round(float(v), 4) for v in point] for point in marks])
    return examples


def observe(
    inputs: Sequence[Mapping[str, Any]],
    events: Sequence[Mapping[str, Any]],
    log: Sequence[Mapping[str, Any]],
) -> Observed:
    """One session's behaviour from its three line files."""
    return Observed(
        gesture_latencies(inputs, events, log),
        judgements(inputs, events, log),
        hand_examples(inputs),
    )


def _share(hits: int, total: int) -> float | None:
    return None if total == 0 else round(hits / total, 4)


def session_measures(summary: Mapping[str, Any], observed: Observed) -> dict[str, Any]:
    """The figures a recorded and a simulated session are compared on (None: not defined)."""
    tables = summary.get("tables") or 1
    wrong = [j for j in observed.judgements if j.wrong]
    right = [j for j in observed.judgements if not j.wrong]
    latencies = observed.gesture_latencies
    return {
        "status": summary.get("status"),
        "actions": summary.get("actions"),
        "gestures": summary.get("gestures"),
        "rejected": summary.get("rejected"),
        "legs_delivered": summary.get("legs_delivered"),
        "time_per_table_s": round(float(summary.get("sim_time_s") or 0.0) / tables, 3),
        "gesture_latency_median_s": round(statistics.median(latencies), 3) if latencies else None,
        "thumb_down_on_wrong": _share(
            sum(j.thumb == "down" and not j.late for j in wrong), len(wrong)
        ),
        "silence_on_right": _share(sum(j.thumb is None or j.late for j in right), len(right)),
    }


COMPARED_MEASURES: dict[str, str] = {
    "actions": "robot actions",
    "gestures": "instruction gestures",
    "rejected": "rejected actions",
    "time_per_table_s": "time per table (sim s)",
    "gesture_latency_median_s": "median gesture latency (s)",
    "thumb_down_on_wrong": "thumb down on a wrong action (share)",
    "silence_on_right": "silence on a right action (share)",
}
