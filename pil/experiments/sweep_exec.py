"""Running a sweep's runs on a back end (:mod:`pil.experiments.sweep_backends`), in one loop.

The back ends (a local process pool, a Dask cluster) are :class:`concurrent.futures.Executor`
s, so :func:`execute` is the same code for both.
Workers receive the kind's run function (a module-level function, pickled by name) and the
run's typed spec (:attr:`~pil.experiments.sweep_grid.GridRow.spec`), never pickled code nor a
value to parse: a Dask worker needs nothing but the installed package.

Failure semantics: a run that raises comes back as a failed outcome with the error; a run
whose worker process dies comes back as a failed outcome too. Each failed run is retried once
(``max_attempts=2``). When a local worker dies the pool breaks and every run in flight fails
with it; those runs are then rerun one at a time, so only the run that kills its worker is
charged a failed attempt. Dask does this bookkeeping itself (``KilledWorker``).
On ``KeyboardInterrupt`` the pending runs are cancelled, local workers are stopped, and the
interrupt propagates; every outcome already handed to ``on_outcome`` was written by then.
"""

from __future__ import annotations

import os
import socket
import time
import traceback
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, CancelledError, Future, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from typing import Any

from pil.experiments.sweep_backends import Backend, SchedulerError
from pil.experiments.sweep_kinds import GridRow

_ERROR_LIMIT = 2000  # characters of an error kept in the results


class ClusterLostError(SchedulerError):
    """The connection to the Dask scheduler was lost mid-sweep (not the runs' fault)."""


# --- worker side ----------------------------------------------------------------------------
RunFunction = Callable[[Any], Mapping[str, Any]]  # a kind's run: typed spec -> metrics


def execute_run(run: RunFunction, spec: Any) -> dict[str, Any]:
    """Run ``run(spec)`` in a worker; return the outcome, never raise."""
    started = time.perf_counter()
    outcome: dict[str, Any]
    try:
        metrics = run(spec)
        if not isinstance(metrics, Mapping):
            raise TypeError(f"{run.__name__} returned {type(metrics).__name__}, not a dict")
        outcome = {"status": "ok", "error": "", "metrics": _plain_values(metrics)}
        if metrics.get("status") == "failed":  # a run function that reports its own failure
            outcome.update(status="failed", error=str(metrics.get("error") or "failed"))
    except Exception as error:
        detail = "".join(traceback.format_exception_only(type(error), error)).strip()
        outcome = {"status": "failed", "error": detail[:_ERROR_LIMIT], "metrics": {}}
    outcome["wall_s"] = time.perf_counter() - started
    outcome["host"] = f"{socket.gethostname()}:{os.getpid()}"
    return outcome


def _plain_values(metrics: Mapping[str, Any]) -> dict[str, Any]:
    """numpy scalars to Python numbers, so rows pickle small and serialise exactly."""
    plain = {}
    for key, value in metrics.items():
        item = getattr(value, "item", None)
        plain[str(key)] = item() if callable(item) and not isinstance(value, str) else value
    return plain


# --- the loop -------------------------------------------------------------------------------
@dataclass
class Tally:
    """What happened in one call of :func:`execute`."""

    ok: int = 0
    failed: int = 0  # runs whose last attempt failed
    attempts: int = 0
    failed_ids: list[str] = field(default_factory=list)


OnOutcome = Callable[[GridRow, dict[str, Any], int, bool], None]
WAIT_NOTICE_S = 10.0  # how long runs may make no progress before on_wait is told why


