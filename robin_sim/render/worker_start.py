"""The first code a render worker process runs, and how the pool starts it deaf to Ctrl-C.

A spawned worker is a fresh Python interpreter: before any of our code runs, it imports its
standard library and unpickles its arguments (MuJoCo included), for a second or more on a busy
machine. A SIGINT to the process group in that time used to raise ``KeyboardInterrupt`` inside
those imports (the worker exited with code 1 "while starting"). Blocking the signals does not
help: the blocked mask does not survive the spawn. An *ignored* disposition does survive
``exec``, and Python leaves an ignored SIGINT ignored at start-up, so the pool starts each worker
inside :func:`ignored_for_children`. :func:`start_worker` sets both signals to ignored again
(they stay so) and only then imports MuJoCo and the renderer; the main process ends the workers.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from typing import Any

from robin_sim.render.worker_signals import SIGNALS


def _deliver_pending() -> None:
    """Let a signal that is waiting (blocked) reach this process's handler now."""
    if set(signal.sigpending()) & set(SIGNALS):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, SIGNALS)
        signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)


@contextlib.contextmanager
def ignored_for_children() -> Iterator[None]:
    """Inside, processes started by this thread begin with SIGINT and SIGTERM ignored.

    This process loses nothing: both signals are blocked in this thread meanwhile, and the
    kernel keeps a blocked signal pending even while its disposition is "ignore"; when the
    handlers are restored and the block lifted, it is delivered as usual. One that was already
    pending is delivered first. (A signal taken by another thread of this process while inside
    would be ignored; the episode starts its pool from its only thread.) Outside the main
    thread (the live server's session thread) Python cannot set handlers: there only the block
    applies, as before, and a worker is deaf to the signals from :func:`start_worker` on.
    """
    previous_mask = signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
    previous: dict[signal.Signals, Any] = {}
    try:
        if threading.current_thread() is threading.main_thread():  # else: only the block
            _deliver_pending()  # (Python sets handlers in the main thread only, e.g. not in
            for signum in SIGNALS:  # the live server's session thread)
                previous[signum] = signal.signal(signum, signal.SIG_IGN)
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        signal.pthread_sigmask(signal.SIG_SETMASK, previous_mask)


def start_worker(*args: Any) -> None:
    """Process target of a render worker: keep the signals ignored, then run the worker loop."""
    for signum in SIGNALS:
        signal.signal(signum, signal.SIG_IGN)
    from robin_sim.render.worker import worker_main  # MuJoCo and GL: only now

    worker_main(*args)
