"""Test helper: a person's body and Robin acting in a ``PhysicalWorld``, as the runner orders it.

:class:`Acted` performs each new intent's gesture with a :class:`PhysicalBody`, lets the world
execute the action, and shows the thumb that the action earned (OK for a wanted action that
worked, else not-OK), so physics tests can script exact action sequences.
"""

from __future__ import annotations

from pil.task.world import Intent, Outcome, Target
from pil.types import Action, Feedback, Gesture
from robin_sim.person.body import PhysicalBody
from robin_sim.robot.world import PhysicalWorld


def intent(gesture: str, action: str, target: Target | None = None) -> Intent:
    """An intent of handover 0 on table 0."""
    return Intent(Gesture(gesture), Action(action), target, handover=0, table=0)


class Acted:
    """A world and the person's body in it; :meth:`act` is one runner step."""

    def __init__(
        self, world: PhysicalWorld | None = None, seed: int = 0, reaction: float = 0.5
    ) -> None:
        self.world = world or PhysicalWorld()
        self.body = PhysicalBody(self.world, seed=seed)
        self.reaction = reaction
        self._performed: Intent | None = None

    def act(self, action: Action, meant: Intent) -> Outcome:
        """The person performs ``meant`` (if new), the robot runs ``action`` while the person
        watches, then the thumb follows."""
        if meant is not self._performed:
            self.body.perform(meant.gesture, meant.target)
            self._performed = meant
        outcome = self.world.execute(action, meant.target, self.body.watch(meant, self.reaction))
        ok = action is meant.action and outcome.succeeded and not outcome.interrupted
        thumb = Feedback.OK if ok else Feedback.NOT_OK
        self.body.show_feedback(thumb)
        self.body.after_feedback(thumb)
        return outcome
