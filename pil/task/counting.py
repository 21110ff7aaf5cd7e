"""What a run cost and achieved, counted from its step records: the one place that counts.

:class:`RunStats` is filled record by record (:meth:`RunStats.add`) by the learner-only study
(:func:`pil.task.runner.run`) and the physical episode alike, so that "gestures", "actions",
"repeats" and the rest mean the same in a study's CSV and an episode's summary (the counting of
Figs. 3 and 4: a repeated gesture counts again; rejected actions count).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from pil.task.records import StepRecord
from pil.task.script import ScriptStep
from pil.types import Feedback


@dataclass(slots=True)
class RunStats:
    """The study's counts; :meth:`add` each record of :func:`pil.task.runner.steps` in order."""

    gestures: int = 0  # instruction gestures performed, repeats included
    actions: int = 0  # robot actions executed, rejected ones included
    rejected: int = 0  # actions that got not-OK
    corrections: int = 0  # states corrected by the learner (section III-B)
    repeats: int = 0  # gestures performed again (robot asked, manual repetition, patience)
    misdetections: int = 0  # gestures read wrong or discarded
    discarded: int = 0
    exploited: int = 0  # actions chosen as the unique best (eq. 4)
    legs: int = 0  # legs delivered
    handovers: int = 0  # handovers in the script
    scripted_gestures: int = 0  # gestures the script needs when every one is read right
    interrupted: int = 0  # actions the person stopped with a thumb down (physical worlds)
    drops: int = 0  # actions during which a held leg left the robot's hand
    recoveries: int = 0  # instructions the person added to have a dropped leg picked up
    anticipated: int = 0  # actions performed before the instruction's gesture (proactive)
    anticipated_ok: int = 0  # of them let happen: a gesture the person did not perform
    _last_step: tuple[int, int, bool] | None = field(default=None, repr=False)

    @classmethod
    def for_script(cls, script: Sequence[ScriptStep]) -> RunStats:
        """Empty counts for a run of ``script``."""
        handovers = len({item.intent.handover for item in script})
        return cls(handovers=handovers, scripted_gestures=len(script))

    def add(self, record: StepRecord) -> None:
        """Count one record (a gesture's first record counts the gesture)."""
        if record.gesture_count != self.gestures:
            self.gestures = record.gesture_count
            step = (record.handover, record.step, record.recovery)
            self.repeats += step == self._last_step
            self.recoveries += record.recovery and step != self._last_step
            self._last_step = step
            if record.detected_gesture is not record.true_gesture:
                self.misdetections += 1
                self.discarded += record.detected_gesture is None
            if record.corrected_gesture is not None:
                self.corrections += 1
        self.legs = record.legs_delivered
        if record.action is None:
            return
        self.actions = record.t
        self.rejected += record.feedback is Feedback.NOT_OK
        self.exploited += record.exploited
        self.interrupted += record.interrupted
        self.drops += record.dropped is not None
        if record.proactive:
            self.anticipated += 1
            self.anticipated_ok += record.feedback is not Feedback.NOT_OK

    def as_dict(self) -> dict[str, int]:
        """The counts by name."""
        return {name: getattr(self, name) for name in self.__slots__ if not name.startswith("_")}
