"""The live server's tabs: one per WebSocket, what waits to be sent to it, and who controls.

A :class:`Tab` holds a socket, its role (``control``, ``watch``, ``experimenter``) and what
waits for it: text messages, the newest status and experimenter's view, the newest frame
(older frames are dropped: a lagging tab gets the newest when it is ready again).

:class:`ControlSlot` keeps the session's controlling tab. A page whose connection drops (a
network hiccup, a reload, a frozen tab the heartbeat gave up on) reconnects by itself and takes
its place again: the session runs on meanwhile (physics does not wait for a socket) and nothing
of it is lost. Only when no page has come back for :attr:`ControlSlot.grace_s` does the slot
call ``on_abandoned`` (the session is then saved ``closed``). While the control is vacant, the
first tab that connects takes it: the participant's page coming back, or a new one they opened.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import struct
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from aiohttp import web

LOG = logging.getLogger("robin_sim.live.server")  # one logger for the server's lines
RATE_LIMIT = 20  # messages per second from one tab; more are dropped with an error reply
QUEUED_TEXTS = 64  # text messages waiting for one tab; beyond, the oldest are dropped
EXAMPLE = '{"type": "thumb", "value": "up"}'  # a valid message, for error replies


def frame_message(seq: int, sim_time: float, captured: float, jpeg: bytes, block: int = 1) -> bytes:
    """One frame as the page reads it; ``captured`` is a ``time.monotonic()`` reading,
    ``block`` the run's block (1-based) whose session it comes from (its seq counts from 1)."""
    now_ms = time.time() * 1000.0
    captured_ms = now_ms - (time.monotonic() - captured) * 1000.0
    header = json.dumps(
        {
            "seq": seq,
            "block": block,
            "sim_time": round(sim_time, 4),
            "captured_ms": round(captured_ms, 2),
            "sent_ms": round(now_ms, 2),
        }
    ).encode()
    return struct.pack(">I", len(header)) + header + jpeg


def error_reply(message: str) -> dict[str, str]:
    """The one shape of every refusal a tab is sent."""
    return {"type": "error", "message": message}


@dataclass(eq=False)
class Tab:
    """One connected tab: its socket, role, what waits to be sent, and its recent inputs."""

    ws: web.WebSocketResponse
    role: str  # "control" | "watch" | "experimenter"
    transport: asyncio.BaseTransport | None = None  # its connection (abort: a network failure)
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


MAX_DROPS_LOGGED = 5  # dropped messages logged one by one; later ones are counted


class DropLog:
    """Messages dropped over :data:`RATE_LIMIT`: each gets an error reply, and a participant's
    is recorded in the block's ``inputs.jsonl`` with why; the log gets the first
    :data:`MAX_DROPS_LOGGED` one by one, then one line saying the rest are counted, and the
    count when the server stops (:meth:`summary`): a flood of messages never floods the log."""

    def __init__(self) -> None:
        self.dropped = 0

    def drop(self, tab: Tab, data: str | bytes, record: Callable[[object, str], None]) -> None:
        """Drop one message of ``tab``'s; ``record`` logs a participant's in ``inputs.jsonl``."""
        why = f"too many messages: at most {RATE_LIMIT} per second; this one was dropped"
        self.dropped += 1
        if self.dropped <= MAX_DROPS_LOGGED:
            LOG.warning("dropped a message from a %s tab: over %d per second", tab.role, RATE_LIMIT)
        elif self.dropped == MAX_DROPS_LOGGED + 1:
            LOG.warning("more messages over the rate limit; counted, no longer logged one by one")
        if tab.role == "control":
            record(data, why)
        tab.send(error_reply(why))

    def summary(self) -> None:
        """The count of the messages dropped, when more were dropped than logged."""
        if self.dropped > MAX_DROPS_LOGGED:
            LOG.warning("dropped %d messages over the rate limit in all", self.dropped)


class ControlSlot:
    """Which tab controls the session, and the wait for one that went away (module doc)."""

    def __init__(self, grace_s: float, on_abandoned: Callable[[], None]) -> None:
        self.grace_s, self.on_abandoned = grace_s, on_abandoned
        self.tab: Tab | None = None
        self.ever = False  # a controlling tab has connected once
        self.lost_at: float | None = None  # monotonic time the controlling tab went away
        self.returns = 0  # times a page took the vacant control again
        self._timer: asyncio.TimerHandle | None = None

    def claim(self, tab: Tab) -> bool:
        """``tab`` connected: it controls when nobody does (True), else it watches."""
        if self.tab is not None:
            return False
        if self.lost_at is not None:
            self.returns += 1
        self.tab, self.ever, self.lost_at = tab, True, None
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        return True

    def left(self, tab: Tab, loop: asyncio.AbstractEventLoop) -> bool:
        """``tab`` closed; True when it was the controlling one (the wait begins)."""
        if tab is not self.tab:
            return False
        self.tab, self.lost_at = None, time.monotonic()
        self._timer = loop.call_later(self.grace_s, self._abandoned)
        return True

    def _abandoned(self) -> None:
        self._timer = None
        if self.tab is None:
            self.on_abandoned()

    def cancel(self) -> None:
        """The run is over: wait no longer."""
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None

    def state(self) -> dict[str, Any]:
        """For the experimenter: is the participant's page there, and since when not."""
        away = None if self.lost_at is None else round(time.monotonic() - self.lost_at, 1)
        return {
            "connected": self.tab is not None,
            "away_s": away,
            "grace_s": self.grace_s,
            "returns": self.returns,
        }


async def send_loop(tab: Tab) -> None:
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


async def close_tabs(tabs: list[Tab], timeout_s: float) -> None:
    """Say goodbye to every tab, for at most ``timeout_s``: a tab that does not read is then
    dropped (a signal meanwhile waits no longer than that)."""
    goodbye = b"the session has ended"
    closing = [asyncio.ensure_future(tab.ws.close(code=1001, message=goodbye)) for tab in tabs]
    if not closing:
        return
    await asyncio.wait(closing, timeout=timeout_s)
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
