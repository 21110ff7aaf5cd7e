"""One action the person watches, from the moment it is shown to the feedback learnt.

:func:`watched_action` is the step loop's one home for an executed action, whether the robot
acts on a gesture (:meth:`pil.task.step_phases.StepPhases.acting`) or before it
(:func:`pil.task.proactive_step.anticipate_step`). In the order things happen: the person
watches (a thumb is taken from the moment the action is shown), the observer learns the
decision, the world executes, the person judges, the observer learns the answer, the person
shows the thumb, the robot reads it, the learner (and a reader that learns from feedback)
receives it, the observer gets the complete record and the person does what follows the thumb.
The robot never knows the verdict before the person gives it.
"""

from __future__ import annotations

from dataclasses import dataclass

from pil.gesture_evidence import meant_gesture
from pil.learner import Learner
from pil.table import AssociationTable
from pil.task.detector import GestureReader, LearnsFromFeedback
from pil.task.person import Person
from pil.task.records import StepObserver, StepRecord
from pil.task.world import Intent, World
from pil.types import Action, Feedback, Gesture, Hand, State

DELIVERY_FROM: tuple[Action, ...] = (Action.HUMAN, Action.LOCATION)  # an open then delivers


@dataclass(frozen=True, slots=True)
class StepParts:
    """What the loop acts with: the learner, the person, the reader, the world and the
    observer (None: nobody presents the loop)."""

    learner: Learner
    person: Person
    detector: GestureReader
    world: World
    observer: StepObserver | None


def watched_action(
    parts: StepParts,
    intent: Intent,
    shown: StepRecord,
    hand: Hand,
    previous: Action,
    *,
    exploited: bool,
    reason: str,
    confirm: bool = False,
) -> StepRecord:
    """Execute ``shown.action`` on ``shown.target`` while the person watches; its record.

    ``shown`` is the action as shown (its ``t``, ``state``, ``action`` and ``target``; the
    person means ``intent``); ``exploited`` and ``reason`` say why the robot chose it: the
    observer's decided record and the returned one carry them, the answered record is
    ``shown`` with the feedback. ``hand`` and ``previous`` are the robot's hand and last
    approved action before it (an approved open from a handing action delivers a leg,
    counted on ``shown.legs_delivered``). A reader that learns from feedback
    (:class:`LearnsFromFeedback`) is told the verdict on a gesture's action, not on a
    proactive one (``shown.proactive``: no gesture was read). ``confirm``: the robot asks for
    an explicit thumb on this action (the decided record says so, for a page to show); a
    person or reader with ``confirm_requested`` is told before the action runs (:func:`ask`).
    """
    learner, person, detector = parts.learner, parts.person, parts.detector
    observer = parts.observer
    learnt, action = shown.state, shown.action
    assert learnt is not None and action is not None
    decided = shown._replace(exploited=exploited, reason=reason, confirm=confirm)
    if confirm:
        ask(person, detector)
    watcher = person.watch(intent)  # a thumb is taken from the moment the action is shown
    if observer is not None:
        observer.decided(decided)
    outcome = parts.world.execute(action, shown.target, watcher)
    feedback = person.judge(intent, action, outcome)
    if observer is not None:
        observer.answered(shown._replace(feedback=feedback))
    person.show_feedback(feedback)
    # What the robot sees of the thumb: it stopped a stopped action because it saw the thumb
    # go down; the thumb after an action that ran to its end is read.
    heard = Feedback.NOT_OK if outcome.interrupted else detector.read_feedback(feedback)
    ok = heard is not Feedback.NOT_OK  # no feedback counts as OK (eq. 1)
    delivered = ok and action is Action.OPEN and previous in DELIVERY_FROM and hand is Hand.OCCUPIED
    record = decided._replace(
        feedback=feedback,
        succeeded=outcome.succeeded,
        detail=outcome.detail,
        delivered=delivered,
        legs_delivered=shown.legs_delivered + delivered,
        interrupted=outcome.interrupted,
        dropped=outcome.dropped,
        feedback_read=heard,
    )
    learner.feedback(learnt, action, heard)  # what the robot read (silence: NONE, eq. 1)
    if not shown.proactive and isinstance(detector, LearnsFromFeedback):
        detector.verdict(meant_by_table(learner, action, learnt) if ok else None, ok)
    if observer is not None:
        observer.received(record)
    person.after_feedback(feedback)  # e.g. a delivered leg carried to the bin
    return record


def ask(*listeners: object) -> None:
    """The robot asks for an explicit thumb on the action about to run: each listener with a
    ``confirm_requested()`` (the scripted person, who then never stays silent; the bench's
    :class:`pil.bench.noise.FeedbackChannel`, whose silence and late thumbs then do not apply)
    is told. A live page reads the request from the decided record (``confirm``)."""
    for listener in listeners:
        told = getattr(listener, "confirm_requested", None)
        if told is not None:
            told()


def meant_by_table(learner: Learner, action: Action, state: State) -> Gesture | None:
    """The gesture an approved ``action`` means by the learner's table (None: a learner
    without one, or no evidence yet)."""
    table = getattr(learner, "table", None)
    if not isinstance(table, AssociationTable):
        return None
    return meant_gesture(table, action, state.previous_action, state.hand)
