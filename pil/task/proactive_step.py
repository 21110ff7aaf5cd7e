"""The proactive robot's step: an action before the instruction's gesture, watched.

:func:`anticipate_step` is the step loop's (:mod:`pil.task.step_phases`) phase for a proactive
learner (``Learner(proactive=True)``, :mod:`pil.anticipation`): after an approved action, when
the learnt transitions make one next state likely enough, the robot performs that state's best
action while the person watches.
"""

from __future__ import annotations

from pil.anticipation import Anticipation
from pil.learner import Learner
from pil.task.detector import GestureReader
from pil.task.person import Person, ScriptStep
from pil.task.records import StepObserver, StepRecord
from pil.task.world import World
from pil.types import Action, Feedback, Hand

DELIVERY_FROM: tuple[Action, ...] = (Action.HUMAN, Action.LOCATION)  # an open then delivers


def anticipate_step(
    learner: Learner,
    person: Person,
    detector: GestureReader,
    world: World,
    item: ScriptStep,
    guess: Anticipation,
    t: int,
    gestures: int,
    legs: int,
    previous: Action,
    observer: StepObserver | None,
) -> StepRecord:
    """Perform ``guess`` before ``item``'s gesture while the person watches; its record.

    Nothing is pointed at (the world gets no target; :mod:`pil.anticipation` offers only a close
    or an open on a spot, done where the hand is); the person watches it as any action, meaning
    ``item``'s instruction, and stops it when it is not. The learner receives the feedback
    after the thumb, for the anticipated state; no gesture is performed or counted
    (``gesture_count`` stays).
    """
    intent, action, hand = item.intent, guess.action, world.hand()
    base = StepRecord(
        t=t,
        gesture_count=gestures,
        table=intent.table,
        handover=intent.handover,
        handover_type=item.handover_type,
        step=item.step,
        true_gesture=intent.gesture,
        detected_gesture=None,
        intended_action=intent.action,
        legs_delivered=legs,
        recovery=item.recovery,
        state=guess.state,
        action=action,
        exploited=True,
        reason=guess.reason,
        proactive=True,
    )
    watcher = person.watch(intent)  # a thumb is taken from the moment the action is shown
    if observer is not None:
        observer.decided(base)
    outcome = world.execute(action, None, watcher)
    feedback = person.judge(intent, action, outcome)
    if observer is not None:
        observer.answered(base._replace(feedback=feedback))
    person.show_feedback(feedback)
    heard = Feedback.NOT_OK if outcome.interrupted else detector.read_feedback(feedback)
    ok = heard is not Feedback.NOT_OK
    delivered = ok and action is Action.OPEN and previous in DELIVERY_FROM and hand is Hand.OCCUPIED
    record = base._replace(
        feedback=feedback,
        succeeded=outcome.succeeded,
        detail=outcome.detail,
        delivered=delivered,
        legs_delivered=legs + delivered,
        interrupted=outcome.interrupted,
        dropped=outcome.dropped,
        feedback_read=heard,
    )
    learner.feedback(guess.state, action, ok)
    if observer is not None:
        observer.received(record)
    person.after_feedback(feedback)
    return record
