"""The proactive robot's rule: act on the next instruction before it is given.

After an approved action the table's transitions (the counts that the correction of section
III-B reads) give P(next state | last approved state). :func:`anticipate` reads them for the
states possible now (those with the robot's current previous action and hand) and, when one of
them has at least ``threshold`` of the probability on at least ``min_count`` observed
transitions, returns it with its best action by eq. 4 (a unique best; no anticipation on a tie).

The robot anticipates only what it can do without being shown anything: a close, and an open
on a table spot. An ``object`` or ``location`` needs the leg or spot the person points at, and
``human`` and an open after it need the person's palm (held out by the give-me gesture, brought
under the leg by the release gesture): a robot arriving before the palm would be in its way, so
for those it waits for the gesture.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from pil.table import AssociationTable
from pil.types import ACTIONS, Action, State
from pil.validity import ALL_STATES

DEFAULT_THRESHOLD = 0.8  # P(next state | state) at least this to act without the gesture
DEFAULT_MIN_COUNT = 3  # observed transitions from the state before the share is trusted
_NEEDS_THE_PERSON = frozenset({Action.OBJECT, Action.LOCATION, Action.HUMAN})


@dataclass(frozen=True, slots=True)
class Anticipation:
    """The state the robot expects next, the action it performs for it, and the evidence."""

    state: State
    action: Action
    share: float  # P(state | last approved state) among the states possible now
    evidence: int  # observed transitions to the states possible now

    @property
    def reason(self) -> str:
        """Why the robot acts now (for the log)."""
        return (
            f"anticipated {self.state.gesture.value} (P={self.share:.2f} of "
            f"{self.evidence}); best action"
        )


def can_anticipate(state: State, action: Action) -> bool:
    """True when ``action`` in ``state`` needs nothing shown by the person (module doc)."""
    if action in _NEEDS_THE_PERSON:
        return False
    return not (action is Action.OPEN and state.previous_action is Action.HUMAN)


def anticipate(
    table: AssociationTable,
    source: int,
    candidates: frozenset[int],
    threshold: float = DEFAULT_THRESHOLD,
    min_count: int = DEFAULT_MIN_COUNT,
) -> Anticipation | None:
    """The next state and its action when the transitions from ``source`` make it likely
    enough, else None.

    ``source`` is the id of the last approved state (``pil.table.START`` at the task start),
    ``candidates`` the ids of the states possible now (same previous action and hand).
    """
    followers: Mapping[int, int] = table.followers(source)
    seen = {sid: n for sid, n in followers.items() if sid in candidates and n > 0}
    evidence = sum(seen.values())
    if evidence < min_count:
        return None
    top = max(seen.values())
    tops = [sid for sid, n in seen.items() if n == top]
    share = top / evidence
    if len(tops) > 1 or share < threshold:
        return None
    sid = tops[0]
    best = table.best_id(sid)
    if best < 0:
        return None
    state, action = ALL_STATES[sid], ACTIONS[best]
    if not can_anticipate(state, action):
        return None
    return Anticipation(state, action, share, evidence)
