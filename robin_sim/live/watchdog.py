"""The live step's watchdog: how much the robot may do on one gesture of the participant's.

A live session must never loop: after each instruction gesture the robot acts, the participant
judges, and the step ends when an action stands. :class:`StepWatchdog` counts the robot's
attempts and the simulated time since the participant's last instruction gesture; past
:attr:`WatchdogLimits.attempts` attempts or :attr:`WatchdogLimits.seconds` s, the participant
(:class:`~robin_sim.live.participant.LiveParticipant`) hands the step back: the robot stops
trying, the page asks for a gesture, and the event is logged (``events.jsonl``).
"""

from __future__ import annotations

from collections.abc import Callable

from robin_sim.live.limits import WatchdogLimits


class StepWatchdog:
    """Counts attempts and simulated time (``clock``) since the last instruction gesture."""

    def __init__(self, limits: WatchdogLimits, clock: Callable[[], float]) -> None:
        self.limits, self._clock = limits, clock
        self.attempts = 0
        self._since = clock()

    def gesture(self) -> None:
        """The participant made an instruction gesture: the count starts again."""
        self.attempts, self._since = 0, self._clock()

    def attempt(self) -> None:
        """The robot starts an action."""
        self.attempts += 1

    @property
    def seconds(self) -> float:
        """Simulated seconds since the last instruction gesture."""
        return self._clock() - self._since

    def tripped(self) -> str:
        """Why the robot must stop trying now ("" while within the limits)."""
        limits = self.limits
        if self.attempts >= limits.attempts:
            return f"{self.attempts} actions since your last gesture"
        if self.seconds >= limits.seconds:
            return f"{self.seconds:.0f} s since your last gesture"
        return ""
