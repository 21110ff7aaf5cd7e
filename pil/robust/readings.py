"""Which state the person was in: the reading, or another gesture of the same context.

The robot acts on the gesture it read, and a reading can be wrong: a misread gesture that is
still valid in the context (the paper's second cause of trouble, section I) makes the robot
act on the wrong state. :class:`Readings` weighs the context's valid states (same previous
action and hand) as the person's true state:

    P(true s' | read s) ∝ P(s' | last approved state) · P(read s | true s')

with P(s' | last approved state) the learnt transitions that the paper's correction reads
(section III-B; counts plus one), and P(read s | s') = 1 - m for s' = s and m / 3 otherwise
(a misread is one of the other three gestures). For a corrected gesture (invalid or
discarded reading) the reading says nothing and the transitions alone weigh the states.

The misread rate m starts at ``prior`` and is learnt: after each approval, the share of the
credit that went to another state than the reading (:meth:`Readings.credit`) counts as the
expected misreads of that approval (one EM step, the prior counting as ``PRIOR_WEIGHT``
approvals).

:meth:`Readings.credit` says which state a signal is about: with ``split`` on, the signal is
shared among the weighed states by how likely each was the person's given the signal (an OK
for an action is about the state whose right action it is), the reading's state keeping at
least ``READING_FLOOR`` of it: a gesture whose meaning changed to what another gesture of
the context means would otherwise be taken for that gesture misread, again and again (on
the development seeds the floor cost the assembly 1-3 actions and saved 7-15 on the
meaning-change and transfer tracks); off, the signal is the reading's.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from pil.learner import SAME_CONTEXT, VALID_BY_ID
from pil.validity import ALL_STATES

PRIOR_WEIGHT = 10.0  # the prior misread rate counts as this many approved readings
OTHER_GESTURES = 3  # a misread gesture is one of the other three
MIN_CREDIT = 1e-3  # shares below this are dropped from a credit
READING_FLOOR = 0.5  # the reading's state keeps at least this share of a signal


class Readings:
    """The person's true state behind a reading, and the misread rate (module docstring)."""

    def __init__(self, prior: float, split: bool = True) -> None:
        self.split = bool(split)
        self.expected = [float(prior) * PRIOR_WEIGHT, PRIOR_WEIGHT]  # misreads, approvals

    @property
    def misread(self) -> float:
        """The misread rate now (prior and the approvals so far)."""
        return self.expected[0] / self.expected[1]

    def weigh(self, sid: int, followers: Mapping[int, int], read: bool) -> dict[int, float]:
        """P(the person's state | the robot's state ``sid``): the context's valid states;
        ``followers`` are the transition counts from the last approved state, ``read`` False
        for a corrected state (the reading says nothing). An invalid ``sid`` is itself."""
        state = ALL_STATES[sid]
        context = SAME_CONTEXT[(state.previous_action, state.hand)]
        if not VALID_BY_ID[sid] or sid not in context:
            return {sid: 1.0}
        m = self.misread
        weights: dict[int, float] = {}
        for other in sorted(context):
            prior = followers.get(other, 0) + 1.0
            if read:
                prior *= 1.0 - m if other == sid else m / OTHER_GESTURES
            weights[other] = prior
        total = sum(weights.values())
        return {other: w / total for other, w in weights.items()}

    def credit(
        self,
        sid: int,
        weights: Mapping[int, float],
        p_right: Callable[[int], float],
        approved: bool,
    ) -> dict[int, float]:
        """The states a signal on an action in ``sid`` is about, with their shares;
        ``weights``: :meth:`weigh`'s for that choice, ``p_right(s)``: P(the action is right in
        s), ``approved``: the signal approves. An approval also updates the misread rate."""
        if not self.split or len(weights) < 2 or sid not in weights:
            return {sid: 1.0}
        shares = {
            other: w * (p_right(other) if approved else 1.0 - p_right(other))
            for other, w in weights.items()
        }
        total = sum(shares.values())
        if total <= 0.0:
            return {sid: 1.0}
        share = shares[sid] / total
        if share < READING_FLOOR:  # the others share the rest in their proportions
            rest = (1.0 - READING_FLOOR) / (total - shares[sid])
            shares = {o: READING_FLOOR if o == sid else s * rest for o, s in shares.items()}
        else:
            shares = {o: s / total for o, s in shares.items()}
        credit = {other: s for other, s in shares.items() if s > MIN_CREDIT}
        if approved:
            self.expected[0] += 1.0 - credit.get(sid, 0.0)
            self.expected[1] += 1.0
        return credit
