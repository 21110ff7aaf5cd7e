"""Running a sweep's runs: a local process pool or a Dask cluster, behind one loop.

Both back ends are :class:`concurrent.futures.Executor` s (``ProcessPoolExecutor``, and the
``ClientExecutor`` of a ``distributed.Client``), so :func:`execute` is the same code for both.
Workers receive the run function's import path and the run's arguments, never pickled code:
a Dask worker needs nothing but the installed package.

Failure semantics: a run that raises comes back as a failed outcome with the error; a run
whose worker process dies comes back as a failed outcome too. Each failed run is retried once
(``max_attempts=2``). When a local worker dies the pool breaks and every run in flight fails
with it; those runs are then rerun one at a time, so only the run that kills its worker is
charged a failed attempt. Dask does this bookkeeping itself (``KilledWorker``).
On ``KeyboardInterrupt`` the pending runs are cancelled, local workers are stopped, and the
interrupt propagates; every outcome already handed to ``on_outcome`` was written by then.
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing
import os
import signal
import socket
import threading
import time
import traceback
from abc import ABC, abstractmethod
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, CancelledError, Executor, Future, wait
from concurrent.futures.process import BrokenProcessPool, ProcessPoolExecutor
from dataclasses import dataclass, field
from typing import Any

from pil.errors import RobinPilError, quote
from pil.experiments.sweep_grid import RunSpec, import_object
from pil.task.params import ParamSpec

DEFAULT_CONNECT_TIMEOUT_S = 10.0
WORKERS = ParamSpec(
    "workers", "int", None, "local worker processes", 1, 1024, optional=True, empty="all cores"
)
CONNECT_TIMEOUT = ParamSpec(
    "connect_timeout", "float", DEFAULT_CONNECT_TIMEOUT_S, "seconds to reach the scheduler",
    0.1, 3600.0,
)  # fmt: skip
SCHEMES: tuple[str, ...] = ("tcp", "tls", "ws", "wss")
_ERROR_LIMIT = 2000  # characters of an error kept in the results
_SLOTS_REFRESH_S = 5.0  # how often to ask a Dask cluster how many threads it has


class SchedulerError(RobinPilError):
    """A Dask scheduler that cannot be reached or used."""


class ClusterLostError(SchedulerError):
    """The connection to the Dask scheduler was lost mid-sweep (not the runs' fault)."""


# --- worker side ----------------------------------------------------------------------------
def execute_run(function: str, args: Sequence[Any], kwargs: Mapping[str, Any]) -> dict[str, Any]:
    """Run ``function(*args, **kwargs)`` in a worker; return the outcome, never raise."""
    started = time.perf_counter()
    try:
        metrics = import_object(function)(*args, **kwargs)
        if not isinstance(metrics, Mapping):
            raise TypeError(f"{function} returned {type(metrics).__name__}, not a dict")
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


def _init_worker() -> None:
    """Pool worker initializer: leave Ctrl-C to the parent; exit when orphaned.

    Workers are children of the sweep process, so a changed parent pid means the sweep is
    gone (e.g. ``kill -9``): stop within half a second instead of idling forever.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, name="orphan-watch", daemon=True).start()


# --- back ends ------------------------------------------------------------------------------
class Backend(ABC):
    """An executor that can be rebuilt after a break, with its parallelism."""

    name = "backend"

    @abstractmethod
    def executor(self) -> Executor:
        """The executor to submit runs to."""

    @abstractmethod
    def renew(self) -> None:
        """Replace a broken executor by a fresh one."""

    @abstractmethod
    def slots(self) -> int:
        """How many runs to keep in flight."""

    @abstractmethod
    def close(self, cancel: bool = False) -> None:
        """Release the executor; ``cancel`` stops runs in flight instead of waiting."""

    def lost(self) -> str | None:
        """Why the back end can no longer run anything (a lost cluster), else None."""
        return None

    def waiting(self) -> str | None:
        """What runs in flight wait for when none can progress (no workers), else None."""
        return None


class LocalBackend(Backend):
    """A process pool on this machine (``spawn`` processes: no inherited threads or locks)."""

    name = "local"

    def __init__(self, workers: int | None = None) -> None:
        self.workers = workers or os.cpu_count() or 1
        self._pool: ProcessPoolExecutor | None = None

    def executor(self) -> ProcessPoolExecutor:
        if self._pool is None:
            context = multiprocessing.get_context("spawn")
            self._pool = ProcessPoolExecutor(
                self.workers, mp_context=context, initializer=_init_worker
            )
        return self._pool

    def renew(self) -> None:
        self.close(cancel=True)

    def slots(self) -> int:
        return self.workers

    def close(self, cancel: bool = False) -> None:
        pool, self._pool = self._pool, None
        if pool is None:
            return
        if not cancel:
            pool.shutdown(wait=True)
        elif hasattr(pool, "terminate_workers"):  # Python >= 3.14
            pool.terminate_workers()
        else:  # stop runs in flight now, not when they end (the pool's own process table)
            processes = list((getattr(pool, "_processes", None) or {}).values())
            pool.shutdown(wait=False, cancel_futures=True)
            for process in processes:
                if process.is_alive():
                    process.terminate()
            for process in processes:
                process.join(timeout=5)


class DaskBackend(Backend):
    """A Dask distributed cluster, reached through its scheduler's address."""

    name = "dask"

    def __init__(self, address: str, timeout_s: float = DEFAULT_CONNECT_TIMEOUT_S) -> None:
        from distributed import Client  # imported here: the CLI must start fast

        self.address = address
        try:
            self._client = Client(address, timeout=f"{timeout_s}s", set_as_default=False)
        except (OSError, TimeoutError, ValueError) as error:
            raise SchedulerError(
                f"cannot reach the Dask scheduler at {address!r} within {timeout_s:g} s "
                f"({type(error).__name__}: {error}); start one with 'dask scheduler' and "
                "workers with 'dask worker <address>'"
            ) from None
        self._executor = self._client.get_executor(pure=False)
        self._slots, self._slots_checked = 2, -float("inf")

    def executor(self) -> Executor:
        return self._executor

    def renew(self) -> None:
        """Nothing to do: Dask replaces lost workers itself."""

    def slots(self) -> int:
        """Twice the cluster's worker threads (asked again every few seconds: workers come
        and go), at least 2."""
        if time.monotonic() - self._slots_checked > _SLOTS_REFRESH_S:
            self._slots = max(2 * sum(self._client.nthreads().values()), 2)
            self._slots_checked = time.monotonic()
        return self._slots

    def lost(self) -> str | None:
        if self._client.status in ("running", "newly-created"):
            return None
        return (
            f"lost the connection to the Dask scheduler at {self.address!r} "
            f"(client {self._client.status})"
        )

    def waiting(self) -> str | None:
        try:
            threads = sum(self._client.nthreads().values())
        except Exception:  # the scheduler is going away: lost() will say so
            return None
        if threads:
            return None
        return (
            f"waiting for Dask workers: the scheduler at {self.address!r} has none; start "
            f"them with 'dask worker {self.address} --nthreads 1'"
        )

    def close(self, cancel: bool = False) -> None:
        if self._executor is not None:
            lost = self.lost() is not None
            if lost:  # we say what happened; the client's reconnect traceback adds nothing
                logging.getLogger("distributed.client").setLevel(logging.CRITICAL)
            with contextlib.suppress(Exception):  # a lost scheduler: nothing left to release
                self._executor.shutdown(wait=not (cancel or lost))
            self._executor = None
            with contextlib.suppress(Exception):
                self._client.close(timeout=2 if lost else None)


def check_address(address: str) -> str:
    """``address`` if it reads ``SCHEME://HOST:PORT`` (or ``HOST:PORT``), else an error."""
    scheme, sep, rest = address.rpartition("://") if "://" in address else ("tcp", "", address)
    host, colon, port = rest.rpartition(":")
    good = (
        scheme in SCHEMES
        and colon
        and host.strip("[]")
        and not any(c.isspace() or c == "/" for c in host)
        and port.isdigit()
        and 0 < int(port) < 65536
    )
    if not good:
        raise SchedulerError(
            f"--scheduler must be a Dask scheduler address SCHEME://HOST:PORT (scheme "
            f"{', '.join(SCHEMES)}), e.g. tcp://127.0.0.1:8786, got {quote(address)}"
        )
    return address if sep else f"tcp://{address}"


def make_backend(
    workers: int | None = None,
    scheduler: str | None = None,
    timeout_s: float = DEFAULT_CONNECT_TIMEOUT_S,
) -> Backend:
    """A Dask back end when ``scheduler`` is given, else a local pool of ``workers``."""
    if scheduler:
        return DaskBackend(scheduler, timeout_s)
    if workers is not None and workers < 1:
        raise RobinPilError(f"--workers must be at least 1, got {workers}")
    return LocalBackend(workers)


# --- the loop -------------------------------------------------------------------------------
@dataclass
class Tally:
    """What happened in one call of :func:`execute`."""

    ok: int = 0
    failed: int = 0  # runs whose last attempt failed
    attempts: int = 0
    failed_ids: list[str] = field(default_factory=list)


OnOutcome = Callable[[RunSpec, dict[str, Any], int, bool], None]
WAIT_NOTICE_S = 10.0  # how long runs may make no progress before on_wait is told why


def execute(
    specs: Sequence[RunSpec],
    function: str,
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
    queue: deque[RunSpec] = deque(specs)
    alone: deque[RunSpec] = deque()  # runs in flight when a local worker died
    tries: dict[str, int] = {}  # attempts in this call
    bases: dict[str, int] = {}  # number of each run's first attempt in this call
    in_flight: dict[Future[dict[str, Any]], tuple[RunSpec, bool]] = {}

    def finish(spec: RunSpec, outcome: dict[str, Any], isolated: bool) -> None:
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

    def submit(spec: RunSpec, isolated: bool) -> None:
        args, kwargs = spec.call_args()
        future = backend.executor().submit(execute_run, function, args, kwargs)
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
