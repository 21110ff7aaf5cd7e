"""The person's script: each instruction in order with its target (:func:`plan_script`), and
the leg the person saw the robot take (:class:`LegsSeen`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from pil.task.scenario import HandoverType
from pil.task.world import Intent, Target
from pil.types import Action


@dataclass(frozen=True, slots=True)
class ScriptStep:
    """One instruction of the whole script: what is performed and meant, and where it lies."""

    intent: Intent
    handover_type: str
    step: int  # 0-based index of the gesture within its handover
    first_of_table: bool  # the first gesture of a table (the world lays out its legs)
    recovery: bool = False  # inserted by the person to have a dropped leg picked up again


def plan_script(
    types: Sequence[HandoverType], legs_per_table: int, spots: int
) -> tuple[ScriptStep, ...]:
    """The person's whole script for handing over ``types`` in order, with targets.

    Handover ``i`` is leg ``i % legs_per_table`` of table ``i // legs_per_table``. An ``object``
    step points at that leg and a ``location`` step at spot ``leg % spots``; when the same
    intent is pointed at twice in a row, the first point goes elsewhere, as the person changes
    their mind: to the next leg or spot, which belongs to a later handover of the table and is
    therefore still there or still free; for the table's last one, to the same leg or spot
    (a spot of an earlier handover may hold a placed leg).
    """
    script: list[ScriptStep] = []
    for handover, handover_type in enumerate(types):
        table, leg = divmod(handover, legs_per_table)
        steps = handover_type.steps
        for i, step in enumerate(steps):
            repeated = i + 1 < len(steps) and steps[i + 1].action is step.action
            target: Target | None = None
            if step.action is Action.OBJECT:
                index = min(leg + 1, legs_per_table - 1) if repeated else leg
                target = Target("leg", index)
            elif step.action is Action.LOCATION:
                later = leg + 1 < min(spots, legs_per_table)
                index = leg + 1 if repeated and later else leg % spots
                target = Target("spot", index)
            intent = Intent(step.gesture, step.action, target, handover, table)
            script.append(ScriptStep(intent, handover_type.name, i, leg == 0 and i == 0))
    return tuple(script)


@dataclass(slots=True)
class LegsSeen:
    """Which leg the person saw the robot take, from the actions they approved: an "object"
    points at a leg, a close takes the leg pointed at, an open lets it go."""

    holding: int | None = None  # the leg the person saw the robot grasp
    pointed: int | None = None  # the leg of the last approved "object"

    def approved(self, action: Action, target: Target | None) -> None:
        """``action`` on ``target`` was let stand."""
        if action is Action.OBJECT:
            self.pointed = None if target is None or target.kind != "leg" else target.index
        elif action is Action.CLOSE:
            self.holding = self.pointed
        elif action is Action.OPEN:
            self.holding = None

    def lost(self) -> int | None:
        """The leg the robot held, now gone from its hand (forgotten here)."""
        leg, self.holding = self.holding, None
        return leg
