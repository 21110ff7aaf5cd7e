"""The live session's observer of the step loop, and the steps kept for the experimenter."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from pil.task.records import StepRecord
from robin_sim.live.participant import LiveParticipant
from robin_sim.live.status import LiveStatus
from robin_sim.live.webcam import Webcam

TAIL_KEYS = (
    "t",
    "handover",
    "step",
    "true_gesture",
    "action",
    "target",
    "feedback",
    "delivered",
    "legs_delivered",
    "sim_time",
    "reason",
)


def tail_entry(entry: dict[str, Any]) -> dict[str, Any]:
    """What the experimenter's view shows of a logged step."""
    return {key: entry.get(key) for key in TAIL_KEYS}


class Booking:
    """The step loop's observer: the page's view, and each step logged and counted (``book``)
    as soon as the learner has its feedback (before the participant carries a delivered leg
    away); the webcam, if any, adapts to the participant then."""

    def __init__(
        self,
        view: LiveStatus,
        participant: LiveParticipant,
        webcam: Webcam | None,
        book: Callable[[StepRecord], None],
    ) -> None:
        self.view, self.participant, self.webcam, self.book = view, participant, webcam, book
        self.last: StepRecord | None = None  # the record booked last

    def decided(self, record: StepRecord) -> None:
        self.view.decided(record)
        self.participant.acting(record)

    def answered(self, record: StepRecord) -> None:
        self.view.answered(record)

    def received(self, record: StepRecord) -> None:
        self.last = record
        self.participant.received(record)
        if self.webcam is not None and not record.proactive:
            self.webcam.settled(self.participant, record.feedback)
        self.book(record)
