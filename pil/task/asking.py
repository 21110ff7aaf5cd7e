"""When the robot cannot read the gesture: it proposes an action instead of asking again.

A gesture the detector discards again and again (a dim room, a hand the cameras never learnt),
or an invalid one the correction cannot mend (nothing learnt yet in this context), used to
leave the robot asking for it until the run gave up. After
:data:`pil.task.step_phases.ASK_AFTER_REPEATS` repeat requests in a row the loop asks
:func:`ask_unreadable` instead: the robot guesses the gesture among those valid in its context
(the paper's correction first, section III-B: the state that most often followed the last
approved one; then the states this context approved most often; then the task's order of
gestures, a different one on each ask) and performs that state's action. The person answers
with a thumb as for any action, so a wrong guess costs one refused action, never a dead end.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from pil.learner import Decision
from pil.table import AssociationTable, state_id
from pil.types import Action, Hand, State
from pil.validity import VALID_STATES


def context_states(previous: Action, hand: Hand) -> tuple[State, ...]:
    """The valid states whose previous action and hand are ``previous`` and ``hand``."""
    return tuple(s for s in VALID_STATES if (s.previous_action, s.hand) == (previous, hand))


def _approved(table: Any, state: State) -> int:
    if not isinstance(table, AssociationTable):
        return 0
    row = table.row(state_id(state))
    return 0 if row is None else sum(row)


def guesses(agent: Any, previous: Action, hand: Hand) -> list[State]:
    """The states to propose in this context, the likeliest first (module docstring)."""
    candidates = list(context_states(previous, hand))
    table = getattr(agent, "table", None)
    candidates.sort(key=lambda s: -_approved(table, s))  # stable: the task's order on ties
    correct = getattr(agent, "correct", None)
    if candidates and correct is not None:
        corrected = correct(candidates[0], getattr(agent, "last_ok_state", None))
        if corrected in candidates:
            candidates.remove(corrected)
            candidates.insert(0, corrected)
    return candidates


def ask_unreadable(
    agent: Any, unread: Decision, previous: Action, hand: Hand, attempt: int
) -> Decision:
    """A decision to act on a guessed state after repeated unreadable gestures (``unread``
    is the learner's request for a repeat; ``attempt`` counts the asks since a gesture was
    last read, from 0, so each ask proposes the next guess); ``unread`` itself where the
    context has no valid state (the loop grounds it first, so it always has one)."""
    options = guesses(agent, previous, hand)
    if not options:
        return unread
    state = options[attempt % len(options)]
    action = agent.choose(state)
    why = "discarded" if unread.detected_state is None else "not valid here"
    return replace(
        unread,
        state=state,
        action=action,
        corrected=True,
        exploited=False,
        confirm=getattr(agent, "last_confirm", False),
        reason=(
            f"cannot read the gesture ({why}, asked again and again); the robot proposes "
            f"{action.value} as for {state.gesture.value}: {agent.last_reason}"
        ),
    )
