"""The signals a render worker leaves to the main process (Ctrl-C and SIGTERM end the episode)."""

from __future__ import annotations

import signal

SIGNALS: tuple[signal.Signals, ...] = (signal.SIGINT, signal.SIGTERM)
