"""Attacks on the live server over raw sockets on loopback, with no physics running: DNS
rebinding (a foreign Host), foreign Origins, framing, half-open and idle HTTP clients, and more
connections than the server keeps. The server runs a protocol-style session, so a WebSocket
gets the instruction screen and no session starts."""

from __future__ import annotations

import logging
import socket
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from conftest import Served, start_server
from raw_http import exchange, get, handshake, parse_reply, reset, websocket

from robin_sim.live.connections import Limits
from robin_sim.live.session import LiveConfig

pytestmark = pytest.mark.slow  # a real server with the engine behind it (~1 s each)

FRAMING = {
    "x-frame-options": "DENY",
    "x-content-type-options": "nosniff",
    "referrer-policy": "no-referrer",
}


@pytest.fixture
def guarded(tmp_path: Path) -> Iterator[Any]:
    """``guarded(limits)``: a server whose first tab sees an instruction screen (no physics)."""
    started: list[Served] = []

    def make(limits: Limits | None = None) -> Served:
        config = LiveConfig(
            out_root=tmp_path / "live",
            protocol="guard-test",
            instructions="read me",
            session="block1-pil",
            video=False,
        )
        served = start_server([config], limits=limits)
        started.append(served)
        return served

    yield make
    for served in started:
        served.server.stop_soon()
        served.thread.join(30)
        assert not served.thread.is_alive(), "the live server did not stop"


def test_a_foreign_host_is_refused_dns_rebinding(guarded, caplog) -> None:
    served = guarded()
    port = served.port
    caplog.set_level(logging.WARNING)
    for host in (
        f"evil.example:{port}",
        f"127.0.0.1:{port + 1}",
        "127.0.0.1",
        f"localhost.evil.example:{port}",
    ):
        status, _, body = get(port, "/", host=host)
        assert status == 421, f"Host {host!r}: HTTP {status}"
        assert len(body) < 200 and b"<canvas" not in body
    assert get(port, "/", host="")[0] == 400  # no Host at all: aiohttp refuses it
    # the rebinding page's own Origin matches its Host: still refused (Host first)
    status, _, _ = get(
        port, "/", host=f"evil.example:{port}", extra=f"Origin: http://evil.example:{port}\r\n"
    )
    assert status == 421
    status, _, _ = exchange(port, handshake("/ws", port, host=f"evil.example:{port}"))
    assert status == 421 and served.conductor.phase == "waiting"  # no tab took control
    for host in (f"127.0.0.1:{port}", f"localhost:{port}", f"[::1]:{port}"):
        status, _, body = get(port, "/", host=host)
        assert status == 200 and b"<canvas" in body, host
    refused = [r.getMessage() for r in caplog.records if "refused a request" in r.getMessage()]
    assert any("evil.example" in line for line in refused)
    assert all("\n" not in line for line in refused)
    assert len(refused) <= 6  # one line per distinct value (evil.example came twice)
    assert not any(r.exc_info for r in caplog.records)  # the 400 too: one line, no traceback


def test_origin_is_checked_against_the_allow_list(guarded) -> None:
    served = guarded()
    port = served.port
    for origin in (
        f"http://evil.example:{port}",
        "null",
        f"http://127.0.0.1:{port + 1}",
        f"https://127.0.0.1:{port}",
    ):
        status, _, _ = get(port, "/", extra=f"Origin: {origin}\r\n")
        assert status == 403, origin
        status, headers, _ = exchange(port, handshake("/ws", port, extra=f"Origin: {origin}\r\n"))
        assert status == 403 and headers.get("connection") == "close", (origin, headers)
    assert served.conductor.phase == "waiting"
    status, _, _ = get(port, "/", extra=f"Origin: http://localhost:{port}\r\n")
    assert status == 200


