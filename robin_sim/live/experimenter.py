"""The experimenter's view of a live run: its commands and what it is shown.

``GET /experimenter?token=...`` serves the view; it always needs its own token (printed when the
server starts), on loopback too, because it controls the run. Its WebSocket (``/ws`` with that
token) gets what every tab gets (frames and the participant's status) and, a few times a
second, an ``{"type": "experimenter", ...}`` message (:func:`experimenter_view`): the stream's
and the pacer's figures, the newest steps of the log and the tabs. It sends commands
(:func:`parse_command`): ``pause``, ``resume``, ``end`` (the run), ``next_block`` (this block
saved as ``ended``, the next block's screen follows) and ``note`` (text saved with its time in
the session folder's ``notes.jsonl``).
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from robin_sim.live.inputs import LiveInputError

if TYPE_CHECKING:
    from robin_sim.live.conductor import Conductor
    from robin_sim.live.run import LiveRun

COMMANDS = ("pause", "resume", "end", "next_block", "note")
MAX_COMMAND_BYTES = 4096
MAX_NOTE_CHARS = 2000


@dataclass(frozen=True, slots=True)
class Command:
    """A checked command from the experimenter's view."""

    kind: str
    text: str = ""


def parse_command(raw: str | bytes) -> Command:
    """Check one message from the experimenter's view; :class:`LiveInputError` says why not."""
    if len(raw) > MAX_COMMAND_BYTES:
        raise LiveInputError(f"a command is at most {MAX_COMMAND_BYTES} bytes")
    try:
        message = json.loads(raw)
    except (ValueError, RecursionError):
        raise LiveInputError("a command is a JSON object, e.g. {\"type\": \"pause\"}") from None
    if not isinstance(message, Mapping) or message.get("type") not in COMMANDS:
        kind = message.get("type") if isinstance(message, Mapping) else None
        raise LiveInputError(f"unknown command {str(kind)[:40]!r}; valid: {', '.join(COMMANDS)}")
    kind = str(message["type"])
    if kind != "note":
        return Command(kind)
    text = message.get("text")
    if not isinstance(text, str) or not text.strip():
        raise LiveInputError("note: write some text first")
    if len(text) > MAX_NOTE_CHARS:
        raise LiveInputError(f"note: at most {MAX_NOTE_CHARS} characters, got {len(text)}")
    return Command(kind, text.strip())


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
    }


def pacing_figures(run: LiveRun | None, speed: float, paused: bool) -> dict[str, Any]:
    """The stream's and the pacer's figures of a running session now."""
    stream = None if run is None else run.stream
    pacer = None if run is None else run.pacer
    stats = None if stream is None else stream.stats
    figures: dict[str, Any] = {
        "frames": 0, "stream_fps": None, "latency_ms": None, "frame_ms": None,
        "behind_s": None if pacer is None else round(pacer.behind_s, 3),
        "slips": None if pacer is None else pacer.slips,
        "lag_s": None if pacer is None else round(pacer.lag_s, 3),
        "speed": speed, "paused": paused,
    }  # fmt: skip
    if stats is not None and stats.frames:
        figures.update(
            frames=stats.frames,
            stream_fps=None if stats.fps is None else round(stats.fps, 2),
            latency_ms={"median": stats.latency_ms(0.5), "p95": stats.latency_ms(0.95)},
            frame_ms=round((stats.render_s + stats.encode_s) / stats.frames * 1000, 1),
        )
    return figures
