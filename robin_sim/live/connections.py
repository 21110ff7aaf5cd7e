"""The live server's connections: the listening socket (:func:`bind`), a cap on connections,
the cheapest dropped first, and quiet resource errors.

aiohttp closes a connection whose request headers are not complete within its
``keepalive_timeout`` of connecting (or of the previous response), which this server sets to
:attr:`Limits.header_timeout_s`; a client that sends half a request and waits is dropped then.
What aiohttp does not bound is how many connections are open at once: every one holds a file
descriptor, and once the process runs out, ``accept()`` fails with EMFILE, asyncio logs a
traceback for each try, and new visitors wait. :class:`Connections` therefore wraps aiohttp's
protocol for each accepted socket (:class:`GuardedConnection`) and keeps at most
:attr:`Limits.max_connections` open (fewer when the descriptor limit is low): a newcomer over
the cap closes the oldest connection that has not yet sent a whole request (a half-open one,
the cheapest to lose); if every connection is serving, the newcomer gets a short 503. The
loop's exception handler (:meth:`Connections.loop_exception`) logs an accept failure once, in
one line, and :data:`HTTP_LOG`, aiohttp's logger here, logs a client that went away while being
answered (a closed tab: ``ClientConnectionResetError``) or malformed HTTP (a 400) in one
line, without the traceback.
:meth:`Connections.abort_all` drops whatever is left when the server stops, so a
client that never reads cannot hold the exit up.
"""

from __future__ import annotations

import asyncio
import errno
import logging
import resource
import socket
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from aiohttp import web
from aiohttp.http_exceptions import HttpProcessingError

from pil.errors import RobinPilError, quote

LOG = logging.getLogger(__name__)
HTTP_LOG = logging.getLogger("robin_sim.live.http")  # given to aiohttp's request handlers
RESERVED_FDS = 96  # descriptors kept for the engine (a running session holds about 12), logs
# Connections asyncio accepts in one go: each holds a descriptor until the loop's next pass, and
# one dropped for it holds its own until then: the cap leaves room for a few bursts.
ACCEPT_BURST = 16
LISTEN_QUEUE = 128  # connections the kernel holds for us meanwhile (they cost no descriptor)
BUSY_BODY = b"503: too many connections now\r\n"
BUSY_REPLY = (
    b"HTTP/1.1 503 Service Unavailable\r\nContent-Type: text/plain\r\nConnection: close\r\n"
    b"Content-Length: %d\r\n\r\n%s" % (len(BUSY_BODY), BUSY_BODY)
)


class OneLineClientErrors(logging.Filter):
    """A record about a client's fault (it went away, or sent malformed HTTP): one warning
    line, no traceback."""

    def filter(self, record: logging.LogRecord) -> bool:
        error = record.exc_info[1] if record.exc_info else None
        if isinstance(error, ConnectionError):
            record.msg = "a client went away while being answered (%s: %s)"
        elif isinstance(error, HttpProcessingError):
            record.msg = "refused a malformed request (%s: %s)"
        else:
            return True
        record.args = (type(error).__name__, " ".join(str(error).split())[:200])
        record.exc_info, record.exc_text = None, None
        record.levelno, record.levelname = logging.WARNING, "WARNING"
        return True


HTTP_LOG.addFilter(OneLineClientErrors())


@dataclass(frozen=True)
class Limits:
    """How long and how many: the server's bounds on its HTTP clients."""

    header_timeout_s: float = 10.0  # whole request headers within this of connecting / a reply
    max_connections: int = 64  # open at once (lowered to what the descriptor limit allows)
    close_timeout_s: float = 1.0  # what closing the tabs may take when the run ends

    def connection_cap(self) -> int:
        """:attr:`max_connections`, or fewer when the process may open few descriptors."""
        soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
        if soft == resource.RLIM_INFINITY:
            return self.max_connections
        return max(4, min(self.max_connections, soft - RESERVED_FDS - 4 * ACCEPT_BURST))


class GuardedConnection(asyncio.Protocol):
    """aiohttp's protocol for one socket, counted by :class:`Connections` (calls pass through)."""

    def __init__(self, inner: asyncio.Protocol, owner: Connections) -> None:
        self.inner, self.owner = inner, owner
        self.transport: asyncio.Transport | None = None
        self.opened = time.monotonic()
        self.served = False  # a whole request has arrived (the app saw it)
        self.admitted = False  # under the cap: aiohttp's protocol has the socket

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self.transport = transport  # type: ignore[assignment]
        if not self.owner.admit(self):
            transport.write(BUSY_REPLY)  # type: ignore[attr-defined]
            transport.close()
            return
        self.admitted = True
        self.inner.connection_made(transport)

    def data_received(self, data: bytes) -> None:
        if self.admitted:
            self.inner.data_received(data)

    def eof_received(self) -> bool | None:
        return self.inner.eof_received() if self.admitted else None

    def pause_writing(self) -> None:
        if self.admitted:
            self.inner.pause_writing()

    def resume_writing(self) -> None:
        if self.admitted:
            self.inner.resume_writing()

    def connection_lost(self, exc: Exception | None) -> None:
        self.owner.release(self)
        if self.admitted:
            self.inner.connection_lost(exc)


