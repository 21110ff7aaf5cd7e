"""What the learner loop needs from whatever executes the robot's actions.

The same loop (:mod:`pil.task.runner`) drives a :class:`SymbolicWorld` (learner-only study)
and the physical robot (``robin_sim.robot.world.PhysicalWorld``). A world executes one action
on the leg or spot the person indicated and reports what physically happened; the learner's
hand state is always read from the world, never kept as a flag by the loop.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from pil.types import Action, Gesture, Hand, hand_after


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
    """Executes the robot's actions; symbolic in the study, MuJoCo in an episode.

    The world acts for the robot only: it is told the action and the leg or spot it concerns,
    never what the person wants it to be. The person (:mod:`pil.task.person`) acts in it too.
    """

    def hand(self) -> Hand:
        """The hand state as the world sees it (from physics, for the physical robot)."""
        ...

    def execute(self, action: Action, target: Target | None, wanted: bool) -> Outcome:
        """Perform ``action`` on ``target`` (the leg or spot the person indicated, if any).

        ``wanted`` says whether the person means this action. An unwanted action is shown far
        enough for the person to reject it and then undone, so that the world is back in its
        state before the call (``Outcome.undone`` is True). A wanted action is completed; if it
        fails physically the world undoes it too and says why.
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
        """Occupied after a wanted close, free after a wanted open (:func:`hand_after`)."""
        return self._hand

    def execute(self, action: Action, target: Target | None, wanted: bool) -> Outcome:
        """Apply a wanted action's effect on the hand; an unwanted one changes nothing."""
        if not wanted:
            return Outcome(succeeded=True, undone=True)
        self._hand = hand_after(action, self._hand)
        return Outcome(succeeded=True)

    def start_table(self, table: int) -> None:
        """Nothing to lay out symbolically."""
