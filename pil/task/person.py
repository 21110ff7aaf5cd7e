"""The scripted person: performs each handover type's gestures and judges the robot's actions.

One :class:`ScriptedPerson` owns everything the person does, in the order a person does it:
:meth:`~ScriptedPerson.perform` the gesture, watch the robot act, :meth:`~ScriptedPerson.judge`
it and :meth:`~ScriptedPerson.show_feedback` with a thumb; only then does the learner receive
the feedback. The same person serves the symbolic study (no body: nothing to show) and the
physical episode, whose :class:`PersonBody` makes the gestures and thumbs visible, holds out
the palm and carries delivered legs away.

The person knows the correct association T_c: for every gesture of the script they want one
action (the step's action). They approve an action exactly when it is the wanted one *and* the
world reports that it worked; otherwise they give not-OK. With probability ``silent_ok`` they
approve by giving no feedback at all (the learner counts that as OK, eq. 1).

``patience`` (0 = off) models a person who, after that many rejected actions in a row for
one gesture, performs the gesture again instead of waiting for the robot to find the action.
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from pil.errors import RobinPilError, check_rate
from pil.task.scenario import HandoverType, Scenario
from pil.task.world import Intent, Outcome, Target
from pil.types import Action, Feedback, Gesture


@dataclass(frozen=True, slots=True)
class ScriptStep:
    """One instruction of the whole script: what is performed and meant, and where it lies."""

    intent: Intent
    handover_type: str
    step: int  # 0-based index of the gesture within its handover
    first_of_table: bool  # the first gesture of a table (the world lays out its legs)


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


class PersonBody(Protocol):
    """What the person's body does in a world where it can be seen (a physical episode)."""

    def start_table(self, table: int) -> None:
        """Before a new table's legs are laid out: the hand goes back to rest."""
        ...

    def perform(self, gesture: Gesture, target: Target | None) -> None:
        """Make ``gesture`` visibly (pointing at ``target``), hold it, and make room."""
        ...

    def show_feedback(self, feedback: Feedback) -> None:
        """Show the thumb (or nothing for silence) and hold it; then do what follows from it,
        e.g. carry a leg that now lies on the palm to the bin."""
        ...


class ScriptedPerson:
    """Performs a script and gives feedback (own seeded RNG for ``silent_ok``).

    ``body``, when given, makes what the person does visible in a physical world.
    """

    def __init__(
        self,
        script: Sequence[ScriptStep],
        seed: int = 0,
        *,
        silent_ok: float = 0.0,
        patience: int = 0,
        body: PersonBody | None = None,
    ) -> None:
        self.script = tuple(script)
        self.body = body
        self.silent_ok = check_rate(silent_ok, "silent_ok probability")
        if isinstance(patience, bool) or not isinstance(patience, int) or patience < 0:
            raise RobinPilError(f"patience must be a whole number >= 0 (0 = off), got {patience!r}")
        self.patience = patience
        self._rng = random.Random(seed)

    @classmethod
    def for_types(
        cls, scenario: Scenario, types: Sequence[HandoverType], seed: int = 0, **options: float
    ) -> ScriptedPerson:
        """A person performing ``types`` with the scenario's legs per table and spots."""
        script = plan_script(types, scenario.legs_per_table, scenario.spots)
        return cls(script, seed, **options)  # type: ignore[arg-type]

    def start_table(self, table: int) -> None:
        """A new table begins: the body (if any) rests its hand."""
        if self.body is not None:
            self.body.start_table(table)

    def perform(self, intent: Intent) -> None:
        """Perform ``intent``'s gesture (visibly, with a body)."""
        if self.body is not None:
            self.body.perform(intent.gesture, intent.target)

    def judge(self, intent: Intent, action: Action, outcome: Outcome) -> Feedback:
        """OK (or silence) for the wanted action when it worked, else not-OK."""
        if action is not intent.action or not outcome.succeeded:
            return Feedback.NOT_OK
        if self.silent_ok and self._rng.random() < self.silent_ok:
            return Feedback.NONE
        return Feedback.OK

    def show_feedback(self, feedback: Feedback) -> None:
        """Give the thumb ``feedback`` (visibly, with a body), before the learner receives it."""
        if self.body is not None:
            self.body.show_feedback(feedback)

    def loses_patience(self, rejections: int) -> bool:
        """True when ``rejections`` in a row make the person perform the gesture again."""
        return self.patience > 0 and rejections >= self.patience
