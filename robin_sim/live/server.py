"""The live page's web server (aiohttp): the page, its own static files and a WebSocket per tab.

``GET /`` serves the page, ``GET /static/NAME`` one of the page's files (a fixed list: no path
from a request ever reaches the file system), ``GET /ws`` the WebSocket. The first tab that
connects controls the session; later tabs watch read-only. To every tab the server pushes each
new frame as one binary message (a 4-byte big-endian header length, a JSON header with ``seq``,
``sim_time``, ``captured_ms`` = the wall-clock time in ms when physics was rendered, and the
JPEG) and the session's status as JSON a few times a second. A lagging tab gets the newest frame
when it is ready again; older ones are dropped, and physics never waits for a socket.

The run (:class:`robin_sim.live.conductor.Conductor`) is one session, or a protocol's blocks one
after another, each behind an instruction screen. A closed controlling tab saves the session as
``closed`` and stops the server; so do SIGINT and SIGTERM, with ``interrupted``.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import secrets
import signal
import socket
import struct
import time
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from aiohttp import WSMsgType, web

from robin_sim.live.commands import parse_command
from robin_sim.live.conductor import Conductor
from robin_sim.live.connections import HTTP_LOG, Connections, GuardedSite, Limits, bind
from robin_sim.live.experimenter import experimenter_view
from robin_sim.live.guard import Guard, is_loopback
from robin_sim.live.hands.vendor import TEXT_TYPES, VENDOR_DIR, VENDOR_TYPES
from robin_sim.live.inputs import LiveInputError
from robin_sim.live.session import Frame

LOG = logging.getLogger(__name__)
__all__ = ["LiveServer", "bind", "is_loopback", "new_token"]
STATIC_DIR = Path(__file__).with_name("static")
STATIC_TYPES = {  # all /static/ serves
    "live.js": "text/javascript",
    "live.css": "text/css",
    "experimenter.js": "text/javascript",
    "questionnaire.js": "text/javascript",
    "questionnaire.css": "text/css",
    "webcam.js": "text/javascript",
}
RATE_LIMIT = 20  # messages per second from one tab; more are dropped with an error reply
STATUS_HZ = 5.0  # status messages per second
MAX_MESSAGE_BYTES = 1 << 20  # larger closes the socket (1009); parse_input refuses > 4 KiB
SEND_BUFFER_BYTES = 128 * 1024  # kernel send buffer of a tab's socket: a few frames, not seconds
EXAMPLE = '{"type": "thumb", "value": "up"}'  # a valid message, for error replies
QUEUED_TEXTS = 64  # text messages waiting for one tab; beyond, the oldest are dropped


def new_token() -> str:
    """A fresh access token for a server reachable from other machines."""
    return secrets.token_urlsafe(16)


def frame_message(seq: int, sim_time: float, captured: float, jpeg: bytes) -> bytes:
    """One frame as the page reads it; ``captured`` is a ``time.monotonic()`` reading."""
    now_ms = time.time() * 1000.0
    captured_ms = now_ms - (time.monotonic() - captured) * 1000.0
    header = json.dumps(
        {
            "seq": seq,
            "sim_time": round(sim_time, 4),
            "captured_ms": round(captured_ms, 2),
            "sent_ms": round(now_ms, 2),
        }
    ).encode()
    return struct.pack(">I", len(header)) + header + jpeg


@dataclass(eq=False)
class Tab:
    """One connected tab: its socket, role, what waits to be sent, and its recent inputs."""

    ws: web.WebSocketResponse
    role: str  # "control" | "watch" | "experimenter"
    frame: bytes | None = None  # the newest frame not yet sent (older ones are dropped)
    status: dict[str, Any] | None = None  # the newest status not yet sent
    view: dict[str, Any] | None = None  # the newest experimenter's view not yet sent
    texts: deque[dict[str, Any]] = field(default_factory=lambda: deque(maxlen=QUEUED_TEXTS))
    wake: asyncio.Event = field(default_factory=asyncio.Event)
    recent: deque[float] = field(default_factory=deque)  # monotonic times of the last second
    frames_dropped: int = 0

    def send(self, message: dict[str, Any]) -> None:
        self.texts.append(message)
        self.wake.set()

    def over_rate(self, now: float) -> bool:
        """Count one message; True when it is over :data:`RATE_LIMIT` in the last second."""
        while self.recent and now - self.recent[0] >= 1.0:
            self.recent.popleft()
        if len(self.recent) >= RATE_LIMIT:
            return True
        self.recent.append(now)
        return False


class LiveServer:
    """The aiohttp application of one run; :meth:`serve` returns the run's final status."""

    def __init__(
        self,
        conductor: Conductor,
        *,
        token: str | None = None,
        experimenter_token: str | None = None,
        host: str | None = None,
        limits: Limits | None = None,
    ) -> None:
        """``host``: the ``--host`` given (None: the bound address); ``limits``: the bounds
        on HTTP clients (:class:`~robin_sim.live.connections.Limits`)."""
        self.conductor = conductor
        self.token = token
        # the experimenter's view always needs its own token, on loopback too
        self.experimenter_token = experimenter_token or new_token()
        self.tabs: list[Tab] = []
        self.limits = limits or Limits()
        self.connections = Connections(self.limits)
        # --webcam: the page runs the hand tracker (WebAssembly served from here)
        self.webcam = any(config.webcam for config in conductor.configs)
        self.guard = Guard(host, on_request=self.connections.served, wasm=self.webcam)
        self.app = web.Application(
            middlewares=[self.guard.middleware, self._guard], client_max_size=64 * 1024
        )
        self.guard.install(self.app)
        self.app.router.add_get("/", self._index)
        self.app.router.add_get("/static/{name}", self._static)
        self.app.router.add_get("/static/vendor/{name}", self._vendor)
        self.app.router.add_get("/ws", self._websocket)
        self.app.router.add_get("/favicon.ico", self._no_icon)
        self.app.router.add_get("/experimenter", self._experimenter_page)
        self._loop: asyncio.AbstractEventLoop | None = None
        self._controller_seen = False

    # --- HTTP -------------------------------------------------------------------------------
    @web.middleware
    async def _guard(self, request: web.Request, handler: Any) -> web.StreamResponse:
        """403 without the token (when one is required); Host and Origin: :class:`Guard`."""
        if self.token is not None:
            given = request.query.get("token", "")
            if not (
                secrets.compare_digest(given.encode(), self.token.encode())
                or self._is_experimenter(request)
            ):
                return web.Response(
                    status=403,
                    text="403: this server needs ?token=... (the URL printed when it started)\n",
                )
        return await handler(request)

    def _query(self) -> str:
        return "" if self.token is None else f"?token={self.token}"

    def _is_experimenter(self, request: web.Request) -> bool:
        given = request.query.get("token", "")
        return secrets.compare_digest(given.encode(), self.experimenter_token.encode())

    async def _experimenter_page(self, request: web.Request) -> web.Response:
        if not self._is_experimenter(request):
            return web.Response(
                status=403,
                text="403: the experimenter's view needs its own "
                "?token=... (printed when the server started)\n",
            )
        page = (STATIC_DIR / "experimenter.html").read_text(encoding="utf-8")
        query = f"?token={self.experimenter_token}"
        return web.Response(text=page.replace("{{QUERY}}", query), content_type="text/html")

    async def _index(self, request: web.Request) -> web.Response:
        page = (STATIC_DIR / "index.html").read_text(encoding="utf-8")
        page = page.replace("{{WEBCAM}}", "on" if self.webcam else "off")
        return web.Response(text=page.replace("{{QUERY}}", self._query()), content_type="text/html")

    async def _no_icon(self, request: web.Request) -> web.Response:
        return web.Response(status=204)

    async def _static(self, request: web.Request) -> web.Response:
        name = request.match_info["name"]
        if name not in STATIC_TYPES:  # only the page's own files, by exact name
            raise web.HTTPNotFound(text="404: not one of the page's files\n")
        body = (STATIC_DIR / name).read_bytes()
        return web.Response(body=body, content_type=STATIC_TYPES[name], charset="utf-8")

    async def _vendor(self, request: web.Request) -> web.Response:
        """The hand tracker's files (``--webcam`` only), by exact name as well."""
        name = request.match_info["name"]
        if not self.webcam or name not in VENDOR_TYPES:
            raise web.HTTPNotFound(text="404: not one of the page's files\n")
        kind = VENDOR_TYPES[name]
        body = await asyncio.to_thread((VENDOR_DIR / name).read_bytes)
        charset = "utf-8" if kind in TEXT_TYPES else None
        return web.Response(body=body, content_type=kind, charset=charset)

    # --- WebSocket --------------------------------------------------------------------------
    async def _websocket(self, request: web.Request) -> web.WebSocketResponse:
        ws = web.WebSocketResponse(max_msg_size=MAX_MESSAGE_BYTES, heartbeat=20.0)
        await ws.prepare(request)
        sock = request.transport.get_extra_info("socket") if request.transport else None
        if sock is not None:  # a lagging tab backs up within a few frames, then gets the newest
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SEND_BUFFER_BYTES)
        if self._is_experimenter(request):
            tab = Tab(ws, "experimenter")
        else:
            tab = Tab(ws, "watch" if self._controller_seen else "control")
            self._controller_seen = True
        self.tabs.append(tab)
        tab.send({"type": "role", "role": tab.role})
        tab.status = self.conductor.status()
        latest = self.conductor.latest_frame()
        if latest is not None:
            tab.frame = frame_message(latest.seq, latest.sim_time, latest.captured, latest.jpeg)
        sender = asyncio.create_task(self._sender(tab))
        try:
            if tab.role == "control":
                await self.conductor.participant_arrived()
            async for message in ws:
                if message.type in (WSMsgType.TEXT, WSMsgType.BINARY):
                    await self._received(tab, message.data)
        finally:
            self.tabs.remove(tab)
            sender.cancel()
            if tab.role == "control":
                await self.conductor.participant_left()
        return ws

    async def _received(self, tab: Tab, data: str | bytes) -> None:
        """Validate one message and act on it; anything wrong gets an error reply."""
        if tab.over_rate(time.monotonic()):
            LOG.warning("dropped a message from a %s tab: over %d per second", tab.role, RATE_LIMIT)
            tab.send(
                _error(f"too many messages: at most {RATE_LIMIT} per second; this one was dropped")
            )
            return
        if tab.role == "experimenter":
            await self._command(tab, data)
            return
        if tab.role != "control":
            tab.send(_error("this tab watches read-only; the first tab opened controls"))
            return
        try:
            reply = await self.conductor.receive(data)  # checked with parse_input, then acted on
            if reply is not None:
                tab.send(reply)
        except LiveInputError as problem:
            tab.send(_error(str(problem)))
        except Exception as problem:  # never lets one message end the session
            LOG.warning(
                "a message could not be handled: %s: %.200s", type(problem).__name__, problem
            )
            tab.send(
                _error(
                    f"this message could not be handled ({type(problem).__name__}); "
                    f"send one JSON object such as {EXAMPLE}"
                )
            )

    async def _command(self, tab: Tab, data: str | bytes) -> None:
        """One experimenter's command; its reply (``done``, with a saved note) or an error."""
        try:
            item = parse_command(data)
            note = await self.conductor.command(item)
        except LiveInputError as problem:
            tab.send(_error(str(problem)))
            return
        LOG.info("experimenter: %s", item.kind)
        tab.send({"type": "done", "command": item.kind, "note": note})
        self.push_status()

    async def _sender(self, tab: Tab) -> None:
        """Send what waits for ``tab``: texts, the newest status, the newest frame."""
        with contextlib.suppress(ConnectionError, RuntimeError, asyncio.CancelledError):
            while not tab.ws.closed:
                await tab.wake.wait()
                tab.wake.clear()
                while tab.texts:
                    await tab.ws.send_json(tab.texts.popleft())
                if tab.status is not None:
                    status, tab.status = tab.status, None
                    await tab.ws.send_json({"type": "status", **status})
                if tab.view is not None:
                    view, tab.view = tab.view, None
                    await tab.ws.send_json(view)
                if tab.frame is not None:
                    frame, tab.frame = tab.frame, None
                    await tab.ws.send_bytes(frame)

    # --- frames and status ------------------------------------------------------------------
    def frame_from_physics(self, frame: Frame) -> None:
        """Called on the physics thread for every new frame: hand it to the event loop."""
        loop = self._loop
        if loop is None or loop.is_closed():
            return
        message = frame_message(frame.seq, frame.sim_time, frame.captured, frame.jpeg)
        with contextlib.suppress(RuntimeError):  # the loop closed in between
            loop.call_soon_threadsafe(self._deliver, message)

    def _deliver(self, message: bytes) -> None:
        for tab in self.tabs:
            if tab.frame is not None:
                tab.frames_dropped += 1
            tab.frame = message
            tab.wake.set()

    def push_status(self) -> None:
        status = self.conductor.status()
        view = None
        for tab in self.tabs:
            tab.status = status
            if tab.role == "experimenter":
                if view is None:
                    roles = [(t.role, t.frames_dropped) for t in self.tabs]
                    view = experimenter_view(self.conductor, roles)
                tab.view = view
            tab.wake.set()

    async def _status_loop(self) -> None:
        while True:
            self.push_status()
            await asyncio.sleep(1.0 / STATUS_HZ)

    # --- the run ----------------------------------------------------------------------------
    async def serve(self, sock: socket.socket, *, handle_signals: bool = True) -> str:
        """Serve on the listening ``sock`` until the run ends; return its final status.
        ``handle_signals``: SIGINT / SIGTERM save the session (main thread only)."""
        loop = self._loop = asyncio.get_running_loop()
        self.guard.hosts.bind_to(sock.getsockname())
        handle_exception = loop.get_exception_handler()
        loop.set_exception_handler(self.connections.loop_exception)
        self.conductor.attach(loop, self.frame_from_physics)
        signals = (signal.SIGINT, signal.SIGTERM) if handle_signals else ()
        for signum in signals:
            loop.add_signal_handler(signum, self._signalled, signum)
        runner = web.AppRunner(
            self.app,
            handle_signals=False,
            access_log=None,
            shutdown_timeout=1.0,
            keepalive_timeout=self.limits.header_timeout_s,  # also bounds unfinished headers
            logger=HTTP_LOG,  # a closed tab: one line, no traceback
        )
        await runner.setup()
        status_task = None
        try:
            await GuardedSite(runner, sock, self.connections).start()
            status_task = asyncio.create_task(self._status_loop())
            outcome = await self.conductor.finished()
            self.push_status()  # the last status reaches every tab before the sockets close
            await asyncio.sleep(0.3)
        finally:
            if status_task is not None:
                status_task.cancel()
            await self._close_tabs()
            self.connections.abort_all()  # a client that never reads holds nothing up
            await runner.cleanup()
            for signum in signals:
                loop.remove_signal_handler(signum)
            loop.set_exception_handler(handle_exception)
        return outcome

    async def _close_tabs(self) -> None:
        """Say goodbye to every tab, for at most ``limits.close_timeout_s``: a tab that does not
        read is then dropped (a signal meanwhile waits no longer than that)."""
        goodbye = b"the session has ended"
        closing = [
            asyncio.ensure_future(tab.ws.close(code=1001, message=goodbye))
            for tab in list(self.tabs)
        ]
        if not closing:
            return
        await asyncio.wait(closing, timeout=self.limits.close_timeout_s)
        for task in closing:
            if task.done() and not task.cancelled():
                task.exception()  # a failed goodbye is no error: the tab is gone either way
        late = [task for task in closing if not task.done()]
        for task in late:
            task.cancel()
        if late:
            LOG.warning(
                "%d tab(s) did not take the goodbye in time; their connections were dropped",
                len(late),
            )

    def stop_soon(self) -> None:
        """From any thread: end the run as if signalled (the session saved ``interrupted``)."""
        if self._loop is not None and not self._loop.is_closed():
            self._loop.call_soon_threadsafe(self.conductor.interrupt)

    def _signalled(self, signum: int) -> None:
        LOG.warning("%s: saving the session", signal.Signals(signum).name)
        self.conductor.interrupt()


def _error(message: str) -> dict[str, str]:
    return {"type": "error", "message": message}
