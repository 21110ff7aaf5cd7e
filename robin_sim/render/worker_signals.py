"""The signals a render worker leaves to the main process (Ctrl-C and SIGTERM end the episode)."""

from __future__ import annotations

from pil.signal_policy import SIGNALS

__all__ = ["SIGNALS"]
