"""The agent protocol, and a base class for agents that act on the detected state as it is.

An :class:`Agent` is used through ``decide`` (one detected gesture: Algorithm 1, lines 3-15),
``choose`` (the next action within a step after a not-OK), ``feedback`` (the person's verdict),
``correct`` (a better state for an invalid one, or None), ``save``, and the attributes
``last_exploited``, ``last_reason`` and ``table`` (an :class:`AssociationTable` of what got OK
and not-OK, kept by every agent so that tables can be saved, shown and compared alike).
"""

from __future__ import annotations

import os
import random
from pathlib import Path
from typing import Protocol, runtime_checkable

from pil.errors import RobinPilError
from pil.learner import Decision
from pil.step_memory import StepMemory
from pil.table import START, AssociationTable, action_index, approves, state_id
from pil.table_io import save_table
from pil.types import Action, Feedback, Gesture, Hand, State
from pil.validity import ALL_STATES


@runtime_checkable
class Agent(Protocol):
    """What the step loop, the study and the environment need from a learner."""

    table: AssociationTable
    last_exploited: bool
    last_reason: str

    def decide(
        self, detected: Gesture | str | None, previous_action: Action | str, hand: Hand | str
    ) -> Decision:
        """What to do for one detected gesture (None: discarded by the detector)."""
        ...

    def choose(self, state: State) -> Action:
        """The next action to try in ``state`` within the current step."""
        ...

    def feedback(self, state: State, action: Action | str, ok: bool | Feedback | str) -> None:
        """The person's verdict on ``action`` in ``state`` (OK or no feedback approves)."""
        ...

    def correct(self, state: State, previous_state: State | None) -> State | None:
        """A valid state to act on instead of invalid ``state``, or None."""
        ...

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Save the agent's association table."""
        ...


class FeedbackAgent:
    """Base of the baselines: acts on the detected state as it is (no validity check, no
    correction), asks for a repeat of a discarded gesture, and records approvals, rejections
    and transitions in :attr:`table` like PIL does. ``step_memory`` (:mod:`pil.step_memory`,
    on by default: :data:`STEP_MEMORY_OWN`): within a step it never repeats an action the
    person refused until all five were refused; off, it chooses among all five. Subclasses
    implement :meth:`_pick` (given the actions allowed) and :meth:`_learn`.
    """

    name = "agent"
    STEP_MEMORY_OWN = True  # the baselines' own within-step memory setting

    def __init__(
        self,
        seed: int = 0,
        *,
        table: AssociationTable | None = None,
        step_memory: bool = STEP_MEMORY_OWN,
    ) -> None:
        if table is not None and not isinstance(table, AssociationTable):
            raise RobinPilError(
                f"table must be an AssociationTable (or None), got {type(table).__name__}"
            )
        self.seed = seed
        self.table = AssociationTable() if table is None else table
        self.last_exploited = False
        self.last_reason = ""
        self._rng = random.Random(seed)
        self._last_ok = START
        self._memory = StepMemory(step_memory)  # actions refused in this step

    def _pick(self, sid: int, allowed: list[int]) -> tuple[int, bool, str]:
        """Action index (one of ``allowed``), exploit?, reason for state id ``sid``."""
        raise NotImplementedError

    def _learn(self, sid: int, index: int, reward: float) -> None:
        """Update the estimates with ``reward`` (+1 OK, -1 not-OK) for ``index`` in ``sid``."""
        raise NotImplementedError

    def choose(self, state: State) -> Action:
        """The next action to try in ``state``."""
        sid = state_id(state)
        _refused, mask = self._memory.masks(sid)  # all five refused: the step starts over
        allowed = [i for i in range(len(_ACTIONS)) if mask >> i & 1]
        index, self.last_exploited, self.last_reason = self._pick(sid, allowed)
        return _ACTIONS[index]

    def decide(
        self, detected: Gesture | str | None, previous_action: Action | str, hand: Hand | str
    ) -> Decision:
        """Act on <detected, previous_action, hand>; a discarded gesture asks for a repeat."""
        if detected is None:
            return Decision(None, None, None, False, False, "discarded; no correction (repeat)")
        state = ALL_STATES[state_id(State(detected, previous_action, hand))]  # type: ignore[arg-type]
        action = self.choose(state)
        return Decision(state, state, action, False, self.last_exploited, self.last_reason)

    def feedback(self, state: State, action: Action | str, ok: bool | Feedback | str) -> None:
        """Learn from the verdict and record it in :attr:`table`."""
        sid, index = state_id(state), action_index(action)
        good = approves(ok)
        self._learn(sid, index, 1.0 if good else -1.0)
        if good:
            self.table.approve_id(sid, index)
            self.table.follow_id(self._last_ok, sid)
            self._last_ok = sid
            self._memory.clear()
        else:
            self.table.reject_id(sid, index)
            self._memory.refuse(sid, index)

    def correct(self, state: State, previous_state: State | None) -> State | None:
        """Baselines do not correct gestures."""
        return None

    def restart(self) -> None:
        """Back at the task start (the previous approved state is forgotten)."""
        self._last_ok = START
        self._memory.clear()

    @property
    def step_memory(self) -> bool:
        """Whether the within-step memory is on (:mod:`pil.step_memory`)."""
        return self._memory.on

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Save :attr:`table` (:func:`pil.save_table`)."""
        return save_table(self.table, path)


_ACTIONS = tuple(Action)