class Connections:
    """The open connections of one server (see the module doc)."""

    def __init__(self, limits: Limits) -> None:
        self.limits = limits
        self.cap = limits.connection_cap()
        self.open: dict[asyncio.BaseTransport, GuardedConnection] = {}  # in order of arrival
        self.dropped = self.refused = 0
        self._said: set[str] = set()

    def factory(self, make: Callable[[], asyncio.Protocol]) -> Callable[[], asyncio.Protocol]:
        """A protocol factory for ``loop.create_server`` around aiohttp's ``make``."""
        return lambda: GuardedConnection(make(), self)

    def admit(self, connection: GuardedConnection) -> bool:
        """Count a new connection; over the cap, drop the oldest half-open one or refuse."""
        if len(self.open) >= self.cap:
            waiting = next((c for c in self.open.values() if not c.served), None)
            if waiting is None:
                self.refused += 1
                self._say_once(
                    "busy",
                    "%d connections are open (the cap): refusing new ones "
                    "with 503 until some close",
                    self.cap,
                )
                return False
            self.dropped += 1
            self._say_once(
                "drop",
                "%d connections are open (the cap): dropping the oldest "
                "that have not sent a whole request",
                self.cap,
            )
            self._forget(waiting)
        assert connection.transport is not None
        self.open[connection.transport] = connection
        return True

    def release(self, connection: GuardedConnection) -> None:
        """Forget a closed connection."""
        if connection.transport is not None:
            self.open.pop(connection.transport, None)

    def served(self, request: web.Request) -> None:
        """The app got a whole request on this connection: it is no longer half-open."""
        connection = self.open.get(request.transport) if request.transport else None
        if connection is not None:
            connection.served = True

    def abort_all(self) -> None:
        """Drop every connection still open (the server is stopping)."""
        for connection in list(self.open.values()):
            self._forget(connection)

    def _forget(self, connection: GuardedConnection) -> None:
        """Drop ``connection`` now (its ``connection_lost`` follows in the next loop pass)."""
        transport = connection.transport
        if transport is not None:
            self.open.pop(transport, None)
            transport.abort()

    def loop_exception(self, loop: asyncio.AbstractEventLoop, context: dict[str, Any]) -> None:
        """The loop's exception handler: resource errors of ``accept()`` in one line, once."""
        error = context.get("exception")
        if isinstance(error, OSError) and "accept" in str(context.get("message", "")):
            self._say_once(
                "accept",
                "cannot accept connections: %s (the process is out of "
                "descriptors or memory); retrying",
                error.strerror or error,
            )
            return
        if isinstance(error, ConnectionError):  # a client went away under a callback
            LOG.warning("a client went away (%s: %s)", type(error).__name__, error)
            return
        loop.default_exception_handler(context)

    def _say_once(self, key: str, message: str, *args: object) -> None:
        if key not in self._said:
            self._said.add(key)
            LOG.warning(message, *args)


class GuardedSite(web.SockSite):
    """A :class:`aiohttp.web.SockSite` whose connections go through :class:`Connections`."""

    def __init__(self, runner: web.BaseRunner, sock: Any, connections: Connections) -> None:
        super().__init__(runner, sock, backlog=ACCEPT_BURST)
        self.connections = connections

    async def start(self) -> None:
        await web.BaseSite.start(self)  # registers the site with the runner
        server = self._runner.server
        assert server is not None
        loop = asyncio.get_running_loop()
        self._server = await loop.create_server(
            self.connections.factory(server), sock=self._sock, backlog=self._backlog
        )
        self._sock.listen(LISTEN_QUEUE)  # asyncio's listen() took the burst size; Linux updates


def bind(host: str, port: int) -> socket.socket:
    """A listening socket on ``host``:``port``, or one clear error."""
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
    except socket.gaierror as problem:
        raise RobinPilError(
            f"--host {quote(host)} is not an address of this machine "
            f"({problem.strerror}); e.g. 127.0.0.1"
        ) from None
    family, _, _, _, address = infos[0]
    sock = socket.socket(family, socket.SOCK_STREAM)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind(address)
        sock.listen(128)
    except OSError as problem:
        sock.close()
        if problem.errno == errno.EADDRINUSE:
            raise RobinPilError(
                f"--port {port} is in use on {host}; choose another port "
                "(or --port 0 for any free one)"
            ) from None
        raise RobinPilError(f"cannot listen on {host}:{port}: {problem.strerror}") from None
    sock.setblocking(False)
    return sock
