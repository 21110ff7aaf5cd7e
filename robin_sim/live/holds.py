"""Why a live session's physics holds between two ticks, and what the page says meanwhile.

Three reasons, each set and cleared from any thread: the experimenter's pause
(``experimenter``), the participant's page that lost its connection (``page``) and a
participant inactive past the block's timeout (``inactive``, :mod:`robin_sim.live.capping`).
Physics runs on when none is left.
"""

from __future__ import annotations

import threading

from robin_sim.live.capping import INACTIVE_NOTICE

MESSAGES = {  # the page's message for each reason, the first that holds
    "experimenter": "Paused by the experimenter: please wait.",
    "page": "Waiting for the participant's page to come back.",
    "inactive": INACTIVE_NOTICE,
}


class Holds:
    """The reasons physics holds now (thread-safe)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._reasons: set[str] = set()
        self.held = threading.Event()  # set while any reason holds

    def hold(self, reason: str, on: bool) -> None:
        """Hold for ``reason`` (``on``) or no longer."""
        with self._lock:
            if on:
                self._reasons.add(reason)
            else:
                self._reasons.discard(reason)
            if self._reasons:
                self.held.set()
            else:
                self.held.clear()

    def __contains__(self, reason: str) -> bool:
        return reason in self._reasons

    def message(self) -> str:
        """What the page says while held ("" when not held)."""
        return next((text for reason, text in MESSAGES.items() if reason in self._reasons), "")
