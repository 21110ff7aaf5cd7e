"""Bench runs in worker processes that notice a worker ending under them.

What no guard inside a process can catch is the process itself ending: an entrant that calls
``os._exit``, a segmentation fault in an extension, the kernel's out-of-memory killer. The
bench therefore runs an external entrant's runs in forked processes and watches them:

* :func:`run_in_child` runs one task in a forked process and returns its row, re-raises what
  the task raised, or raises :class:`RunEndedError` with the process's exit status when it ended
  without an answer;
* :func:`run_ordered` runs tasks in a pool of forked workers (:class:`pil.worker_pool.SpawnPool`
  with ``fork``), handing back rows in the tasks' order. A worker that ends breaks the pool
  (``BrokenProcessPool``); the runs that were in flight are then run again one at a time in
  :func:`run_in_child`, so the run that ends its process is named (:class:`RunEndedError`), and
  the rest go on in a fresh pool when none does (a crash that does not come back).
"""

from __future__ import annotations

import multiprocessing
import signal
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool
from multiprocessing.connection import Connection, wait
from typing import Any, TypeVar

from pil.signal_policy import blocked_for_children
from pil.worker_pool import SpawnPool, start_worker

TaskT = TypeVar("TaskT")
AHEAD = 2  # tasks queued per worker beyond the one it runs


class RunEndedError(Exception):
    """A run's process ended without handing back a row or an error."""

    def __init__(self, exitcode: int | None, task: object = None) -> None:
        self.exitcode, self.task = exitcode, task
        super().__init__(ended_how(exitcode))


def ended_how(exitcode: int | None) -> str:
    """Words for a process's end: its exit status, or the signal that killed it."""
    if exitcode is not None and exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = f"signal {-exitcode}"
        return f"its process was killed by {name} before the run ended"
    return f"its process ended (exit status {exitcode}) before the run ended"


def _child(work: Callable[[TaskT], Any], task: TaskT, answer: Connection) -> None:
    start_worker(None, ())  # deaf to SIGINT and SIGTERM, dies with the bench
    try:
        outcome: tuple[str, Any] = ("row", work(task))
    except BaseException as error:  # handed to the bench, which decides
        outcome = ("error", error)
    answer.send(outcome)
    answer.close()


def run_in_child(work: Callable[[TaskT], Any], task: TaskT) -> Any:
    """``work(task)`` in a forked process: its row, its exception, or :class:`RunEndedError`."""
    context = multiprocessing.get_context("fork")
    receive, send = context.Pipe(duplex=False)
    with blocked_for_children():
        process = context.Process(target=_child, args=(work, task, send), daemon=True)
        process.start()
    send.close()
    try:
        wait([receive])  # an answer, or the end of the pipe when the process is gone
        try:
            kind, value = receive.recv()
        except EOFError:
            process.join()
            raise RunEndedError(process.exitcode) from None
        process.join()
    finally:
        receive.close()
        if process.is_alive():  # Ctrl-C or SIGTERM to the bench while the run went on
            process.kill()
            process.join()
    if kind == "error":
        raise value
    return value


def run_ordered(
    work: Callable[[TaskT], Any], tasks: Sequence[TaskT], workers: int
) -> Iterator[tuple[TaskT, Any]]:
    """``(task, row)`` for every task in order, ``workers`` forked processes running them;
    :class:`RunEndedError` (with the task as ``.task``) for a run that ends its process."""
    rest: deque[TaskT] = deque(tasks)
    while rest:
        pool = SpawnPool(workers, start_method="fork")
        flight: deque[tuple[TaskT, Future[Any]]] = deque()
        try:
            while rest or flight:
                while rest and len(flight) < workers * (1 + AHEAD):
                    flight.append((rest[0], pool.submit(work, rest[0])))
                    rest.popleft()
                task, future = flight[0]
                row = future.result()
                flight.popleft()
                yield task, row
        except BrokenProcessPool:  # a worker ended: the runs in flight go again, one by one
            rest.extendleft(reversed([t for t, _ in flight]))
            yield from _alone(work, rest, max(len(flight), 1))
        finally:
            pool.stop()


def _alone(
    work: Callable[[TaskT], Any], rest: deque[TaskT], count: int
) -> Iterator[tuple[TaskT, Any]]:
    """Run the first ``count`` tasks of ``rest`` one at a time in a process of their own."""
    for _ in range(min(count, len(rest))):
        task = rest.popleft()
        try:
            row = run_in_child(work, task)
        except RunEndedError as ended:
            raise RunEndedError(ended.exitcode, task) from None
        yield task, row
