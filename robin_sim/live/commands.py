"""The experimenter's commands (pause, resume, end, next block, note), checked before the
conductor acts on them; the view they come from is :mod:`robin_sim.live.experimenter`."""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass

from robin_sim.live.inputs import LiveInputError

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
        raise LiveInputError('a command is a JSON object, e.g. {"type": "pause"}') from None
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
