"""The within-step memory: one option, shared by every learner (PIL, bandit, TAMER).

A *step* is one instruction: it lasts until the person approves an action. With the memory
on, an action the person refused in a state during this step is not chosen again in that
state until all five actions were refused there; then the memory of that state starts over
(so that every step can end). With it off, the learner's own rule alone decides what comes
next: PIL's exploration rule (:mod:`pil.exploration`), the bandit's and TAMER's greedy
choice over all five actions.

:class:`StepMemory` is the one implementation: it records the refusals of the step (PIL's
rules read them whatever the setting, to rank the learnt actions) and gives the mask of the
actions a learner may choose. :data:`STEP_MEMORY` names the choices of the ``step_memory``
run parameter; its default, ``per-learner``, is each learner's setting from before the option
existed (off for PIL, on for the bandit and TAMER), so older seeded results are unchanged.
"""

from __future__ import annotations

from pil.errors import InvalidChoiceError
from pil.types import ACTIONS

ALL_ACTIONS = (1 << len(ACTIONS)) - 1  # the mask of all five actions
PER_LEARNER = "per-learner"
STEP_MEMORY: dict[str, str] = {
    PER_LEARNER: "each learner's own: off for PIL, on for the bandit and TAMER",
    "on": "a refused action is not chosen again in this step until all five were refused",
    "off": "the learner's own rule alone chooses (PIL's exploration rule; the baselines "
    "choose among all five)",
}
DEFAULT_STEP_MEMORY = PER_LEARNER


def step_memory_on(choice: str, own: bool) -> bool:
    """Whether the memory is on for a learner whose own setting is ``own``."""
    if choice not in STEP_MEMORY:
        raise InvalidChoiceError("step_memory", choice, STEP_MEMORY)
    return own if choice == PER_LEARNER else choice == "on"


class StepMemory:
    """The actions refused in each state since the last approval (bit masks by state id)."""

    def __init__(self, on: bool) -> None:
        self.on = bool(on)
        self._refused: dict[int, int] = {}

    def refused(self, sid: int) -> int:
        """The mask of the actions refused in state ``sid`` in this step."""
        return self._refused.get(sid, 0)

    def masks(self, sid: int) -> tuple[int, int]:
        """Before a choice in ``sid``: (refused, allowed) masks. All five refused: the state's
        memory starts over. ``allowed`` is every action with the memory off, else the ones
        not refused in this step."""
        refused = self._refused.get(sid, 0)
        if refused == ALL_ACTIONS:
            refused = self._refused[sid] = 0
        return refused, ALL_ACTIONS & ~refused if self.on else ALL_ACTIONS

    def refuse(self, sid: int, index: int) -> None:
        """The person refused action ``index`` in state ``sid``."""
        self._refused[sid] = self._refused.get(sid, 0) | 1 << index

    def clear(self) -> None:
        """The step ended (an approval) or the task restarted."""
        self._refused.clear()
