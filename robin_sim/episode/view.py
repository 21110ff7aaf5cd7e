"""What the episode's video overlay shows, kept current from the step loop.

:class:`EpisodeView` is the loop's :class:`pil.task.runner.StepObserver`: it is told of each
decision before the robot acts and of each answer before the person shows the thumb, and only
updates the :class:`~robin_sim.render.overlay.OverlayInfo` that the video recorder draws. It
never acts in the world.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

from pil.task.records import StepRecord
from robin_sim.render.overlay import OverlayInfo


@dataclass
class EpisodeView:
    """The overlay's current info; ``table`` (the learner's) feeds the P(a|s) panel if set."""

    info: OverlayInfo = field(default_factory=lambda: OverlayInfo(step=0, sim_time=0.0))
    table: Any = None  # an AssociationTable, or None for no policy panel

    def update(self, **changes: Any) -> None:
        """Replace some fields of the overlay info (an unknown name is a TypeError)."""
        self.info = replace(self.info, **changes)

    # --- the StepObserver protocol -------------------------------------------------------------
    def decided(self, record: StepRecord) -> None:
        """The robot is about to act: the record's gestures, state and action; no feedback."""
        self._show(record, None if record.action is None else record.action.value)
        self.update(policy=self._policy(record))

    def answered(self, record: StepRecord) -> None:
        """The person is about to show the thumb (``record.feedback``)."""
        self.update(feedback=None if record.feedback is None else record.feedback.value)

    def received(self, record: StepRecord) -> None:
        """The learner has the feedback (the overlay changes when the record is finished)."""

    def finished(self, record: StepRecord) -> None:
        """A record is done: the legs delivered so far."""
        self.update(legs_delivered=record.legs_delivered)

    def asked_to_repeat(self, record: StepRecord) -> None:
        """The robot asks for the gesture again (a record without an action)."""
        self._show(record, "(asks to repeat)")

    # --- helpers -------------------------------------------------------------------------------
    def _show(self, record: StepRecord, action: str | None) -> None:
        fields = record.to_dict()
        if record.proactive and record.state is not None:  # no gesture: the robot anticipates
            fields["true_gesture"] = None
            action = f"{action} (anticipating {record.state.gesture.value})"
        self.update(
            step=record.t,
            true_gesture=fields["true_gesture"],
            detected_gesture=fields["detected_gesture"],
            corrected_gesture=fields["corrected_gesture"],
            action=action,
            feedback=None,
            state=None if record.state is None else str(record.state),
            intended=None if record.intended_action is None else record.intended_action.value,
            handover=record.handover,
            handover_type=record.handover_type,
        )

    def _policy(self, record: StepRecord) -> dict[str, float] | None:
        if self.table is None or record.state is None:
            return None
        probabilities = self.table.probabilities(record.state)
        return {action.value: p for action, p in probabilities.items()}
