"""The live page's test rig: a real server on a free loopback port, the real engine behind it,
and Debian's chromium driven headless by Playwright (never a downloaded browser)."""

from __future__ import annotations

import asyncio
import threading
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest

from robin_sim.live.conductor import Conductor
from robin_sim.live.server import LiveServer, bind
from robin_sim.live.session import LiveConfig

CHROMIUM = Path("/usr/bin/chromium")  # Debian's package (.ci/run installs it)


@dataclass
class Served:
    """A running live server (in a thread of this process) and what it returned."""

    server: LiveServer
    conductor: Conductor
    port: int
    thread: threading.Thread
    outcome: list[str] = field(default_factory=list)
    failure: list[BaseException] = field(default_factory=list)

    def url(self, path: str = "/") -> str:
        query = "" if self.server.token is None else f"?token={self.server.token}"
        return f"http://127.0.0.1:{self.port}{path}{query}"

    def wait_over(self, timeout: float) -> str:
        """Wait for the run to end by itself; its final status."""
        self.thread.join(timeout)
        assert not self.thread.is_alive(), f"the server still runs after {timeout} s"
        assert not self.failure, f"the server failed: {self.failure[0]!r}"
        return self.outcome[0]


# s a lost participant's page is waited for in these tests (a tab a test closes on purpose
# then saves the session "closed" soon); the reconnect test sets its own
TEST_GRACE_S = 1.0


def start_server(
    configs: Sequence[LiveConfig],
    token: str | None = None,
    questionnaires: Sequence[Any] = (),
    screens: Any = None,
    journal: Any = None,
    **server_options: Any,
) -> Served:
    """``screens`` and ``journal``: a study's (robin_sim.lab.run.StudyRun)."""
    server_options.setdefault("reconnect_grace_s", TEST_GRACE_S)
    conductor = Conductor(configs, questionnaires, screens, journal)
    server = LiveServer(conductor, token=token, **server_options)
    sock = bind("127.0.0.1", 0)
    port = sock.getsockname()[1]
    served: Served

    def main() -> None:
        try:
            served.outcome.append(asyncio.run(server.serve(sock, handle_signals=False)))
        except BaseException as problem:  # reported by wait_over / the fixture
            served.failure.append(problem)

    thread = threading.Thread(target=main, name="live-server", daemon=True)
    served = Served(server, conductor, port, thread)
    thread.start()
    deadline = time.monotonic() + 10
    while server._loop is None and time.monotonic() < deadline:
        time.sleep(0.01)
    return served


@pytest.fixture
def live_server(tmp_path: Path) -> Iterator[Any]:
    """``live_server(**config)`` starts a server for one session under ``tmp_path``."""
    started: list[Served] = []

    def make(
        token: str | None = None, reconnect_grace_s: float = TEST_GRACE_S, **options: Any
    ) -> Served:
        options.setdefault("out_root", tmp_path / "live")
        served = start_server(
            [LiveConfig(**options)], token=token, reconnect_grace_s=reconnect_grace_s
        )
        started.append(served)
        return served

    yield make
    for served in started:
        served.server.stop_soon()
        served.thread.join(60)
        assert not served.thread.is_alive(), "the live server did not stop"


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    """Headless chromium from Debian's package, for one test module. Playwright's sync API
    runs an event loop in the main thread while it is open, so it is closed after the module
    and asyncio's state reset: other modules' tests (Dask, asyncio.run) see a clean thread."""
    from playwright.sync_api import sync_playwright

    assert CHROMIUM.exists(), f"{CHROMIUM} is missing: apt-get install chromium (see .ci/run)"
    try:
        with sync_playwright() as playwright:
            chromium = playwright.chromium.launch(
                executable_path=str(CHROMIUM), headless=True, args=["--no-sandbox"]
            )
            yield chromium
            chromium.close()
    finally:
        asyncio.set_event_loop_policy(None)  # a fresh policy: no loop left set to None
