"""The experimenter's view of a live run: its commands and what it is shown.

``GET /experimenter?token=...`` serves the view; it always needs its own token (printed when the
server starts), on loopback too, because it controls the run. Its WebSocket (``/ws`` with that
token) gets what every tab gets (frames and the participant's status) and, a few times a
second, an ``{"type": "experimenter", ...}`` message (:func:`experimenter_view`): the stream's
and the pacer's figures, the newest steps of the log and the tabs, a study block's limits
(time, actions, inactivity: what is used and what was reached) and the session's newest
events (silences, hand-backs, watchdog, limits, inactivity, reconnections). It sends commands
(:mod:`robin_sim.live.commands`): ``pause``, ``resume``, ``end`` (the run), ``next_block``
(this block saved as ``ended``, the next block's screen follows) and ``note`` (text saved with
its time in the session folder's ``notes.jsonl``).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from robin_sim.live.conductor import Conductor


def experimenter_view(conductor: Conductor, roles: Iterable[tuple[str, int]]) -> dict[str, Any]:
    """The experimenter's message: pacing, the newest steps, the tabs ((role, frames dropped))."""
    session = conductor.session
    running = conductor.phase == "running"
    return {
        "type": "experimenter",
        "run_phase": conductor.phase,
        "pacing": session.pacing() if running else None,
        "log": list(session.log_tail),
        "tabs": [{"role": role, "frames_dropped": dropped} for role, dropped in roles],
        "session_folder": str(session.out_dir),
        # a study block's caps and what reached them; what the session did of itself
        "limits": None if session.caps is None else session.caps.status(),
        "events": session.recent_events(),
    }