def test_no_response_can_be_framed(guarded) -> None:
    served = guarded()
    port = served.port
    replies = {
        "page": get(port, "/"),
        "script": get(port, "/static/live.js"),
        "404": get(port, "/pyproject.toml"),
        "421": get(port, "/", host=f"evil.example:{port}"),
        "403": get(port, "/", extra="Origin: http://evil.example\r\n"),
    }
    with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
        sock.sendall(handshake("/ws", port))
        head = b""
        while b"\r\n\r\n" not in head:
            head += sock.recv(1)
        replies["101"] = parse_reply(head)
    assert [replies[k][0] for k in replies] == [200, 200, 404, 421, 403, 101]
    for what, (_, headers, _) in replies.items():
        for name, value in FRAMING.items():
            assert headers.get(name) == value, (what, name, headers)
        policy = headers.get("content-security-policy", "")
        assert "frame-ancestors 'none'" in policy and "default-src 'self'" in policy, what


def closed_after(sock: socket.socket, limit: float) -> float:
    """Seconds until the server closes ``sock`` (reading and dropping what it sends)."""
    started = time.monotonic()
    sock.settimeout(limit)
    try:
        while sock.recv(4096):
            pass
    except TimeoutError:
        raise AssertionError(f"the server kept the connection over {limit} s") from None
    except ConnectionResetError:
        pass
    return time.monotonic() - started


def test_half_open_trickling_and_idle_clients_are_dropped(guarded) -> None:
    served = guarded(Limits(header_timeout_s=1.0))
    port = served.port
    half = socket.create_connection(("127.0.0.1", port))
    half.sendall(f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n".encode())  # no blank line
    assert 0.5 < closed_after(half, 5.0) < 4.0
    trickle = socket.create_connection(("127.0.0.1", port))
    started = time.monotonic()
    trickle.settimeout(5.0)
    with pytest.raises((BrokenPipeError, ConnectionResetError)):
        for byte in f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nX-Slow: {'a' * 60}".encode():
            trickle.send(bytes([byte]))  # a byte every 0.1 s: the deadline is not moved
            time.sleep(0.1)
            assert time.monotonic() - started < 4.0, "the trickling client was kept"
    idle = socket.create_connection(("127.0.0.1", port))
    idle.sendall(f"GET /favicon.ico HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode())
    assert idle.recv(12) == b"HTTP/1.1 204"
    assert closed_after(idle, 5.0) < 4.0  # kept alive, then dropped when idle
    for sock in (half, trickle, idle):
        sock.close()
    assert get(port, "/")[0] == 200


def test_500_half_open_requests_and_the_server_still_serves(guarded, caplog) -> None:
    served = guarded(Limits(max_connections=32))
    port = served.port
    caplog.set_level(logging.WARNING)
    stalled = []
    try:
        for _ in range(500):
            sock = socket.create_connection(("127.0.0.1", port), timeout=10)
            sock.sendall(f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nX-Wait: ".encode())
            stalled.append(sock)
        started = time.monotonic()
        status, _, body = get(port, "/")
        assert status == 200 and b"<canvas" in body
        assert time.monotonic() - started < 5.0
        connections = served.server.connections
        assert len(connections.open) <= 32 and connections.dropped >= 500 - 32
    finally:
        for sock in stalled:
            sock.close()
    lines = [r.getMessage() for r in caplog.records]
    assert len(lines) <= 3 and not any(r.exc_info for r in caplog.records), lines


def test_closed_tabs_are_one_line_each_without_a_traceback(guarded, caplog) -> None:
    served = guarded()
    port = served.port
    caplog.set_level(logging.WARNING)
    control = websocket(port)  # the participant's tab stays; the others come and go
    for i in range(40):  # the request sent, then the tab gone at once (a TCP reset)
        sock = socket.create_connection(("127.0.0.1", port))
        page = f"GET /static/live.js HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n".encode()
        sock.sendall(handshake("/ws", port) if i % 2 else page)
        reset(sock)
    time.sleep(0.5)
    assert get(port, "/")[0] == 200  # still serving
    control.close()
    records = caplog.records
    assert not any(r.exc_info or r.exc_text for r in records), [r.getMessage() for r in records]
    assert all("\n" not in r.getMessage() for r in records)
    went = [r for r in records if "went away" in r.getMessage()]
    assert all(r.levelno == logging.WARNING for r in went)
