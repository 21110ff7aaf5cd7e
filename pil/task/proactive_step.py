"""The proactive robot's step: an action before the instruction's gesture, watched.

:func:`anticipate_step` is the step loop's (:mod:`pil.task.step_phases`) phase for a proactive
learner (``Learner(proactive=True)``, :mod:`pil.anticipation`): after an approved action, when
the learnt transitions make one next state likely enough, the robot performs that state's best
action while the person watches (:func:`pil.task.watched_action.watched_action`).
"""

from __future__ import annotations

from pil.anticipation import Anticipation
from pil.task.records import StepRecord, item_record
from pil.task.script import ScriptStep
from pil.task.watched_action import StepParts, watched_action
from pil.types import Action


def anticipate_step(
    parts: StepParts,
    item: ScriptStep,
    guess: Anticipation,
    t: int,
    gestures: int,
    legs: int,
    previous: Action,
) -> StepRecord:
    """Perform ``guess`` before ``item``'s gesture while the person watches; its record.

    Nothing is pointed at (the world gets no target; :mod:`pil.anticipation` offers only a close
    or an open on a spot, done where the hand is); the person watches it as any action, meaning
    ``item``'s instruction, and stops it when it is not. The learner receives the feedback
    after the thumb, for the anticipated state; no gesture is performed or counted
    (``gesture_count`` stays).
    """
    hand = parts.world.hand()
    shown = item_record(item, t, gestures, legs)._replace(
        state=guess.state,
        action=guess.action,
        exploited=True,
        reason=guess.reason,
        proactive=True,
    )
    return watched_action(
        parts, item.intent, shown, hand, previous, exploited=True, reason=guess.reason
    )
