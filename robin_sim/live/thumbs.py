"""What the live participant hands the step loop: a gesture, and their eyes on one action.

:class:`Gesturing` is an instruction gesture (a click resolved to a leg or spot, a key, or a
webcam reading's decision). :class:`ThumbWatcher` is the :class:`pil.task.world.Watcher` of
one robot action: a thumb down during it stops it; after it (also after an action the robot
undid by itself) the feedback window opens, and a thumb down then takes the result back.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from pil.task.world import Target
from pil.types import Action, Feedback, Gesture
from robin_sim.person.body import PhysicalBody


@dataclass(frozen=True, slots=True)
class Gesturing:
    """An instruction gesture from the participant (pointing carries what was clicked)."""

    gesture: Gesture
    target: Target | None = None
    reading: int | None = None  # the webcam reading it was read from (None: a click or key)


class Judging(Protocol):
    """What the watcher reads and sets of the participant
    (:class:`robin_sim.live.participant.LiveParticipant`)."""

    body: PhysicalBody
    thumb: Feedback | None
    feedback_window: float
    window_until: float | None
    ended: bool

    @property
    def gesture_pending(self) -> bool: ...

    def set_phase(self, phase: str, message: str) -> None: ...


class ThumbWatcher:
    """The participant's eyes on one action: stop once a thumb down came during it."""

    def __init__(self, participant: Judging) -> None:
        self.participant = participant
        self.stopped = False

    def stop_now(self, shown: Action | None) -> bool:
        """True once the participant's thumb down has arrived (shown on the simulated hand)."""
        if not self.stopped and self.participant.thumb is Feedback.NOT_OK:
            self.stopped = True
            self.participant.body.display.show(Feedback.NOT_OK)
            self.participant.set_phase(
                "robot_acting", "Thumb down: the robot takes its action back."
            )
        return self.stopped

    def result_window(self, shown: Action | None, *, undone: bool = False) -> float:
        """The feedback window, unless a thumb came during the move: a thumb down in it makes
        the robot take the finished action back (physics runs while the participant decides).
        An action the robot undid by itself (a close on nothing) gets the window too: it was
        shown, and the participant judges it."""
        participant = self.participant
        if participant.thumb is not None:
            return 0.0
        window = participant.feedback_window
        what = "Robin took that back by itself. " if undone else ""
        participant.set_phase(
            "waiting_for_thumb",
            f"{what}Thumb up or down? No thumb within {window:g} s counts as OK.",
        )
        participant.window_until = participant.body.world.time + window
        return window

    def settled(self) -> bool:
        """The result stands: a thumb up, a next gesture instead (silence) or the session's end."""
        participant = self.participant
        return participant.thumb is Feedback.OK or participant.gesture_pending or participant.ended
