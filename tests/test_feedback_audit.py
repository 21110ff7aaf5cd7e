"""The feedback channel audited: the person's thumb against how the verdict reached the robot,
and a discarded thumb asked again (``discarded_thumb=ask``) beside the default."""

from __future__ import annotations

import pytest

from pil.task.feedback_audit import confusion_columns, feedback_confusion, verdict_source
from pil.task.records import StepRecord
from pil.types import Action, Feedback, Gesture


def _record(feedback: Feedback, read: Feedback | None, interrupted: bool = False) -> StepRecord:
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
        action=Action.OBJECT,
        feedback=feedback,
        feedback_read=read,
        interrupted=interrupted,
    )


def test_each_verdict_is_counted_by_how_it_reached_the_robot() -> None:
    records = [
        _record(Feedback.OK, Feedback.OK),
        _record(Feedback.NOT_OK, Feedback.NONE),  # a refusal the classifier discarded: an OK
        _record(Feedback.NOT_OK, Feedback.NOT_OK, interrupted=True),  # stopped, never read
        _record(Feedback.NOT_OK, Feedback.NOT_OK),
        _record(Feedback.NONE, Feedback.NONE),
        _record(Feedback.OK, Feedback.NOT_OK),  # a misread thumb up
    ]
    found = feedback_confusion(records)
    assert found["ok"] == {"read_ok": 1, "read_not_ok": 1, "nothing_read": 0, "stopped_unread": 0}
    assert found["not_ok"] == {
        "read_ok": 0,
        "read_not_ok": 1,
        "nothing_read": 1,
        "stopped_unread": 1,
    }
    assert found["none"]["nothing_read"] == 1
    assert verdict_source(records[2]) == "stopped_unread"
    columns = confusion_columns(found)
    assert columns["feedback_not_ok_nothing_read"] == 1 and len(columns) == 12
    assert set(confusion_columns(None).values()) == {None}


@pytest.mark.slow
def test_a_discarded_thumb_is_asked_again_only_in_the_ask_variant() -> None:
    """In the dark (lighting 0) no eye finds the hand, so every thumb is discarded: the
    default takes it as no feedback after one reading, ``ask`` reads it twice more."""
    from robin_sim.person.body import PhysicalBody
    from robin_sim.render.gl_backend import ensure_gl_backend
    from robin_sim.robot.world import PhysicalWorld
    from robin_sim.vision.detector import ASK_AGAIN, VisionDetector

    ensure_gl_backend()
    world = PhysicalWorld()
    body = PhysicalBody(world)
    found = {}
    for mode in ("approve", "ask"):
        detector = VisionDetector(
            world.sim, display=body.display, seed=1, lighting=0.0, discarded_thumb=mode
        )
        heard = detector.read_feedback(Feedback.NOT_OK)
        summary = detector.summary()
        found[mode] = (heard, summary["feedback_read"], summary["thumbs_asked_again"])
        detector.close()
    assert found["approve"] == (Feedback.NONE, 1, 0)
    assert found["ask"] == (Feedback.NONE, 1 + ASK_AGAIN, ASK_AGAIN)
