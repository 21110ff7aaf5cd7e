"""Robin's state as the live participant's guide takes it: the step loop's bookkeeping, mirrored.

The step loop keeps the robot's last approved action and the hand it left
(:class:`pil.task.step_phases.LoopState`) and grounds them in the hand the world reports at
each safe point (:meth:`pil.task.step_phases.StepPhases.grounded`). :class:`RobinSeen` keeps
the same from the actions the participant lets stand (the live reader takes every thumb as
given) and grounds them by the loop's own rule (:func:`pil.task.grounding.ground`) at the same
safe point, so the guide asks for a gesture in the very state the loop decides in. A take-back
restores the state before an approval, as :meth:`~pil.task.step_phases.StepPhases.take_back`.
"""

from __future__ import annotations

from dataclasses import dataclass

from pil.task.grounding import ground
from pil.types import START_ACTION, START_HAND, Action, Hand, hand_after


@dataclass(slots=True)
class RobinSeen:
    """Robin's last standing action, the hand it left, and whether it was just let stand."""

    previous: Action = START_ACTION
    expected: Hand = START_HAND
    approved: bool = False  # the last action was let stand (a proactive robot may go first)
    hand_before: Hand = START_HAND  # the hand when the current action began

    def acts(self, hand: Hand) -> None:
        """Robin begins an action with ``hand``."""
        self.approved, self.hand_before = False, hand

    def approve(self, action: Action) -> tuple[Action, Hand]:
        """The participant let ``action`` stand; the state before it (for a take-back)."""
        before = self.previous, self.expected
        self.previous, self.expected = action, hand_after(action, self.hand_before)
        self.approved = True
        return before

    def restore(self, before: tuple[Action, Hand]) -> None:
        """An approval taken back: the state before it (grounded at the next safe point)."""
        self.previous, self.expected = before
        self.approved = False

    def ground(self, hand: Hand) -> str:
        """Ground the last action in ``hand`` (the loop's rule); why it changed ("": not)."""
        self.previous, why = ground(self.previous, self.expected, hand)
        self.expected = hand
        return why
