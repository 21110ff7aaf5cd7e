"""Attacks on a running live session, with real physics: messages that used to end it (a
400-digit integer, deep nesting), and a watcher that never reads while the session ends."""

from __future__ import annotations

import json
import time
from typing import Any

import aiohttp
import pytest
from page_driver import read_jsonl, run_async
from raw_http import websocket

from robin_sim.live.files import MAX_RAW_CHARS

pytestmark = pytest.mark.slow

DEADLY = [
    '{"type": "point", "x": ' + "9" * 400 + ', "y": 10}',  # OverflowError in _coordinate
    "[" * 3000,  # RecursionError in json.loads
    '{"type": "point", "x": ' + "[" * 900 + "]" * 900 + ', "y": 10}',
    '{"type": "thumb", "value": ' + "[" * 1500 + "]" * 1500 + "}",
]


async def next_text(ws: aiohttp.ClientWebSocketResponse, kind: str, timeout: float = 60) -> Any:
    deadline = time.monotonic() + timeout
    while (left := deadline - time.monotonic()) > 0:
        message = await ws.receive(timeout=left)
        if message.type == aiohttp.WSMsgType.TEXT:
            data = json.loads(message.data)
            if data["type"] == kind:
                return data
        elif message.type in (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSED):
            raise AssertionError(f"the socket closed waiting for {kind}")
    raise AssertionError(f"no {kind} in {timeout} s")


async def until_phase(ws: aiohttp.ClientWebSocketResponse, phase: str) -> dict[str, Any]:
    deadline = time.monotonic() + 90
    while time.monotonic() < deadline:
        status = await next_text(ws, "status")
        if status["phase"] == phase:
            return status
    raise AssertionError(f"no phase {phase}")


async def send_deadly(url: str) -> dict[str, Any]:
    seen: dict[str, Any] = {}
    async with aiohttp.ClientSession() as http, http.ws_connect(url) as control:
        await until_phase(control, "waiting_for_gesture")
        seen["errors"] = []
        for raw in DEADLY:
            await control.send_str(raw)
            seen["errors"].append((await next_text(control, "error"))["message"])
        seen["after"] = await next_text(control, "status")
        await control.send_str('{"type": "gesture", "gesture": "give_me"}')  # still taken
        seen["acting"] = await until_phase(control, "robot_acting")
        await control.send_str('{"type": "end"}')
        seen["end"] = await until_phase(control, "done")
    return seen


def test_no_message_ends_the_session_and_each_is_logged(live_server) -> None:
    served = live_server(scenario="one_handover", speed=3.0, video=False)
    seen = run_async(send_deadly(served.url("/ws").replace("http://", "ws://")))
    assert len(seen["errors"]) == len(DEADLY)
    assert all(len(message) < 300 for message in seen["errors"]), seen["errors"]
    assert "nested too deeply" in seen["errors"][1]
    assert seen["after"]["status"] == "running" and seen["after"]["phase"] != "done"
    assert seen["end"]["status"] == "ended"  # ended by End, not "closed" by a crash
    folder = served.conductor.session.out_dir
    assert json.loads((folder / "summary.json").read_text())["status"] == "ended"
    inputs = read_jsonl(folder / "inputs.jsonl")
    refused = [entry for entry in inputs if not entry["accepted"]]
    logged = [raw if len(raw) <= MAX_RAW_CHARS else raw[:MAX_RAW_CHARS] + "..." for raw in DEADLY]
    assert [entry["raw"] for entry in refused[: len(DEADLY)]] == logged
    assert all(entry["error"] for entry in refused)
    assert {"type": "gesture", "gesture": "give_me"} in [e["raw"] for e in inputs]


def test_a_watcher_that_never_reads_does_not_hold_the_exit(live_server) -> None:
    served = live_server(scenario="one_handover", speed=3.0, video=False)
    url = served.url("/ws").replace("http://", "ws://")
    stalled: list[Any] = []

    async def run() -> float:
        async with aiohttp.ClientSession() as http, http.ws_connect(url) as control:
            await next_text(control, "role")  # this tab controls; the raw one watches
            stalled.append(websocket(served.port, receive_buffer=4096))
            await until_phase(control, "waiting_for_gesture")
            tab = next(t for t in served.server.tabs if t.role == "watch")
            deadline = time.monotonic() + 30
            while tab.frames_dropped < 5:  # the frozen tab's socket is full: frames wait
                assert time.monotonic() < deadline, "the stalled tab never backed up"
                await next_text(control, "status")
            await control.send_str('{"type": "end"}')
            ended = time.monotonic()
            assert (await until_phase(control, "done"))["status"] == "ended"
            while not control.closed:  # read on, as a page does, until the server says goodbye
                await control.receive(timeout=30)
            return ended

    try:
        ended = run_async(run())
        assert served.wait_over(10) == "ended"
        assert time.monotonic() - ended < 5.0, "the server waited on the frozen tab"
    finally:
        for sock in stalled:
            sock.close()
