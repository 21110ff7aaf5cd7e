"""The first code a render worker process runs, and how the pool starts it deaf to Ctrl-C.

A spawned worker is a fresh Python interpreter: before any of our code runs, it imports its
standard library and unpickles its arguments (MuJoCo included), for a second or more on a busy
machine. A SIGINT to the process group in that time used to raise ``KeyboardInterrupt`` inside
those imports (the worker exited with code 1 "while starting"). Blocking the signals does not
help: the blocked mask does not survive the spawn. An *ignored* disposition does survive
``exec``, and Python leaves an ignored SIGINT ignored at start-up, so the pool starts each worker
inside :func:`pil.signal_policy.ignored_for_children` (the project's one way to start a
process deaf to both). :func:`start_worker` sets both signals to ignored again
(they stay so) and only then imports MuJoCo and the renderer; the main process ends the workers.
"""

from __future__ import annotations

import signal
from typing import Any

from pil.signal_policy import ignored_for_children
from robin_sim.render.worker_signals import SIGNALS

__all__ = ["ignored_for_children", "start_worker"]


def start_worker(*args: Any) -> None:
    """Process target of a render worker: keep the signals ignored, then run the worker loop."""
    for signum in SIGNALS:
        signal.signal(signum, signal.SIG_IGN)
    from robin_sim.render.worker import worker_main  # MuJoCo and GL: only now

    worker_main(*args)
