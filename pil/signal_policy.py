"""One way for every ``robin-pil`` command to meet Ctrl-C (SIGINT) and SIGTERM.

:class:`CommandSignals` is installed on ``main``'s first line and holds both signals for the
command's whole life, whatever disposition the process inherited (a shell's background job
or ``nohup ... &`` starts with SIGINT ignored; a service manager sends SIGTERM):

* **start-up** (imports, option parsing): a signal is only noted, so none lands inside an
  import; the command then ends with 130 before it starts (or, if it holds signals itself,
  such as the episode, it takes the noted signal over and leaves its files consistent);
* **running**: the first SIGINT or SIGTERM raises ``KeyboardInterrupt`` in the main thread,
  as Ctrl-C does in plain Python, so every command's ``finally`` blocks keep its finished work
  (never inside an import: the commands import their heavy modules as they run, and a signal
  there is raised once the import is done);
  further signals are noted, never raised again inside that clean-up. A command that holds
  signals (:attr:`holding`) keeps them noted: its own guard acts on them between two steps
  (an episode's guard takes them over in either case, also inside another command);
* **teardown** (the command returned; its summary is written): both signals are ignored until
  the process exits, so a late SIGTERM can no longer turn a finished run into a -15.

Processes a command starts itself (worker pools) begin with both signals held back and
ignore them from their first call (:func:`blocked_for_children`, :func:`deaf_from_now`); the
command stops them (:mod:`pil.worker_pool`).
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
from collections.abc import Iterator
from types import FrameType
from typing import Any

SIGNALS: tuple[signal.Signals, ...] = (signal.SIGINT, signal.SIGTERM)
INTERRUPTED = 130  # the exit code of an interrupted command (128 + SIGINT), for both signals
RETRY_S = 0.02  # a signal that came inside an import is sent again this much later


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
        self._deferred = 0  # inside signals_deferred(): how deep
        self._previous: dict[signal.Signals, Any] = {}

    @property
    def raised(self) -> bool:
        """Whether a signal was raised as ``KeyboardInterrupt``: any exception after it comes
        from the interrupt unwinding (e.g. the ``ImportError`` of a C extension whose
        initialisation it broke into) and is reported as the interrupt."""
        return self._raised

    def install(self) -> CommandSignals:
        """Take both signals now, whatever they were (ignored included); main thread only."""
        if threading.current_thread() is threading.main_thread():
            for signum in SIGNALS:
                self._previous[signum] = signal.signal(signum, self._handle)
        return self

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        if self.requested is None:
            self.requested = signal.Signals(signum)
        if self.holding or self._raised or self._deferred:
            return
        if _importing(frame):  # never inside an import: the signal again, once it is done
            retry = threading.Timer(RETRY_S, os.kill, (os.getpid(), signum))
            retry.daemon = True
            retry.start()
            return
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

    @contextlib.contextmanager
    def deferring(self) -> Iterator[None]:
        """Inside, a signal is noted only; one noted meanwhile is raised as the block ends."""
        noted = self.requested
        self._deferred += 1
        try:
            yield
        finally:
            self._deferred -= 1
        came = self.requested
        quiet = self._deferred or self.holding or self._raised
        if came is not None and noted is None and not quiet:
            self._raised = True
            raise KeyboardInterrupt(f"{came.name} received")

    def finish(self, exiting: bool = True) -> None:
        """Teardown: both signals ignored until the process exits (the command's exit code
        stands); not ``exiting`` (a command run from Python, e.g. by a test): the handlers
        found at :meth:`install` back instead."""
        previous, self._previous = self._previous, {}
        for signum, handler in previous.items():
            signal.signal(signum, signal.SIG_IGN if exiting else handler)


def _importing(frame: FrameType | None) -> bool:
    """Whether ``frame`` runs inside an import (a module's code, or a C extension's
    initialisation: a ``KeyboardInterrupt`` there leaves a half-made module, or comes out as
    ``ImportError: initialization failed`` and makes Python exit by SIGINT, -2, at the end)."""
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib._bootstrap"):
            return True
        frame = frame.f_back
    return False


def policy_of(handler: Any) -> CommandSignals | None:
    """The :class:`CommandSignals` whose handler ``handler`` is, else None (a nested guard
    may take the signals over from it, and whatever it noted)."""
    owner = getattr(handler, "__self__", None)
    return owner if isinstance(owner, CommandSignals) else None


@contextlib.contextmanager
def signals_deferred() -> Iterator[None]:
    """Inside, the command's policy raises no signal: one that comes is raised as the block
    ends, so what is written inside (a journal line and its record in memory) is written whole.
    (Python runs every handler in the main thread, whichever thread the kernel gave the signal
    to, so a blocked mask in this thread would not hold it back.) Without a policy: nothing."""
    policy = policy_of(signal.getsignal(signal.SIGTERM))
    if policy is None:
        yield
        return
    with policy.deferring():
        yield


@contextlib.contextmanager
def blocked_for_children(*, spawning: bool = True) -> Iterator[None]:
    """Inside, processes started by this thread begin with SIGINT and SIGTERM held back; their
    first call (e.g. :func:`robin_sim.render.worker_start.start_worker`) ignores both and lets
    go of them, so a signal that came meanwhile is dropped there.

    A spawned process is a fresh interpreter that imports for a second or more before any of
    our code runs; a SIGINT to the process group in that time would raise inside its imports.
    A blocked signal mask survives ``fork`` and ``exec``, so both signals are blocked in this
    thread while it starts processes. This process loses nothing: its handlers stay as they
    are, a signal is taken by another of its threads or waits until the block is lifted.
    (Setting them to "ignore" instead would survive ``exec`` as well, but a signal that
    another thread of this process took meanwhile, or this one once multiprocessing lifted
    its block, would be lost.) With ``spawning`` (multiprocessing processes; False: only
    ``subprocess`` ones, which hold the signals back for their whole life) the multiprocessing
    resource tracker is started first: its start unblocks both signals in the thread that
    starts it.
    """
    if spawning:
        from multiprocessing import resource_tracker

        resource_tracker.ensure_running()  # the first spawn's start of it would lift the block
    previous_mask = signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous_mask)


def deaf_from_now() -> None:
    """A started process's first call: SIGINT and SIGTERM ignored from now on (one held back
    since its start (:func:`blocked_for_children`) is dropped), and no longer blocked."""
    for signum in SIGNALS:
        signal.signal(signum, signal.SIG_IGN)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, SIGNALS)
