"""The live session's limits, in one place (light: the command line reads them for --help).

:class:`WatchdogLimits`: how much the robot may do on one gesture of the participant's before
the step goes back to them (:mod:`robin_sim.live.watchdog`). :data:`RECONNECT_GRACE_S`: how
long the server waits for a participant's page that lost its connection
(:class:`robin_sim.live.tabs.ControlSlot`). :class:`BlockLimits`: a study block's caps on its
time and its robot actions, and the participant's inactivity.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from pil.errors import RobinPilError

RECONNECT_GRACE_S = 120.0  # s a lost participant's page is waited for before "closed"
RECONNECT_GRACES = (1.0, 3600.0)  # s: the range --reconnect-grace takes
ATTEMPTS = (1, 100)  # the range of the attempts limit
SECONDS = (5.0, 3600.0)  # s of simulated time


def from_text(value: object, kind: type) -> object:
    """``value`` as a number of ``kind`` when it is a command line's text of one (else as it
    is: the caller's check names what is wrong with it), so that a value given as text is
    checked once, where its range is."""
    if isinstance(value, str):
        try:
            return kind(value)
        except ValueError:
            return value
    return value


@dataclass(frozen=True)
class WatchdogLimits:
    """At most ``attempts`` robot actions and ``seconds`` s of simulated time on one gesture
    (10 is twice through the five actions; 120 s lets ten actions run with their windows), and
    at most ``handed_back`` of the participant's gestures in a row that Robin could not act on:
    on the next one Robin proposes an action itself (the step loop's ``ask_after``,
    :mod:`pil.task.asking`), so a participant is never asked again and again."""

    attempts: int = 10
    seconds: float = 120.0
    handed_back: int = 3

    def checked(self) -> WatchdogLimits:
        """These limits, each checked (one :class:`RobinPilError` naming the valid range)."""
        attempts, seconds = from_text(self.attempts, int), from_text(self.seconds, float)
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
        return WatchdogLimits(attempts, float(seconds), self.handed_back)


BLOCK_SECONDS = (1.0, 36_000.0)  # s of simulated time: the range of a block's time cap
BLOCK_ACTIONS = (1, 10_000)  # robot actions: the range of a block's action cap
INACTIVITY_SECONDS = (5.0, 3600.0)  # s of simulated time waiting for the participant


@dataclass(frozen=True)
class BlockLimits:
    """A block's caps (None: none): ``seconds`` of simulated time, ``actions`` robot actions,
    and ``inactivity`` s of simulated time the participant may leave a turn unanswered before
    the session holds and asks whether they are still there."""

    seconds: float | None = None
    actions: int | None = None
    inactivity: float | None = None

    def checked(self, where: str = "limits") -> BlockLimits:
        """These limits, each checked (one :class:`RobinPilError` naming the valid range)."""
        return BlockLimits(
            _within(self.seconds, f"{where}.block_seconds", BLOCK_SECONDS, float),
            _within(self.actions, f"{where}.block_actions", BLOCK_ACTIONS, int),
            _within(self.inactivity, f"{where}.inactivity_seconds", INACTIVITY_SECONDS, float),
        )

    def reached(self, sim_time: float, actions: int, turn: bool) -> str:
        """Which cap ends the block now ("time", "actions"; "" none): ``actions`` started so
        far, ``turn``: the robot has finished and waits for the participant."""
        if self.seconds is not None and sim_time >= self.seconds:
            return "time"
        if self.actions is not None and (
            actions > self.actions or (turn and actions >= self.actions)
        ):
            return "actions"
        return ""

    def as_dict(self) -> dict[str, float | int | None]:
        return {
            "block_seconds": self.seconds,
            "block_actions": self.actions,
            "inactivity_seconds": self.inactivity,
        }


def _within(value: object, what: str, bounds: tuple[float, float], kind: type) -> Any:
    if value is None:
        return None
    low, high = bounds
    whole = kind is int
    if isinstance(value, bool) or not isinstance(value, int if whole else int | float):
        raise RobinPilError(
            f"{what} must be {'a whole number' if whole else 'a number'} from {low:g} to "
            f"{high:g}, got {value!r:.40}"
        )
    if not low <= value <= high:  # NaN fails too
        raise RobinPilError(f"{what} must lie in [{low:g}, {high:g}], got {value}")
    return kind(value)
