"""Ctrl-C and SIGTERM during an episode: noted at once, acted on between two control ticks.

A terminal's Ctrl-C sends SIGINT to the whole process group, render workers included, and a
cluster or a container stopping us sends SIGTERM. Raising ``KeyboardInterrupt`` wherever the
signal lands can tear the MP4 muxer (inside PyAV) or a pipe to a render worker. Instead,
:class:`InterruptGuard` only records the signal; :meth:`InterruptGuard.check`, a simulator
observer, raises ``KeyboardInterrupt`` after the next control tick, where nothing is half
written, and the episode then closes its video and log normally. A signal that arrives while
the video is being finished is honoured after the file is complete. Render workers ignore both
signals (:mod:`robin_sim.render.worker_start`) and are ended by the episode.

The guard installs its handlers only in the main thread of a process whose SIGINT handler is
Python's default, another guard's or the command's signal policy
(:class:`pil.signal_policy.CommandSignals`): in a pool's worker (signals ignored) or a Dask
worker thread it does nothing, and the pool's own interrupt handling applies. ``robin-pil``
notes signals from its first line (:func:`robin_sim.cli.main.main`), so that a signal while
the command's modules import or the world is built is noted, not raised inside an import; the
episode's own guard takes over a signal noted so, and acts on it once its files are open (an
``interrupted`` summary and a playable MP4 even then).
"""

from __future__ import annotations

import signal
import threading
from types import FrameType, TracebackType
from typing import Any

from pil.signal_policy import SIGNALS, policy_of


class InterruptGuard:
    """Context manager: while inside, SIGINT/SIGTERM set :attr:`requested` instead of raising."""

    def __init__(self) -> None:
        self.requested: signal.Signals | None = None
        self._raised = False
        self._previous: dict[signal.Signals, Any] = {}

    @property
    def active(self) -> bool:
        """Whether the guard's handlers are installed."""
        return bool(self._previous)

    def _note(self, signum: int, frame: FrameType | None) -> None:
        if self.requested is None:
            self.requested = signal.Signals(signum)

    def check(self, *_: object) -> None:
        """Raise ``KeyboardInterrupt`` once, if a signal came (a simulator observer)."""
        if self.requested is not None and not self._raised:
            self._raised = True
            raise KeyboardInterrupt(f"{self.requested.name} received")

    def __enter__(self) -> InterruptGuard:
        in_main = threading.current_thread() is threading.main_thread()
        handler = signal.getsignal(signal.SIGINT)
        outer = getattr(handler, "__self__", None)
        if not isinstance(outer, InterruptGuard):
            outer = policy_of(handler)  # the command's policy, or None
        if in_main and (handler is signal.default_int_handler or outer is not None):
            for signum in SIGNALS:
                self._previous[signum] = signal.signal(signum, self._note)
        if outer is not None and self.requested is None:
            # nested: take over what the outer one noted (read once ours are in: a signal
            # in between went to the outer one, or to ours)
            self.requested = outer.requested
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        previous, self._previous = self._previous, {}
        for signum, handler in previous.items():
            signal.signal(signum, handler)
