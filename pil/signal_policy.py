"""One way for every ``robin-pil`` command to meet Ctrl-C (SIGINT) and SIGTERM.

:class:`CommandSignals` is installed on ``main``'s first line and holds both signals for the
command's whole life, whatever disposition the process inherited (a shell's background job
or ``nohup ... &`` starts with SIGINT ignored; a service manager sends SIGTERM):

* **start-up** (imports, option parsing): a signal is only noted, so none lands inside an
  import; the command then ends with 130 before it starts (or, if it holds signals itself,
  such as the episode, it takes the noted signal over and leaves its files consistent);
* **running**: the first SIGINT or SIGTERM raises ``KeyboardInterrupt`` in the main thread,
  as Ctrl-C does in plain Python, so every command's ``finally`` blocks keep its finished work;
  further signals are noted, never raised again inside that clean-up. A command that holds
  signals (:attr:`holding`) keeps them noted: its own guard acts on them between two steps
  (an episode's guard takes them over in either case, also inside another command);
* **teardown** (the command returned; its summary is written): both signals are ignored until
  the process exits, so a late SIGTERM can no longer turn a finished run into a -15.

Processes a command starts itself (worker pools) begin with both signals ignored
(:func:`ignored_for_children`) and are stopped by the command (:mod:`pil.worker_pool`).
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from types import FrameType
from typing import Any

SIGNALS: tuple[signal.Signals, ...] = (signal.SIGINT, signal.SIGTERM)
INTERRUPTED = 130  # the exit code of an interrupted command (128 + SIGINT), for both signals


class CommandSignals:
    """SIGINT and SIGTERM of one command, from start-up to exit (see the module's docstring).

    ``requested`` is the first signal received (None: none); while ``holding`` signals are
    only noted (start-up, between the command and teardown, a command that acts on them
    itself through a nested :class:`robin_sim.episode.interrupts.InterruptGuard`).
    """

    def __init__(self) -> None:
        self.requested: signal.Signals | None = None
        self.holding = True  # start-up: noted only
        self._raised = False
        self._previous: dict[signal.Signals, Any] = {}

    def install(self) -> CommandSignals:
        """Take both signals now, whatever they were (ignored included); main thread only."""
        if threading.current_thread() is threading.main_thread():
            for signum in SIGNALS:
                self._previous[signum] = signal.signal(signum, self._handle)
        return self

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        if self.requested is None:
            self.requested = signal.Signals(signum)
        if not self.holding and not self._raised:
            self._raised = True
            raise KeyboardInterrupt(f"{signal.Signals(signum).name} received")

    @contextlib.contextmanager
    def running(self, *, holding: bool = False) -> Iterator[CommandSignals]:
        """While the command runs: the first signal raises ``KeyboardInterrupt`` (one noted
        at start-up too, at once), unless ``holding`` (the command acts on them itself)."""
        self.holding = holding
        try:
            if not holding and self.requested is not None and not self._raised:
                self._raised = True
                raise KeyboardInterrupt(f"{self.requested.name} received")
            yield self
        finally:
            self.holding = True

    def finish(self, exiting: bool = True) -> None:
        """Teardown: both signals ignored until the process exits (the command's exit code
        stands); not ``exiting`` (a command run from Python, e.g. by a test): the handlers
        found at :meth:`install` back instead."""
        previous, self._previous = self._previous, {}
        for signum, handler in previous.items():
            signal.signal(signum, signal.SIG_IGN if exiting else handler)


def policy_of(handler: Any) -> CommandSignals | None:
    """The :class:`CommandSignals` whose handler ``handler`` is, else None (a nested guard
    may take the signals over from it, and whatever it noted)."""
    owner = getattr(handler, "__self__", None)
    return owner if isinstance(owner, CommandSignals) else None


def _deliver_pending() -> None:
    """Let a signal that is waiting (blocked) reach this process's handler now."""
    if set(signal.sigpending()) & set(SIGNALS):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, SIGNALS)
        signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)


@contextlib.contextmanager
def ignored_for_children() -> Iterator[None]:
    """Inside, processes started by this thread begin with SIGINT and SIGTERM ignored.

    A spawned process is a fresh interpreter that imports for a second or more before any of
    our code runs; a SIGINT to the process group in that time would raise inside its imports.
    An ignored disposition survives ``exec`` (a blocked mask does not), and Python leaves an
    ignored SIGINT ignored at start-up. This process loses nothing: both signals are blocked
    in this thread meanwhile, and the kernel keeps a blocked signal pending even while its
    disposition is "ignore"; when the handlers are restored and the block lifted, it is
    delivered as usual (one already pending is delivered first). Outside the main thread
    Python cannot set handlers: there only the block applies.
    """
    previous_mask = signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
    previous: dict[signal.Signals, Any] = {}
    try:
        if threading.current_thread() is threading.main_thread():
            _deliver_pending()
            for signum in SIGNALS:
                previous[signum] = signal.signal(signum, signal.SIG_IGN)
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        signal.pthread_sigmask(signal.SIG_SETMASK, previous_mask)