def execute(
    specs: Sequence[GridRow],
    run: RunFunction,
    backend: Backend,
    on_outcome: OnOutcome,
    *,
    max_attempts: int = 2,
    first_attempt: Callable[[str], int] = lambda run_id: 1,
    on_wait: Callable[[str], None] | None = None,
) -> Tally:
    """Run ``specs`` on ``backend``; call ``on_outcome(spec, outcome, attempt, final)`` per try.

    ``final`` is True when the run will not be tried again in this call (it passed, or it
    failed ``max_attempts`` times). ``first_attempt(run_id)`` numbers the first try (a resumed
    sweep continues the count). ``on_wait(message)`` is told what the sweep waits for when no
    run has ended for :data:`WAIT_NOTICE_S` (e.g. a scheduler without workers). A lost
    cluster raises :class:`ClusterLostError`; the runs in flight are not charged an attempt.
    """
    tally = Tally()
    queue: deque[GridRow] = deque(specs)
    alone: deque[GridRow] = deque()  # runs in flight when a local worker died
    tries: dict[str, int] = {}  # attempts in this call
    bases: dict[str, int] = {}  # number of each run's first attempt in this call
    in_flight: dict[Future[dict[str, Any]], tuple[GridRow, bool]] = {}

    def finish(spec: GridRow, outcome: dict[str, Any], isolated: bool) -> None:
        if spec.run_id not in tries:
            tries[spec.run_id], bases[spec.run_id] = 0, first_attempt(spec.run_id)
        count = tries[spec.run_id] = tries[spec.run_id] + 1
        tally.attempts += 1
        ok = outcome["status"] == "ok"
        final = ok or count >= max_attempts
        on_outcome(spec, outcome, bases[spec.run_id] + count - 1, final)
        if ok:
            tally.ok += 1
        elif not final:
            (alone if isolated else queue).appendleft(spec)
        else:
            tally.failed += 1
            tally.failed_ids.append(spec.run_id)

    def submit(spec: GridRow, isolated: bool) -> None:
        future = backend.executor().submit(execute_run, run, spec.spec)
        in_flight[future] = (spec, isolated)

    def check_cluster(error: BaseException | None = None) -> None:
        reason = backend.lost()
        if reason is None and isinstance(error, CancelledError):
            reason = f"a run was cancelled by the cluster ({type(error).__name__})"
        if reason is not None:
            raise ClusterLostError(
                f"{reason}; {len(in_flight) + len(done_now)} runs in flight are not charged "
                "an attempt"
            ) from None

    done_now: set[Future[dict[str, Any]]] = set()
    try:
        while queue or alone or in_flight:
            try:
                if alone:
                    if not in_flight:
                        submit(alone.popleft(), True)
                else:
                    while queue and len(in_flight) < backend.slots():
                        submit(queue.popleft(), False)
            except (OSError, RuntimeError, TimeoutError) as error:  # the scheduler went away
                check_cluster(error)
                raise
            done_now, _ = wait(list(in_flight), timeout=WAIT_NOTICE_S, return_when=FIRST_COMPLETED)
            if not done_now:
                check_cluster()
                message = backend.waiting()
                if message is not None and on_wait is not None:
                    on_wait(message)
                continue
            broken = False
            for future in list(done_now):
                spec, isolated = in_flight[future]
                try:
                    outcome = future.result()
                except BrokenProcessPool as error:
                    del in_flight[future]
                    done_now.discard(future)
                    broken = True
                    if isolated:
                        finish(spec, _lost(error, "worker process died"), True)
                    else:
                        alone.append(spec)  # a suspect: rerun it alone to find the culprit
                    continue
                except Exception as error:  # e.g. Dask's KilledWorker
                    check_cluster(error)  # a lost connection is not the run's fault
                    outcome = _lost(error)
                del in_flight[future]
                done_now.discard(future)
                finish(spec, outcome, isolated)
            if broken:
                for future in list(in_flight):  # they all fail with the broken pool
                    alone.append(in_flight.pop(future)[0])
                backend.renew()
    except BaseException:
        for future in in_flight:
            future.cancel()
        backend.close(cancel=True)
        raise
    return tally


def _lost(error: BaseException, what: str = "run lost") -> dict[str, Any]:
    """The outcome of a run whose result never came back."""
    text = f"{what}: {type(error).__name__}: {error}"
    return {"status": "failed", "error": text[:_ERROR_LIMIT], "metrics": {}, "wall_s": None}
