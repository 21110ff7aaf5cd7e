"""A study block's caps, watched tick by tick: its time, its robot actions, the participant's
inactivity (:class:`~robin_sim.live.limits.BlockLimits`).

:class:`BlockWatch` is asked after every control tick (:meth:`BlockWatch.tick`). A block whose
simulated time or robot actions reach their cap ends as ``capped`` (the session stops it at the
next safe moment: never between a verdict and the learner receiving it); a participant who has
left their turn unanswered for the inactivity timeout makes the session hold (as for a pause)
and the page asks whether they are still there; their next input lets it run on. Each is one
line of the session's ``events.jsonl`` (``limit``, ``inactive``, ``active``) and shown on the
experimenter's view (:meth:`BlockWatch.status`).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from robin_sim.live.limits import BlockLimits

INACTIVE_NOTICE = "Are you still there? Make your next gesture (or a thumb) to go on."
CAPPED_NOTICE = {
    "time": "The time for this block is up.",
    "actions": "This block has reached its number of robot actions.",
}
EventSink = Callable[[str, dict[str, Any]], None]


class BlockWatch:
    """The caps of one block (see the module doc); ``hold`` holds or releases physics."""

    def __init__(
        self, limits: BlockLimits, hold: Callable[[bool], None], on_event: EventSink
    ) -> None:
        self.limits, self._hold, self._event = limits, hold, on_event
        self._lock = threading.Lock()
        self.reached = ""  # the cap that ended the block ("" none)
        self.reached_at: float | None = None
        self.inactive = False
        self.inactive_times = 0
        self._idle_since: float | None = None  # sim time the participant's turn began
        self._poked = False  # an input came since the last tick
        self.sim_time = 0.0
        self.actions = 0

    def tick(self, sim_time: float, actions: int, phase: str) -> str:
        """After a control tick: the cap reached ("time", "actions") or ""; holds the session
        when the participant has been inactive too long."""
        self.sim_time, self.actions = sim_time, actions
        turn = phase == "waiting_for_gesture"
        if not self.reached:
            reached = self.limits.reached(sim_time, actions, turn)
            if reached:
                self.reached, self.reached_at = reached, sim_time
                limit = self.limits.seconds if reached == "time" else self.limits.actions
                self._event("limit", {"limit": reached, "cap": limit, "actions": actions})
        with self._lock:
            poked, self._poked = self._poked, False
        if not turn or poked:
            self._idle_since = sim_time if turn else None
        elif self._idle_since is None:
            self._idle_since = sim_time
        timeout = self.limits.inactivity
        idle = 0.0 if self._idle_since is None else sim_time - self._idle_since
        if timeout is not None and turn and not self.inactive and idle >= timeout:
            self.inactive = True
            self.inactive_times += 1
            self._event("inactive", {"idle_s": round(idle, 2), "timeout_s": timeout})
            self._hold(True)
        return self.reached

    def input(self) -> None:
        """The participant sent something: they are there (a hold for inactivity ends)."""
        with self._lock:
            self._poked = True
            wake = self.inactive
            self.inactive = False
        if wake:
            self._event("active", {})
            self._hold(False)

    def notice(self) -> str:
        """What the page says about the caps now ("" nothing)."""
        if self.inactive:
            return INACTIVE_NOTICE
        return CAPPED_NOTICE.get(self.reached, "")

    def status(self) -> dict[str, Any]:
        """For the experimenter's view and the summary: the caps, what is used, what happened."""
        return {
            **self.limits.as_dict(),
            "sim_time": round(self.sim_time, 2),
            "actions": self.actions,
            "reached": self.reached or None,
            "reached_at": self.reached_at,
            "inactive": self.inactive,
            "inactive_times": self.inactive_times,
        }
