"""Where a sweep's runs execute: a local process pool or a Dask cluster, behind one interface.

Both back ends are :class:`concurrent.futures.Executor` s (``ProcessPoolExecutor``, and the
``ClientExecutor`` of a ``distributed.Client``), so :func:`pil.experiments.sweep_exec.execute`
is the same code for both. A back end also says when it can no longer run anything (a lost
Dask scheduler) and what runs in flight wait for (a scheduler without workers).
"""

from __future__ import annotations

import contextlib
import gc
import logging
import os
import time
from abc import ABC, abstractmethod
from concurrent.futures import Executor

from pil.errors import RobinPilError, quote
from pil.extras import require_extra
from pil.task.params import ParamSpec
from pil.worker_pool import SpawnPool

DEFAULT_CONNECT_TIMEOUT_S = 10.0
WORKERS = ParamSpec(
    "workers", "int", None, "local worker processes", 1, 1024, optional=True, empty="all cores"
)
CONNECT_TIMEOUT = ParamSpec(
    "connect_timeout",
    "float",
    DEFAULT_CONNECT_TIMEOUT_S,
    "seconds to reach the scheduler",
    0.1,
    3600.0,
)
SCHEMES: tuple[str, ...] = ("tcp", "tls", "ws", "wss")
TLS_SCHEMES: tuple[str, ...] = ("tls", "wss")  # these need Dask's TLS settings
_SLOTS_REFRESH_S = 5.0  # how often to ask a Dask cluster how many threads it has


class SchedulerError(RobinPilError):
    """A Dask scheduler that cannot be reached or used."""


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
    """A process pool on this machine (:class:`pil.worker_pool.SpawnPool`: ``spawn``
    processes, deaf to signals, ended with the sweep, even by ``kill -9``)."""

    name = "local"

    def __init__(self, workers: int | None = None) -> None:
        self.workers = workers or os.cpu_count() or 1
        self._pool: SpawnPool | None = None

    def executor(self) -> SpawnPool:
        if self._pool is None:
            self._pool = SpawnPool(self.workers)
        return self._pool

    def renew(self) -> None:
        self.close(cancel=True)

    def slots(self) -> int:
        return self.workers

    def close(self, cancel: bool = False) -> None:
        pool, self._pool = self._pool, None
        if pool is None:
            return
        if cancel:  # stop runs in flight now, not when they end
            pool.stop()
        else:
            pool.shutdown(wait=True)


_DASK_LOGGERS = ("distributed", "distributed.client", "tornado", "tornado.application")


class _OneLineRecords(logging.Filter):
    """Dask's and tornado's log records without their tracebacks, one line each, and without
    tornado's "Exception in callback" for a discarded internal future (a closed comm): when the
    scheduler goes away, the sweep says so itself (:meth:`DaskBackend.lost`); the comm stack
    of the library's internals adds nothing for the user."""

    def filter(self, record: logging.LogRecord) -> bool:
        if record.name == "tornado.application" and str(record.msg).startswith(
            "Exception in callback"
        ):
            return False
        record.exc_info, record.exc_text, record.stack_info = None, None, None
        record.msg, record.args = record.getMessage().splitlines()[0] if record.msg else "", ()
        return True


def _one_line_dask_logs() -> None:
    """Put :class:`_OneLineRecords` on the handlers Dask configures (once per handler)."""
    for name in _DASK_LOGGERS:
        for handler in logging.getLogger(name).handlers:
            if not any(isinstance(f, _OneLineRecords) for f in handler.filters):
                handler.addFilter(_OneLineRecords())


class DaskBackend(Backend):
    """A Dask distributed cluster, reached through its scheduler's address."""

    name = "dask"

    def __init__(self, address: str, timeout_s: float = DEFAULT_CONNECT_TIMEOUT_S) -> None:
        require_extra("cluster")
        from distributed import Client  # imported here: the CLI must start fast

        _one_line_dask_logs()
        self.address = address
        try:
            self._client = Client(address, timeout=f"{timeout_s}s", set_as_default=False)
        except (OSError, TimeoutError, ValueError, TypeError) as error:  # TypeError: TLS unset
            problem = f"{type(error).__name__}: {error}"
        else:
            problem = ""
        if problem:
            # The half-built client is garbage now: collect it here. Left to a later, random
            # collection, its __del__ may run inside another Dask event-loop thread while that
            # thread starts, and block it on distributed's loop lock (seen as "loop is None").
            gc.collect()
            raise SchedulerError(
                f"cannot reach the Dask scheduler at {address!r} within {timeout_s:g} s "
                f"({problem}); start one with 'dask scheduler' and workers with "
                "'dask worker <address>'"
            )
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
    if scheme in TLS_SCHEMES and not _tls_configured():
        raise SchedulerError(
            f"--scheduler {quote(address)}: a {scheme}:// scheduler needs Dask's TLS settings "
            "(distributed.comm.tls.ca-file, .client.cert and .client.key in the Dask config, "
            "e.g. ~/.config/dask/distributed.yaml); none are set: configure them or use tcp://"
        )
    return address if sep else f"tcp://{address}"


def _tls_configured() -> bool:
    """Whether Dask's configuration names a CA file or a client certificate for TLS."""
    import dask.config  # imported here: the CLI must start fast

    return any(
        dask.config.get(key, None)
        for key in ("distributed.comm.tls.ca-file", "distributed.comm.tls.client.cert")
    )


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
