"""An episode's running totals and per-handover figures, for ``summary.json``.

The counts shared with the study come from :class:`pil.task.counting.RunStats` (one place
counts). On top, what only physics tells, in the spirit of human-to-robot handover benchmarks
(HandoverSim): per handover whether it succeeded and how long it took from its first gesture to
the delivering open, timeouts, drops, actions the person stopped, person interventions, and
robot-person contacts.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from typing import Any

from pil.task.counting import RunStats
from pil.task.feedback_audit import TRUE_NAME, feedback_confusion, verdict_source
from pil.task.records import StepRecord
from pil.types import Action


@dataclass
class Handover:
    """One handover (one leg) as it went."""

    handover: int
    table: int
    type: str
    started_s: float  # sim time of its first gesture
    delivered: bool = False
    to: str | None = None  # "person" or "spot"
    seconds: float | None = None  # first gesture to the end of the delivering open
    actions: int = 0
    gestures: int = 0
    interrupted: int = 0
    drops: int = 0


@dataclass
class EpisodeTotals:
    """Running totals for the summary: the study's counts plus what only physics tells."""

    counts: RunStats = field(default_factory=RunStats)
    legs_to_person: int = 0
    legs_placed: int = 0
    physical_failures: int = 0
    render_checks: int = 0
    render_disagreements: int = 0
    handovers: list[Handover] = field(default_factory=list)
    timeout_s: float = 180.0  # s from a handover's first gesture (param handover_timeout)
    # the person's feedback against how the verdict reached the robot (pil.task.feedback_audit)
    feedback: dict[str, dict[str, int]] = field(default_factory=lambda: feedback_confusion(()))

    def add(
        self, record: StepRecord, entry: Mapping[str, Any], gesture_started: float, ended: float
    ) -> None:
        """Count ``record`` (its log ``entry``); ``gesture_started`` is the sim time its gesture
        began, ``ended`` the sim time its action ended."""
        first_gestures = record.gesture_count != self.counts.gestures
        self.counts.add(record)
        if not self.handovers or self.handovers[-1].handover != record.handover:
            self.handovers.append(
                Handover(record.handover, record.table, record.handover_type, gesture_started)
            )
        now = self.handovers[-1]
        now.gestures += first_gestures
        check = entry.get("render_check")
        if check is not None:
            self.render_checks += 1
            self.render_disagreements += not check["agrees"]
        if record.action is None:
            return
        if record.feedback is not None:
            self.feedback[TRUE_NAME[record.feedback]][verdict_source(record)] += 1
        now.actions += 1
        now.interrupted += record.interrupted
        now.drops += record.dropped is not None
        meant = record.action is record.intended_action  # a failure of what the person wanted
        self.physical_failures += record.succeeded is False and meant and not record.interrupted
        if record.delivered:
            to_person = record.state is not None and record.state.previous_action is Action.HUMAN
            self.legs_to_person += to_person
            self.legs_placed += not to_person
            now.delivered, now.to = True, "person" if to_person else "spot"
            now.seconds = round(ended - now.started_s, 3)

    def as_summary(self, person_contacts: int, interventions: int, now: float) -> dict[str, Any]:
        """The summary's count fields (the study's names, legs as ``legs_delivered``); ``now``
        is the sim time (an undelivered handover older than the timeout counts as one)."""
        c = self.counts
        done = [h for h in self.handovers if h.delivered]
        took = [now - h.started_s if h.seconds is None else h.seconds for h in self.handovers]
        timeouts = sum(t > self.timeout_s for t in took)
        times = [h.seconds for h in done if h.seconds is not None]
        return {
            "gestures": c.gestures,
            "actions": c.actions,
            "rejected": c.rejected,
            "corrections": c.corrections,
            "repeats": c.repeats,
            "misdetections": c.misdetections,
            "discarded": c.discarded,
            "legs_delivered": c.legs,  # Algorithm 1's count (handed over or placed)
            "legs_to_person": self.legs_to_person,
            "legs_placed": self.legs_placed,
            "physical_failures": self.physical_failures,
            "interrupted_actions": c.interrupted,
            "anticipated_actions": c.anticipated,  # proactive: performed before the gesture
            "anticipated_ok": c.anticipated_ok,  # of them let happen (a gesture saved each)
            "drops": c.drops,
            "recovery_gestures": c.recoveries,
            "person_interventions": interventions,
            "person_contacts": person_contacts,
            "timeouts": timeouts,
            "handover_timeout_s": self.timeout_s,
            "handover_success_rate": round(len(done) / len(self.handovers), 4)
            if self.handovers
            else None,
            "mean_handover_s": round(sum(times) / len(times), 3) if times else None,
            "render_checks": self.render_checks,
            "render_disagreements": self.render_disagreements,
            "feedback_confusion": self.feedback,
            "handovers": [asdict(h) for h in self.handovers],
        }
