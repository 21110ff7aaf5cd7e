"""The WebSocket with a plain client (no browser): frames, junk, floods, read-only watchers."""

from __future__ import annotations

import asyncio
import json
import struct
import time
from typing import Any

import aiohttp
import pytest
from page_driver import read_jsonl

from robin_sim.live.server import RATE_LIMIT

pytestmark = pytest.mark.slow

JUNK: list[Any] = [
    "not json",
    "[1, 2, 3]",
    '"text"',
    "{}",
    '{"type": "dance"}',
    '{"type": "point", "x": 640, "y": 10}',
    '{"type": "point", "x": -1, "y": 10}',
    '{"type": "point", "x": "NaN", "y": 10}',
    '{"type": "point", "x": 1e400, "y": 10}',
    '{"type": "gesture", "gesture": "wave"}',
    '{"type": "thumb", "value": "sideways"}',
    '{"type": "thumb", "value": "up", "extra": 1}',
    '{"type": "start"}',  # no instruction screen is shown
    b"\xff\xfe\x00binary",
    "x" * 5000,
]


async def receive_until(ws: aiohttp.ClientWebSocketResponse, kind: str, timeout: float = 30):
    """The next text message of ``kind`` (frames and other messages are passed over)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        message = await ws.receive(timeout=deadline - time.monotonic())
        if message.type == aiohttp.WSMsgType.TEXT:
            data = json.loads(message.data)
            if data["type"] == kind:
                return data
        elif message.type in (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSED):
            raise AssertionError(f"socket closed waiting for {kind}")
    raise AssertionError(f"no {kind} message in {timeout} s")


async def wait_phase(ws, phase: str, timeout: float = 60) -> dict[str, Any]:
    deadline = time.monotonic() + timeout
    while True:
        status = await receive_until(ws, "status", timeout)
        if status["phase"] == phase:
            return status
        assert time.monotonic() < deadline, f"phase {status['phase']}, not {phase}"


async def frame(ws) -> tuple[dict[str, Any], bytes]:
    while True:
        message = await ws.receive(timeout=30)
        if message.type == aiohttp.WSMsgType.BINARY:
            (length,) = struct.unpack(">I", message.data[:4])
            return json.loads(message.data[4 : 4 + length]), message.data[4 + length :]


async def exercise(url: str) -> dict[str, Any]:
    seen: dict[str, Any] = {}
    async with aiohttp.ClientSession() as http:
        control = await http.ws_connect(url)
        assert (await receive_until(control, "role"))["role"] == "control"
        header, jpeg = await frame(control)
        seen["frame"] = header, jpeg[:3]
        await wait_phase(control, "waiting_for_gesture")
        errors = []
        for junk in JUNK:
            await (control.send_bytes(junk) if isinstance(junk, bytes) else control.send_str(junk))
            errors.append(await receive_until(control, "error"))
            await asyncio.sleep(1.0 / RATE_LIMIT)  # stay under the rate limit here
        seen["errors"] = errors
        await asyncio.sleep(1.1)
        watcher = await http.ws_connect(url)
        assert (await receive_until(watcher, "role"))["role"] == "watch"
        await watcher.send_str('{"type": "gesture", "gesture": "grasp"}')
        seen["watch_error"] = (await receive_until(watcher, "error"))["message"]
        await asyncio.sleep(1.1)
        flood = [control.send_str('{"type": "thumb", "value": "sideways"}')
                 for _ in range(3 * RATE_LIMIT)]  # fmt: skip
        await asyncio.gather(*flood)
        replies = [await receive_until(control, "error") for _ in range(3 * RATE_LIMIT)]
        seen["flood"] = [r["message"] for r in replies]
        await asyncio.sleep(1.1)
        await control.send_str('{"type": "gesture", "gesture": "give_me"}')  # still served
        seen["after"] = await wait_phase(control, "robot_acting")
        await watcher.close()
        await control.close()
    return seen


def test_junk_floods_and_watchers_get_errors_and_the_server_goes_on(live_server) -> None:
    served = live_server(scenario="one_handover", speed=3.0, video=False)
    seen = asyncio.run(exercise(served.url("/ws").replace("http://", "ws://")))
    header, magic = seen["frame"]
    assert magic == b"\xff\xd8\xff" and header["seq"] >= 1  # a JPEG with its seq
    assert abs(header["captured_ms"] - time.time() * 1000) < 60_000
    assert len(seen["errors"]) == len(JUNK)
    assert all(error["message"] for error in seen["errors"])
    assert "valid choices" in seen["errors"][4]["message"]  # an unknown type names the types
    assert "read-only" in seen["watch_error"]
    limited = [m for m in seen["flood"] if m.startswith("too many messages")]
    assert len(limited) >= RATE_LIMIT  # 60 sent at once: at most 20 a second are looked at
    assert len(seen["flood"]) - len(limited) <= RATE_LIMIT
    assert seen["after"]["phase"] == "robot_acting"
    assert served.wait_over(60) == "closed"  # the controlling socket closed: saved as closed
    folder = served.conductor.session.out_dir
    assert json.loads((folder / "summary.json").read_text())["status"] == "closed"
    inputs = read_jsonl(folder / "inputs.jsonl")
    assert sum(not e["accepted"] for e in inputs) >= len(JUNK) - 1  # the refused ones logged
    assert inputs[-1]["raw"] == {"type": "gesture", "gesture": "give_me"}
    assert inputs[-1]["accepted"]
