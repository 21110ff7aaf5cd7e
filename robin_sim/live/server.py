"""The live page's web server (aiohttp): the page, its own static files and a WebSocket per tab.

``GET /`` serves the page, ``GET /static/NAME`` one of the page's files (a fixed list: no path
from a request ever reaches the file system), ``GET /ws`` the WebSocket. The first tab that
connects controls the session; later tabs watch read-only. To every tab the server pushes each
new frame as one binary message (a 4-byte big-endian header length, a JSON header with ``seq``,
``sim_time``, ``captured_ms`` = the wall-clock time in ms when physics was rendered, and the
JPEG) and the session's status as JSON a few times a second. A lagging tab gets the newest frame
when it is ready again; older ones are dropped, and physics never waits for a socket.

The run (:class:`robin_sim.live.conductor.Conductor`) is one session, or a protocol's blocks one
after another, each behind an instruction screen. A controlling page that loses its connection
comes back by itself and takes its place again (:class:`~robin_sim.live.tabs.ControlSlot`); when
none has come back for the grace time the session is saved ``closed`` and the server stops; so
do SIGINT and SIGTERM, with ``interrupted``.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import secrets
import signal
import socket
import time

from aiohttp import WSMsgType, web

from robin_sim.live.commands import parse_command
from robin_sim.live.conductor import Conductor
from robin_sim.live.connections import HTTP_LOG, Connections, GuardedSite, Limits, bind
from robin_sim.live.experimenter import experimenter_view
from robin_sim.live.guard import Guard, is_loopback
from robin_sim.live.inputs import LiveInputError
from robin_sim.live.limits import RECONNECT_GRACE_S
from robin_sim.live.pages import Pages
from robin_sim.live.session import Frame
from robin_sim.live.tabs import (
    EXAMPLE,
    RATE_LIMIT,
    ControlSlot,
    DropLog,
    Tab,
    close_tabs,
    error_reply,
    frame_message,
    send_loop,
)

LOG = logging.getLogger(__name__)
__all__ = ["RATE_LIMIT", "LiveServer", "bind", "is_loopback", "new_token"]
STATUS_HZ = 5.0  # status messages per second
# s between pings; a pong must come within half of it. A page whose thread is held (the hand
# tracker without a GPU: 4-7 s a reading, more on a busy machine) reads nothing meanwhile, so
# its pong waits too: past the half the connection drops, and the page comes back by itself.
HEARTBEAT_S = 30.0
MAX_MESSAGE_BYTES = 1 << 20  # larger closes the socket (1009); parse_input refuses > 4 KiB
SEND_BUFFER_BYTES = 128 * 1024  # kernel send buffer of a tab's socket: a few frames, not seconds


def new_token() -> str:
    """A fresh access token for a server reachable from other machines."""
    return secrets.token_urlsafe(16)


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
        reconnect_grace_s: float = RECONNECT_GRACE_S,
    ) -> None:
        """``host``: the ``--host`` given (None: the bound address); ``limits``: the bounds
        on HTTP clients (:class:`~robin_sim.live.connections.Limits`); ``reconnect_grace_s``:
        how long a participant's page that lost its connection is waited for."""
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
        self.pages = Pages(token, self.experimenter_token, webcam=self.webcam)
        self.app = web.Application(
            middlewares=[self.guard.middleware, self.pages.token_check],
            client_max_size=64 * 1024,
        )
        self.guard.install(self.app)
        self.pages.install(self.app)
        self.app.router.add_get("/ws", self._websocket)
        self._loop: asyncio.AbstractEventLoop | None = None
        self.control = ControlSlot(reconnect_grace_s, self._abandoned)
        self.drops = DropLog()

    # --- WebSocket --------------------------------------------------------------------------
    async def _websocket(self, request: web.Request) -> web.WebSocketResponse:
        ws = web.WebSocketResponse(max_msg_size=MAX_MESSAGE_BYTES, heartbeat=HEARTBEAT_S)
        await ws.prepare(request)
        sock = request.transport.get_extra_info("socket") if request.transport else None
        if sock is not None:  # a lagging tab backs up within a few frames, then gets the newest
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SEND_BUFFER_BYTES)
        if self.pages.is_experimenter(request):
            tab = Tab(ws, "experimenter", request.transport)
        else:
            tab = Tab(ws, "watch", request.transport)
            returning = self.control.ever
            if self.control.claim(tab):
                tab.role = "control"
                if returning:  # the participant's page is back: the session goes on
                    self.conductor.page_away(False, returns=self.control.returns)
        self.tabs.append(tab)
        tab.send({"type": "role", "role": tab.role})
        tab.status = self.conductor.status()
        latest = self.conductor.latest_frame()
        if latest is not None:
            tab.frame = frame_message(
                latest.seq, latest.sim_time, latest.captured, latest.jpeg, self.conductor.index + 1
            )
        sender = asyncio.create_task(send_loop(tab))
        try:
            if tab.role == "control":
                await self.conductor.participant_arrived()
            async for message in ws:
                if message.type in (WSMsgType.TEXT, WSMsgType.BINARY):
                    await self._received(tab, message.data)
        finally:
            self.tabs.remove(tab)
            sender.cancel()
            assert self._loop is not None
            if self.control.left(tab, self._loop):  # waited for: see ControlSlot
                code = ws.close_code
                self.conductor.page_away(True, code=code, grace_s=self.control.grace_s)
                LOG.warning(
                    "the participant's page lost its connection (code %s); waiting %g s for "
                    "it to come back",
                    code,
                    self.control.grace_s,
                )
        return ws

    def _abandoned(self) -> None:
        """No page came back in time: the session is saved ``closed`` and the run ends."""
        LOG.warning("no page came back in %g s: saving the session", self.control.grace_s)
        assert self._loop is not None
        self._loop.create_task(self.conductor.participant_left())

    async def _received(self, tab: Tab, data: str | bytes) -> None:
        """Validate one message and act on it; anything wrong gets an error reply."""
        if tab.over_rate(time.monotonic()):
            self.drops.drop(tab, data, self.conductor.session.record_input)  # logged, capped
            return
        if tab.role == "experimenter":
            await self._command(tab, data)
            return
        if tab.role != "control":
            tab.send(error_reply("this tab watches read-only; the first tab opened controls"))
            return
        try:
            reply = await self.conductor.receive(data)  # checked with parse_input, then acted on
            if reply is not None:
                tab.send(reply)
        except LiveInputError as problem:
            tab.send(error_reply(str(problem)))
        except Exception as problem:  # never lets one message end the session
            LOG.warning(
                "a message could not be handled: %s: %.200s", type(problem).__name__, problem
            )
            tab.send(
                error_reply(
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
            tab.send(error_reply(str(problem)))
            return
        LOG.info("experimenter: %s", item.kind)
        tab.send({"type": "done", "command": item.kind, "note": note})
        self.push_status()

    # --- frames and status ------------------------------------------------------------------
    def frame_from_physics(self, frame: Frame) -> None:
        """Called on the physics thread for every new frame: hand it to the event loop."""
        loop = self._loop
        if loop is None or loop.is_closed():
            return
        block = self.conductor.index + 1  # frames come from the running block's session
        message = frame_message(frame.seq, frame.sim_time, frame.captured, frame.jpeg, block)
        with contextlib.suppress(RuntimeError):  # the loop closed in between
            loop.call_soon_threadsafe(self._deliver, message)

    def _deliver(self, message: bytes) -> None:
        for tab in self.tabs:
            if tab.frame is not None:
                tab.frames_dropped += 1
            tab.frame = message
            tab.wake.set()

    def push_status(self) -> None:
        status = {**self.conductor.status(), "participant_page": self.control.state()}
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
        previous = {signum: signal.getsignal(signum) for signum in signals}  # the command's
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
            self.control.cancel()
            self.drops.summary()
            if status_task is not None:
                status_task.cancel()
            await close_tabs(self.tabs, self.limits.close_timeout_s)
            self.connections.abort_all()  # a client that never reads holds nothing up
            await runner.cleanup()
            mask = signal.pthread_sigmask(signal.SIG_BLOCK, signals)  # none lost meanwhile
            for signum in signals:  # the command's handlers back (asyncio would set defaults)
                loop.remove_signal_handler(signum)
                signal.signal(signum, previous[signum])
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)
            loop.set_exception_handler(handle_exception)
        return outcome

    def stop_soon(self) -> None:
        """From any thread: end the run as if signalled (the session saved ``interrupted``)."""
        if self._loop is not None and not self._loop.is_closed():
            self._loop.call_soon_threadsafe(self.conductor.interrupt)

    def _signalled(self, signum: int) -> None:
        LOG.warning("%s: saving the session", signal.Signals(signum).name)
        self.conductor.interrupt()
