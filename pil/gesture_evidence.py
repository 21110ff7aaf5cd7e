"""Which gesture an approved action means, by what the learner has learnt: labels for a reader
that adapts to the person (e.g. Robin's eye cameras with ``adapt``).

The gesture the robot *read* is poor evidence of the gesture the person *made*: PIL learns
whatever state a person's gesture is read as, so a gesture misread the same way again and
again gets its action learnt for the misread state, and the misread action is approved. The
learnt table holds better evidence. Where the last approved action was ``previous`` and the
hand is ``hand``, an approved ``action`` means the gesture whose state has approved that action
most consistently: the largest share of that state's approvals, at least :data:`MIN_SHARE`,
with at least :data:`MIN_COUNT` approvals, ahead of every other gesture's share by
:data:`MIN_LEAD`. Anything less is no evidence (None): early on, nothing is labelled.
"""

from __future__ import annotations

from pil.table import AssociationTable
from pil.types import GESTURES, Action, Gesture, Hand, State

MIN_SHARE = 0.5  # of the state's approvals that went to the action
MIN_COUNT = 2  # approvals of the action in that state
MIN_LEAD = 0.2  # share ahead of any other gesture's


def meant_gesture(
    table: AssociationTable, action: Action, previous: Action, hand: Hand
) -> Gesture | None:
    """The gesture an approved ``action`` means in context (see the module doc), or None."""
    shares: list[tuple[float, int, Gesture]] = []
    for gesture in GESTURES:
        counts = table.counts(State(gesture, previous, hand))
        total = sum(counts.values())
        if total:
            shares.append((counts[action] / total, counts[action], gesture))
    if not shares:
        return None
    shares.sort(key=lambda s: s[0], reverse=True)
    share, count, gesture = shares[0]
    runner_up = shares[1][0] if len(shares) > 1 else 0.0
    if share < MIN_SHARE or count < MIN_COUNT or share - runner_up < MIN_LEAD:
        return None
    return gesture
