"""The first code a render worker process runs: ignore Ctrl-C and SIGTERM, then import the rest.

The pool starts workers with both signals blocked (:func:`blocked_signals`, inherited through
``exec``). This module imports nothing heavy, so no library thread that could accept the
signal exists yet when :func:`start_worker` sets both to ignored and lifts the block; only then
are MuJoCo and the renderer imported. A Ctrl-C sent to the whole process group at any moment
therefore reaches only the main process, which ends the workers itself.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from typing import Any

from robin_sim.render.worker_signals import SIGNALS


@contextlib.contextmanager
def blocked_signals() -> Iterator[None]:
    """SIGINT and SIGTERM blocked in this thread inside; processes started here inherit it.

    This process loses nothing: another of its threads takes a signal that comes meanwhile
    and Python runs the handler in the main thread as usual.
    """
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def start_worker(*args: Any) -> None:
    """Process target of a render worker: ignore the signals, then run the worker loop."""
    if threading.current_thread() is threading.main_thread():
        for signum in SIGNALS:
            signal.signal(signum, signal.SIG_IGN)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, SIGNALS)
    from robin_sim.render.worker import worker_main  # MuJoCo and GL: only now

    worker_main(*args)
