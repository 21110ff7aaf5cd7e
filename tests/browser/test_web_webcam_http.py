"""``--webcam`` over plain HTTP: the tracker's files come from the server itself, by exact name,
and the page may compile WebAssembly only then (no tab connects, so no physics starts)."""

from __future__ import annotations

from urllib.error import HTTPError
from urllib.request import urlopen

import pytest

from robin_sim.live.hands.vendor import VENDOR_DIR, VENDOR_TYPES

pytestmark = pytest.mark.slow  # a server with a real session behind it (~1 s each)


def get(url: str) -> tuple[int, dict[str, str], bytes]:
    try:
        with urlopen(url, timeout=30) as response:
            return response.status, dict(response.headers), response.read()
    except HTTPError as error:
        return error.code, dict(error.headers), error.read()


def test_the_tracker_is_served_with_webcam_only(live_server) -> None:
    served = live_server(webcam=True)
    status, headers, page = get(served.url("/"))
    assert status == 200 and b'data-webcam="on"' in page and b"/static/webcam.js" in page
    policy = headers["Content-Security-Policy"]
    assert "script-src 'self' 'wasm-unsafe-eval';" in policy and "unsafe-eval'" not in (
        policy.replace("'wasm-unsafe-eval'", "")
    )
    assert "connect-src 'self'" in policy and "default-src 'self'" in policy
    for name, kind in VENDOR_TYPES.items():
        status, headers, body = get(served.url(f"/static/vendor/{name}"))
        assert status == 200, name
        assert headers["Content-Type"].startswith(kind), (name, headers["Content-Type"])
        assert body == (VENDOR_DIR / name).read_bytes(), name
    for name in ("LICENSE", "README.md", "../server.py", "%2e%2e%2fserver.py", "hands.js.map"):
        assert get(served.url(f"/static/vendor/{name}"))[0] == 404, name


def test_without_webcam_no_tracker_and_no_webassembly(live_server) -> None:
    served = live_server()
    status, headers, page = get(served.url("/"))
    assert status == 200 and b'data-webcam="off"' in page
    assert "wasm-unsafe-eval" not in headers["Content-Security-Policy"]
    assert get(served.url("/static/vendor/hands.js"))[0] == 404
