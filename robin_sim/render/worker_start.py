"""The first code a render worker process runs, and how the pool starts it deaf to Ctrl-C.

A spawned worker is a fresh Python interpreter: before any of our code runs, it imports its
standard library and unpickles its arguments (MuJoCo included), for a second or more on a busy
machine. A SIGINT to the process group in that time used to raise ``KeyboardInterrupt`` inside
those imports (the worker exited with code 1 "while starting"). A blocked signal mask survives
``exec``, so the pool starts each worker with both signals blocked, inside
:func:`pil.signal_policy.blocked_for_children` (the project's one way to start a process deaf
to both). :func:`start_worker` ignores both signals (:func:`pil.signal_policy.deaf_from_now`)
and only then imports MuJoCo and the renderer; the main process ends the workers.
"""

from __future__ import annotations

from typing import Any

from pil.signal_policy import blocked_for_children, deaf_from_now

__all__ = ["blocked_for_children", "start_worker"]


def start_worker(*args: Any) -> None:
    """Process target of a render worker: keep the signals ignored, then run the worker loop."""
    deaf_from_now()
    from robin_sim.render.worker import worker_main  # MuJoCo and GL: only now

    worker_main(*args)
