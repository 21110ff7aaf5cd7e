"""The record of one event of the step loop (:func:`pil.task.runner.steps`).

An executed action, or a request to the person to repeat the gesture (``action`` None). The
study counts records (:mod:`pil.task.counting`), an episode logs and renders them. Every record
of the loop starts from its script item (:func:`item_record`).
"""

from __future__ import annotations

from typing import Any, NamedTuple, Protocol

from pil.task.script import ScriptStep
from pil.task.world import Target
from pil.types import Action, Feedback, Gesture, State


class StepRecord(NamedTuple):
    """One event of the loop (immutable). ``action`` None: the robot asks for a repeat.

    Built with keywords: one base record per performed gesture, updated per action.
    """

    t: int  # robot actions so far, this one included (Table I's step t)
    gesture_count: int  # instruction gestures performed so far, this one included
    table: int  # 0-based table
    handover: int  # 0-based handover (leg) in the whole run
    handover_type: str
    step: int  # 0-based gesture index within the handover
    true_gesture: Gesture
    detected_gesture: Gesture | None  # None: discarded as low-confidence
    intended_action: Action
    legs_delivered: int
    corrected_gesture: Gesture | None = None  # set when the learner corrected the state
    state: State | None = None  # the state acted on (None for a repeat request)
    action: Action | None = None
    feedback: Feedback | None = None
    succeeded: bool | None = None  # what the world reported (None: no action)
    detail: str = ""
    delivered: bool = False  # Algorithm 1, line 19: this approved open delivered a leg
    exploited: bool = False
    reason: str = ""
    target: Target | None = None  # the leg or spot the person indicates (None: nothing)
    recovery: bool = False  # an instruction the person added to have a dropped leg picked up
    interrupted: bool = False  # the person stopped the action while it ran (or at its end)
    dropped: int | None = None  # a leg that left the robot's hand during the action
    feedback_read: Feedback | None = None  # the thumb as the robot read it (what it learnt)
    proactive: bool = False  # performed before the gesture, on the learnt transitions
    confirm: bool = False  # the robot asks for an explicit thumb on this action (pil.robust)

    @property
    def state_key(self) -> str | None:
        """The acted-on state as its text key, e.g. ``"pointing|open|free"``."""
        return None if self.state is None else self.state.key()

    @property
    def is_repeat(self) -> bool:
        """True for a repeat request (no action executed)."""
        return self.action is None

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready values (enums as the paper's names, the state as its key)."""
        out = self._asdict()
        out["state"] = self.state_key
        target = self.target
        out["target"] = None if target is None else {"kind": target.kind, "index": target.index}
        for key, value in out.items():
            if isinstance(value, (Gesture, Action, Feedback)):
                out[key] = value.value
        return out


def item_record(
    item: ScriptStep,
    t: int,
    gestures: int,
    legs: int,
    detected: Gesture | None = None,
    target: Target | None = None,
) -> StepRecord:
    """The base record of one event for script ``item``: its instruction (``item.intent``)
    and place in the script, the counts so far (``t`` actions, ``gestures``, ``legs``
    delivered), the gesture as ``detected`` and the ``target`` pointed at (None: no gesture
    read, nothing pointed at)."""
    intent = item.intent
    return StepRecord(
        t=t,
        gesture_count=gestures,
        table=intent.table,
        handover=intent.handover,
        handover_type=item.handover_type,
        step=item.step,
        true_gesture=intent.gesture,
        detected_gesture=detected,
        intended_action=intent.action,
        legs_delivered=legs,
        target=target,
        recovery=item.recovery,
    )


class StepObserver(Protocol):
    """Presentation of the loop (e.g. a video overlay); it must not act in the world."""

    def decided(self, record: StepRecord) -> None:
        """The robot is about to act on ``record`` (no feedback or outcome yet)."""
        ...

    def answered(self, record: StepRecord) -> None:
        """The person is about to show ``record.feedback``."""
        ...

    def received(self, record: StepRecord) -> None:
        """The learner has received ``record``'s feedback (the step is complete; a delivered
        leg is in the person's hand, before they carry it away)."""
        ...
