"""What the learner loop needs from whatever executes the robot's actions.

The same loop (:mod:`pil.task.runner`) drives a :class:`SymbolicWorld` (learner-only study) and the
physical robot (``robin_sim.robot.world.PhysicalWorld``). A world executes one action for one of the
person's intents and reports what physically happened; the learner's hand state is always read
from the world, never kept as a flag by the loop.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from pil.types import Action, Gesture, Hand


@dataclass(frozen=True, slots=True)
class Target:
    """What the person points at: leg ``index`` ("leg") or table spot ``index`` ("spot").

    Indices are within the current table's layout; the physical world maps them to positions.
    """

    kind: str  # "leg" or "spot"
    index: int


@dataclass(frozen=True, slots=True)
class Intent:
    """What the person means by the gesture now performed."""

    gesture: Gesture  # the gesture really performed (the detector may read another)
    action: Action  # the action the person wants (the correct association T_c)
    target: Target | None  # the leg or spot pointed at; None when nothing is indicated
    handover: int  # 0-based index of the leg being handed over in the whole assembly
    table: int  # 0-based index of the table being assembled


@dataclass(frozen=True, slots=True)
class Outcome:
    """What executing an action did physically."""

    succeeded: bool  # the action achieved its purpose (e.g. the grasp holds the leg)
    detail: str = ""  # why not, or a measurement worth logging
    undone: bool = False  # the world was returned to its state before the action


class World(Protocol):
    """Executes the robot's actions; symbolic in the study, MuJoCo in an episode."""

    def hand(self) -> Hand:
        """The hand state as the world sees it (from physics, for the physical robot)."""
        ...

    def execute(self, action: Action, intent: Intent, wanted: bool) -> Outcome:
        """Perform ``action``.

        ``wanted`` says whether it is the action the person means. An unwanted action is shown
        to the person (far enough for them to reject it) and then undone, so that the world is
        back in its state before the call (``Outcome.undone`` is True). A wanted action is
        completed; if it fails physically the world undoes it too and says why.
        """
        ...

    def start_table(self, table: int) -> None:
        """A new table's legs are laid out (called before its first handover)."""
        ...


class SymbolicWorld:
    """A world in which every wanted action succeeds; the hand follows close and open."""

    def __init__(self) -> None:
        self._hand = Hand.FREE

    def hand(self) -> Hand:
        """Occupied after a wanted close, free after a wanted open."""
        return self._hand

    def execute(self, action: Action, intent: Intent, wanted: bool) -> Outcome:
        """Apply a wanted action's effect on the hand; an unwanted one changes nothing."""
        if not wanted:
            return Outcome(succeeded=True, undone=True)
        if action is Action.CLOSE:
            self._hand = Hand.OCCUPIED
        elif action is Action.OPEN:
            self._hand = Hand.FREE
        return Outcome(succeeded=True)

    def start_table(self, table: int) -> None:
        """Nothing to lay out symbolically."""
