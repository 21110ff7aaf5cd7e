"""Which states <gesture, previous action, hand> can occur in the table-leg handover task.

A state is *invalid* when the detected gesture asks for something physically impossible or
redundant (grasp with a full hand), or when the pair (previous action, hand) cannot be reached in
this task. The learner never acts on an invalid state once it has learnt something: it corrects
the gesture (section III-B of the paper) or asks the person to repeat it.

The one rule table, :data:`RULES` ("any" matches everything); each row says why such a state
cannot happen:

=========================  =======  ======================  ========
rule                       gesture  previous action         hand
=========================  =======  ======================  ========
grasp while occupied       grasp    any                     occupied
release while free         release  any                     free
give me while free         give me  any                     free
occupied after open        any      open                    occupied
free after close           any      close                   free
free at human or location  any      human, location         free
occupied at object         any      object                  occupied
grasp away from a leg      grasp    open, close, human,     any
                                    location
=========================  =======  ======================  ========

* grasp while occupied: the hand already holds a leg and cannot grasp a second one.
* release while free: there is nothing in the hand to let go of.
* give me while free: there is nothing in the hand to pass to the person.
* occupied after open: an approved open always empties the hand, so the pair is unreachable.
* free after close: in this task a close that got OK always grasped a leg (unreachable).
* free at human or location: the robot only moves to the person or a spot holding a leg.
* occupied at object: the robot only approaches a leg with an empty hand.
* grasp away from a leg: grasping needs the hand at a leg, i.e. the previous action object.

"grasp while occupied" is implied by the last two rules but comes first so that the reason
given is the paper's.

The four context rules (occupied after open, free after close, free at human or location,
occupied at object) are **assumptions**: they hold only while every approval was right. A wrong
action let stand (silence, a missed, late or misread thumb, a participant who lets a wrong move
stand) or a leg that physics took away reaches such a context all the same. Such a context is
evidence that an approval was wrong, not a wall: :mod:`pil.task.grounding` then re-grounds the
robot's last action in its hand's real state (:data:`REACHABLE_CONTEXTS` holds the others).

Twelve of the 40 states are valid: with a free hand <pointing, open>,
<pointing, object> and <grasp, object>; with an occupied hand pointing, give me or release
after close, human or location. Every state of Table I is among them, and the misdetection of
Table I, t = 21, <grasp, human, occupied>, is invalid.
"""

from __future__ import annotations

from dataclasses import dataclass

from pil.types import ACTIONS, GESTURES, HAND_AFTER, HANDS, Action, Gesture, Hand, State


@dataclass(frozen=True, slots=True)
class Rule:
    """One rule: states matching all given fields are invalid (``None`` matches anything)."""

    name: str
    gestures: frozenset[Gesture] | None
    previous_actions: frozenset[Action] | None
    hands: frozenset[Hand] | None
    reason: str

    def matches(self, state: State) -> bool:
        """True if ``state`` breaks this rule."""
        return (
            (self.gestures is None or state.gesture in self.gestures)
            and (self.previous_actions is None or state.previous_action in self.previous_actions)
            and (self.hands is None or state.hand in self.hands)
        )


def _other_hand(hand: Hand) -> Hand:
    return Hand.FREE if hand is Hand.OCCUPIED else Hand.OCCUPIED


_OCCUPIED = frozenset({Hand.OCCUPIED})
_FREE = frozenset({Hand.FREE})

RULES: tuple[Rule, ...] = (
    Rule(
        "grasp while occupied",
        frozenset({Gesture.GRASP}),
        None,
        _OCCUPIED,
        "the hand already holds a leg and cannot grasp a second one",
    ),
    Rule(
        "release while free",
        frozenset({Gesture.RELEASE}),
        None,
        _FREE,
        "the hand holds nothing to let go of",
    ),
    Rule(
        "give me while free",
        frozenset({Gesture.GIVE_ME}),
        None,
        _FREE,
        "the hand holds nothing to hand over",
    ),
    # An approved close fills the hand and an approved open empties it (pil.types.HAND_AFTER),
    # so the other hand state cannot follow either.
    *(
        Rule(
            f"{_other_hand(left)} after {action}",
            None,
            frozenset({action}),
            frozenset({_other_hand(left)}),
            f"an approved {action} always leaves the hand {left} in this task",
        )
        for action, left in (
            (Action.OPEN, HAND_AFTER[Action.OPEN]),
            (Action.CLOSE, HAND_AFTER[Action.CLOSE]),
        )
    ),
    Rule(
        "free at human or location",
        None,
        frozenset({Action.HUMAN, Action.LOCATION}),
        _FREE,
        "the robot only goes to the person or a spot while holding a leg",
    ),
    Rule(
        "occupied at object",
        None,
        frozenset({Action.OBJECT}),
        _OCCUPIED,
        "the robot only approaches a leg with an empty hand",
    ),
    Rule(
        "grasp away from a leg",
        frozenset({Gesture.GRASP}),
        frozenset(a for a in ACTIONS if a is not Action.OBJECT),
        None,
        "the hand is not at a leg, so there is nothing to grasp",
    ),
)

ALL_STATES: tuple[State, ...] = tuple(
    State(g, a, h) for g in GESTURES for a in ACTIONS for h in HANDS
)

_BROKEN: dict[State, tuple[Rule, ...]] = {
    s: tuple(rule for rule in RULES if rule.matches(s)) for s in ALL_STATES
}
VALID_STATES: tuple[State, ...] = tuple(s for s in ALL_STATES if not _BROKEN[s])
# The contexts <previous action, hand> some valid state has: those right approvals reach.
REACHABLE_CONTEXTS: frozenset[tuple[Action, Hand]] = frozenset(
    (s.previous_action, s.hand) for s in VALID_STATES
)
# The last action a state takes when the approved one does not fit the hand (a drop, or a
# wrong approval): an empty hand is open, as at the start; a full one has closed on its leg.
GROUNDED_ACTION: dict[Hand, Action] = {Hand.FREE: Action.OPEN, Hand.OCCUPIED: Action.CLOSE}


def broken_rules(state: State | str) -> tuple[Rule, ...]:
    """The rules ``state`` breaks, in table order (empty for a valid state).

    ``state`` may also be a key such as ``"grasp|human|occupied"``.
    """
    found = _BROKEN.get(state)  # type: ignore[arg-type]
    if found is not None:
        return found
    if isinstance(state, str):
        return _BROKEN[State.from_key(state)]
    raise TypeError(f"expected a State, got {state!r}")


def is_valid(state: State | str) -> bool:
    """True if ``state`` can occur in the handover task."""
    return not broken_rules(state)


def why_invalid(state: State | str) -> str | None:
    """``"<rule>: <reason>"`` for the first rule ``state`` breaks, or None if it is valid."""
    rules = broken_rules(state)
    if not rules:
        return None
    return f"{rules[0].name}: {rules[0].reason}"
