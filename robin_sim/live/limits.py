"""The live session's limits, in one place (light: the command line reads them for --help).

:class:`WatchdogLimits`: how much the robot may do on one gesture of the participant's before
the step goes back to them (:mod:`robin_sim.live.watchdog`). :data:`RECONNECT_GRACE_S`: how
long the server waits for a participant's page that lost its connection
(:class:`robin_sim.live.tabs.ControlSlot`).
"""

from __future__ import annotations

from dataclasses import dataclass

from pil.errors import RobinPilError

RECONNECT_GRACE_S = 120.0  # s a lost participant's page is waited for before "closed"
RECONNECT_GRACES = (1.0, 3600.0)  # s: the range --reconnect-grace takes
ATTEMPTS = (1, 100)  # the range of the attempts limit
SECONDS = (5.0, 3600.0)  # s of simulated time


@dataclass(frozen=True)
class WatchdogLimits:
    """At most ``attempts`` robot actions and ``seconds`` s of simulated time on one gesture
    (10 is twice through the five actions; 120 s lets ten actions run with their windows)."""

    attempts: int = 10
    seconds: float = 120.0

    def checked(self) -> WatchdogLimits:
        """These limits, each checked (one :class:`RobinPilError` naming the valid range)."""
        attempts, seconds = self.attempts, self.seconds
        low, high = ATTEMPTS
        if isinstance(attempts, bool) or not isinstance(attempts, int):
            raise RobinPilError(f"max_attempts must be a whole number, got {attempts!r:.40}")
        if not low <= attempts <= high:
            raise RobinPilError(f"max_attempts must lie in [{low}, {high}], got {attempts}")
        low_s, high_s = SECONDS
        if isinstance(seconds, bool) or not isinstance(seconds, int | float):
            raise RobinPilError(f"max_step_seconds must be a number, got {seconds!r:.40}")
        if not low_s <= seconds <= high_s:  # NaN fails too
            raise RobinPilError(f"max_step_seconds must lie in [{low_s}, {high_s}], got {seconds}")
        return WatchdogLimits(attempts, float(seconds))
