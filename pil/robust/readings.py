"""Which state the person was in: the reading, or another gesture of the same context.

The robot acts on the gesture it read, and a reading can be wrong: a misread gesture that is
still valid in the context (the paper's second cause of trouble, section I) makes the robot
act on the wrong state. :class:`Readings` weighs the context's valid states (same previous
action and hand) as the person's true state:

    P(true s' | read s) ∝ P(s' | last approved state) · P(read s | true s')

with P(s' | last approved state) the learnt transitions that the paper's correction reads
(section III-B; counts plus one), and P(read s | s') = 1 - m for s' = s and m / 3 otherwise
(a misread is one of the other three gestures; m is ``misread``). For a corrected gesture
(invalid or discarded reading) the reading says nothing and the transitions alone weigh the
states. The learner acts on the action most probably wanted under this mixture, so after the
reading's action is refused, what the context's other gestures mean comes next.

A signal is credited to the state the robot acted on, as PIL does. Crediting it instead to
the states by how likely each was the person's (with a misread rate learnt from it) was
tried on the development seeds: 5-8 actions fewer on the assembly at d = 0.4 and with silent
thumbs, but 6-10 more on the transfer and meaning-change tracks, where a gesture whose meaning
changed to another gesture's was taken for that gesture misread; it was left out.
"""

from __future__ import annotations

from collections.abc import Mapping

from pil.learner import SAME_CONTEXT, VALID_BY_ID
from pil.validity import ALL_STATES

OTHER_GESTURES = 3  # a misread gesture is one of the other three


class Readings:
    """The person's true state behind a reading (module docstring)."""

    def __init__(self, misread: float) -> None:
        self.misread = float(misread)

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
