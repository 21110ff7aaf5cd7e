"""The visible person: performs each gesture with the mocap hand and shows feedback.

:class:`Narrator` turns the step loop's events into what a viewer sees: before the robot acts
on a new instruction, the person's hand points at the leg or spot it means, holds out the palm
("give me"), or shows a fist ("grasp") or open fingers ("release") where it is; after each
action it shows thumb up or down. It also keeps the :class:`EpisodeView` that the video
overlay draws. Only the mocap hand and visual-only geoms move; nothing touches the legs.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from pil.task.runner import StepRecord
from pil.task.world import Target
from pil.types import Feedback, Gesture
from robin_sim.person.gestures import GestureDisplay
from robin_sim.render.overlay import OverlayInfo
from robin_sim.robot.world import PhysicalWorld

GESTURE_HOLD = 0.5  # s the person holds a gesture before the robot reacts
FEEDBACK_HOLD = 0.4  # s the thumb stays up or down


@dataclass
class EpisodeView:
    """What the overlay shows now (updated by the narrator, read by the video recorder)."""

    info: OverlayInfo = field(default_factory=lambda: OverlayInfo(step=0, sim_time=0.0))

    def update(self, **changes: object) -> None:
        """Replace some fields of the overlay info."""
        self.info = replace(self.info, **changes)


class Narrator:
    """Shows the person's gestures and feedback in ``world`` and keeps ``view`` current."""

    def __init__(
        self,
        world: PhysicalWorld,
        view: EpisodeView,
        *,
        policy: bool = True,
        learner_table: object | None = None,
    ) -> None:
        self.world, self.view = world, view
        self.display = GestureDisplay(world.model)
        self.table = learner_table if policy else None
        self._gesture_count = 0

    def before_action(self, record: StepRecord) -> None:
        """Called by the step loop just before the robot executes ``record.action``."""
        if record.gesture_count != self._gesture_count:
            self._gesture_count = record.gesture_count
            self.perform(record.true_gesture, record.target)
        self._show_record(record, record.action.value if record.action else None)
        self.view.update(policy=self._policy(record))

    def after_step(self, record: StepRecord) -> None:
        """Show the outcome of a finished record (feedback thumb, or the repeated gesture)."""
        self.view.update(legs_delivered=record.legs_delivered)
        if record.action is None:  # the robot asks for a repeat: the person performs it again
            self._show_record(record, "(asks to repeat)")
            self.perform(record.true_gesture, record.target)
            self._gesture_count = record.gesture_count
            return
        feedback = record.feedback or Feedback.NONE
        self.view.update(feedback=feedback.value)
        self.display.show(feedback)
        self.world.sim.run(FEEDBACK_HOLD)

    def _show_record(self, record: StepRecord, action: str | None) -> None:
        """Put the record's gestures, state and action in the overlay (feedback not yet known)."""
        fields = record.to_dict()
        self.view.update(
            step=record.t,
            true_gesture=fields["true_gesture"],
            detected_gesture=fields["detected_gesture"],
            corrected_gesture=fields["corrected_gesture"],
            action=action,
            feedback=None,
            state=None if record.state is None else str(record.state),
        )

    def perform(self, gesture: Gesture, target: Target | None) -> None:
        """Show ``gesture`` and hold it so the viewer sees it.

        Pointing moves the hand above the pointed leg or spot
        (:meth:`PhysicalWorld.person_points_at`); the world draws it back out of the robot's
        way before the arm moves. The other gestures are shown where the hand is; the palm for
        "give me" is held out by the world when the robot moves to the person, after lifting
        its hand clear of the table.
        """
        self.display.show(gesture)
        if gesture is Gesture.POINTING and target is not None:
            self.world.person_points_at(target)
        self.world.sim.run(GESTURE_HOLD)

    def _policy(self, record: StepRecord) -> dict[str, float] | None:
        if self.table is None or record.state is None:
            return None
        probabilities = self.table.probabilities(record.state)  # type: ignore[attr-defined]
        return {action.value: p for action, p in probabilities.items()}
