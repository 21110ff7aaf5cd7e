"""The live server over plain HTTP on loopback: its page and files, nothing else; the token.

The server runs with the real engine behind it, but no tab connects, so no physics starts."""

from __future__ import annotations

import socket
from urllib.error import HTTPError
from urllib.request import urlopen

import pytest

from robin_sim.live.server import new_token

pytestmark = pytest.mark.slow  # a server with a real session behind it (~1 s each)

TRAVERSALS = (
    "/static/../../pyproject.toml",
    "/static/../pyproject.toml",
    "/static/%2e%2e/%2e%2e/pyproject.toml",
    "/static/..%2f..%2fpyproject.toml",
    "/static/..%2F..%2F..%2Fpyproject.toml",
    "/static/%252e%252e%252f%252e%252e%252fpyproject.toml",
    "/static/....//....//pyproject.toml",
    "/static/..\\..\\pyproject.toml",
    "/static/%5c..%5c..%5cpyproject.toml",
    "/static//etc/passwd",
    "/static/%2fetc%2fpasswd",
    "/static/server.py",
    "/static/../server.py",
    "/static/index.html/../../server.py",
    "/static/live.js%00.css",
    "//etc/passwd",
    "/../../../../etc/passwd",
)


def raw_get(port: int, target: str, headers: str = "") -> tuple[int, bytes]:
    """A GET with ``target`` sent byte for byte (no client normalises it); status and body."""
    with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
        request = f"GET {target} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n{headers}"
        sock.sendall((request + "Connection: close\r\n\r\n").encode("latin-1"))
        reply = b""
        while chunk := sock.recv(65536):
            reply += chunk
    head, _, body = reply.partition(b"\r\n\r\n")
    return int(head.split()[1]), body


def test_page_and_its_files_are_served(live_server) -> None:
    served = live_server()
    status, body = raw_get(served.port, "/")
    assert status == 200 and b'<canvas id="scene" width="640" height="480"' in body
    for name, marker in (("live.js", b"robinLive"), ("live.css", b"#scene")):
        status, body = raw_get(served.port, f"/static/{name}")
        assert status == 200 and marker in body, name


@pytest.mark.parametrize("target", TRAVERSALS)
def test_no_path_outside_the_static_files(live_server, target: str) -> None:
    served = live_server()
    status, body = raw_get(served.port, target)
    assert status in (400, 403, 404), f"{target}: HTTP {status}"
    for secret in (b"[project]", b"root:", b"aiohttp", b"import "):
        assert secret not in body, f"{target} leaked {secret!r}"


def test_token_required_on_every_request(live_server) -> None:
    token = new_token()
    served = live_server(token=token)
    for target in (
        "/",
        "/static/live.js",
        "/static/live.css",
        "/ws",
        f"/?token={token}x",
        "/?token=",
        f"/static/live.js?token={token[:-1]}",
    ):
        status, _ = raw_get(served.port, target)
        assert status == 403, f"{target}: HTTP {status}"
    ws_headers = (
        "Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\n"
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
    )
    status, _ = raw_get(served.port, "/ws", ws_headers)
    assert status == 403
    status, body = raw_get(served.port, f"/?token={token}")
    assert status == 200
    assert f'src="/static/live.js?token={token}"'.encode() in body  # the page's own requests
    assert f'href="/static/live.css?token={token}"'.encode() in body
    status, _ = raw_get(served.port, f"/static/live.js?token={token}")
    assert status == 200


def test_no_token_on_loopback_but_other_sites_pages_refused(live_server) -> None:
    served = live_server()
    with urlopen(served.url("/"), timeout=10) as reply:
        assert reply.status == 200
    status, _ = raw_get(served.port, "/", "Origin: http://evil.example\r\n")
    assert status == 403
    status, _ = raw_get(served.port, "/", f"Origin: http://127.0.0.1:{served.port}\r\n")
    assert status == 200


def test_unknown_route_is_404(live_server) -> None:
    served = live_server()
    with pytest.raises(HTTPError) as caught:
        urlopen(served.url("/pyproject.toml"), timeout=10)
    assert caught.value.code == 404
