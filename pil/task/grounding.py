"""Where the robot stands: its last action and its hand, grounded in what the world says.

The state's context <previous action, hand> is the robot's last approved action and what its
hand holds now. Right approvals only ever reach the five contexts of
:data:`pil.validity.REACHABLE_CONTEXTS`. Two things reach the others:

* physics changed the hand (a leg dropped, or caught): the hand is not the one the approved
  action left;
* a wrong approval: a wrong move let stand (silence counts as OK, eq. 1), a thumb down that was
  missed, misread or came late, e.g. an empty hand moved to the person and approved.

In the paper's simulation neither happens; with real teachers both do. Trusting the approval
then leaves every gesture invalid in that context, and the correction (which keeps the context)
has nothing to offer: the robot would ask for the gesture forever. Instead the robot trusts its
hand: an empty hand stands as after an open (the start of a handover), a full one as after a
close (just grasped). From there every gesture of the task has a valid state.
"""

from __future__ import annotations

from pil.types import Action, Hand
from pil.validity import GROUNDED_ACTION, REACHABLE_CONTEXTS

AFTER_DROP = GROUNDED_ACTION  # the name the step loop and the live page have used


def is_reachable(previous: Action, hand: Hand) -> bool:
    """True if right approvals can leave the robot with ``previous`` and ``hand``."""
    return (previous, hand) in REACHABLE_CONTEXTS


def ground(previous: Action, expected: Hand, hand: Hand) -> tuple[Action, str]:
    """The last action the next state takes, and why it changed ("" when it did not).

    ``previous`` is the last approved action, ``expected`` the hand it left and ``hand`` the
    hand the world reports now.
    """
    if hand is not expected:
        return GROUNDED_ACTION[hand], (
            f"re-grounded: the hand is {hand.value} where the approved {previous.value} left "
            f"it {expected.value}; the robot stands as after {GROUNDED_ACTION[hand].value}"
        )
    if not is_reachable(previous, hand):
        return GROUNDED_ACTION[hand], (
            f"re-grounded: <{previous.value}, {hand.value}> follows no right approval (one was "
            f"wrong); the robot stands as after {GROUNDED_ACTION[hand].value}"
        )
    return previous, ""
