"""The live page shows the robust rule's request for a thumb (StepRecord.confirm)."""

from __future__ import annotations

from pil.task.records import StepRecord
from pil.types import Action, Gesture, Hand, State
from robin_sim.live.config import LiveConfig
from robin_sim.live.status import ASKS_FOR_A_THUMB, LiveStatus


def record(confirm: bool) -> StepRecord:
    return StepRecord(
        t=1,
        gesture_count=1,
        table=0,
        handover=0,
        handover_type="A",
        step=0,
        true_gesture=Gesture.POINTING,
        detected_gesture=Gesture.POINTING,
        intended_action=Action.OBJECT,
        legs_delivered=0,
        state=State(Gesture.POINTING, Action.OPEN, Hand.FREE),
        action=Action.OBJECT,
        confirm=confirm,
    )


def test_an_action_the_robot_is_unsure_of_asks_the_participant_for_a_thumb() -> None:
    for confirm in (True, False):
        status = LiveStatus(LiveConfig(video=False))
        status.decided(record(confirm))
        doing = status.status(None, None)["robot_doing"]
        assert (ASKS_FOR_A_THUMB in doing) is confirm, doing
