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
    undone: bool = False  # the robot took the action back (after a stop, or when it failed)
    interrupted: bool = False  # the person stopped it (thumb down) before or after its end
    dropped: int | None = None  # a leg that left the robot's hand on the way (physics)


class Watcher(Protocol):
    """The person watching the robot act: the world asks it, tick by tick, whether to stop.

    A thumb down is the only thing that flows from the person to the robot during an action;
    the world never learns what the person wanted.
    """

    def stop_now(self, shown: Action | None) -> bool:
        """Called when the action starts and at every control tick while it runs: True when
        the person shows thumb down now. ``shown`` is the action as a symbolic world shows it
        outright; a physical world passes None (a person's body perceives the motion)."""
        ...

    def result_window(self, shown: Action | None, *, undone: bool = False) -> float:
        """Called once when the action has run to its end: how long (s) the world should keep
        asking :meth:`stop_now` before the result stands (0: the person lets it stand).
        ``undone``: the action failed and the robot took it back by itself (a close that caught
        nothing opened again); it is still shown and may be judged, with nothing to take back."""
        ...

    def settled(self) -> bool:
        """Asked with :meth:`stop_now` during the result window: True once the person has let
        the result stand (a thumb up), which ends the window early without a take-back."""
        ...


class World(Protocol):
    """Executes the robot's actions; symbolic in the study, MuJoCo in an episode.

    The world acts for the robot only: it is told the action and the leg or spot it concerns,
    never what the person wants; the person can only stop it, through ``watcher``.
    """

    def hand(self) -> Hand:
        """The hand state as the world sees it (from physics, for the physical robot)."""
        ...

    def execute(
        self, action: Action, target: Target | None, watcher: Watcher | None = None
    ) -> Outcome:
        """Perform ``action`` on ``target`` (the leg or spot the person indicated, if any).

        The robot runs the action as it would, asking ``watcher`` at every tick; when the
        person stops it (during the action, or on seeing its result) the robot stops and takes
        the action back from where it is (``Outcome.interrupted`` and ``undone``). An action
        that fails physically is taken back too, where it can be, and says why.
        """
        ...

    def start_table(self, table: int) -> None:
        """A new table's legs are laid out (called before its first handover)."""
        ...


# the methods of World, for a check that a factory made one (the Protocol is not runtime-checked)
WORLD_METHODS: tuple[str, ...] = tuple(
    name for name, value in vars(World).items() if callable(value) and not name.startswith("_")
)


class SymbolicWorld:
    """An instant world: the person sees the action at once; the hand follows close and open."""

    def __init__(self) -> None:
        self._hand = Hand.FREE

    def hand(self) -> Hand:
        """Occupied after a close that was let stand, free after such an open."""
        return self._hand

    def execute(
        self, action: Action, target: Target | None, watcher: Watcher | None = None
    ) -> Outcome:
        """The person sees ``action`` outright; a stopped action changes nothing."""
        if watcher is not None and (
            watcher.stop_now(action) or watcher.result_window(action) > 0.0
        ):
            return Outcome(False, "stopped by the person", undone=True, interrupted=True)
        self._hand = hand_after(action, self._hand)
        return Outcome(succeeded=True)

    def start_table(self, table: int) -> None:
        """Nothing to lay out symbolically."""
