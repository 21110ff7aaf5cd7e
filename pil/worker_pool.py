"""A ``spawn`` process pool for a command's parallel runs, under the command's signal policy.

Every pool the project starts (a sweep's local back end, the appearance study's episodes, the
gesture data set's chunks) is a :class:`SpawnPool`:

* its workers start with SIGINT and SIGTERM held back and ignore them from their first call
  on (:func:`pil.signal_policy.blocked_for_children`, as render workers do): a Ctrl-C to
  the process group or a SIGTERM is the command's to act on, also while a worker's
  interpreter still starts;
* a worker dies with its parent: a watcher thread ends it (within :data:`WATCH_S`) once its
  parent's pid changes, i.e. the command is gone, even by ``kill -9``;
* :meth:`SpawnPool.stop` ends the workers at once (``SIGKILL``: runs in flight are lost, not
  waited for; their finished results were handed over already), within a few seconds.
"""

from __future__ import annotations

import multiprocessing
import os
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future, ProcessPoolExecutor
from typing import Any

from pil.signal_policy import blocked_for_children, deaf_from_now

WATCH_S = 0.2  # how often a worker looks whether its parent is still there
JOIN_S = 3.0  # how long stop() waits for a killed worker to be reaped


def start_worker(initializer: Callable[..., object] | None, initargs: tuple[Any, ...]) -> None:
    """A pool worker's first call: signals ignored, the parent watched, then ``initializer``."""
    deaf_from_now()
    die_with_parent()
    if initializer is not None:
        initializer(*initargs)


def die_with_parent() -> None:
    """End this process (exit code 1) as soon as its parent is gone (its pid changes)."""
    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(WATCH_S)
        os._exit(1)

    threading.Thread(target=watch, name="parent-watch", daemon=True).start()


class SpawnPool(ProcessPoolExecutor):
    """A ``ProcessPoolExecutor`` of ``spawn`` workers deaf to signals that die with this
    process and are ended at once by :meth:`stop`. ``start_method="fork"`` is for work that
    needs this process's loaded state (the bench's entrants, :mod:`pil.bench.processes`)."""

    def __init__(
        self,
        workers: int,
        initializer: Callable[..., object] | None = None,
        initargs: tuple[Any, ...] = (),
        start_method: str = "spawn",
    ) -> None:
        super().__init__(
            workers,
            mp_context=multiprocessing.get_context(start_method),
            initializer=start_worker,
            initargs=(initializer, initargs),
        )

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future[Any]:
        """Submit ``fn(*args, **kwargs)``; a worker this starts holds the signals back."""
        with blocked_for_children():
            return super().submit(fn, *args, **kwargs)

    def stop(self) -> None:
        """Cancel the pending work and kill the workers now (idempotent)."""
        processes = list((getattr(self, "_processes", None) or {}).values())
        self.shutdown(wait=False, cancel_futures=True)
        for process in processes:
            if process.is_alive():
                process.kill()
        for process in processes:
            process.join(timeout=JOIN_S)
        if not any(process.is_alive() for process in processes):
            self.shutdown(wait=True)  # the manager thread ends, the queues are released
