"""The experimenter's socket with a plain client: refused commands, next block, end."""

from __future__ import annotations

import json
from pathlib import Path

import aiohttp
import pytest
from page_driver import run_async
from test_web_socket import receive_until, wait_phase

from robin_sim.live.session import LiveConfig

pytestmark = pytest.mark.slow


def test_next_block_saves_the_block_and_starts_the_next_then_end(tmp_path: Path) -> None:
    from conftest import start_server  # tests/browser/conftest.py, as test_browser_page does

    options = dict(
        out_root=tmp_path / "live",
        handover_types=("A",),
        speed=3.0,
        video=False,
        protocol="pilot",
        instructions="Hand over the legs.",
    )
    served = start_server(
        [LiveConfig(session="b1", block=1, **options), LiveConfig(session="b2", block=2, **options)]
    )
    base = f"ws://127.0.0.1:{served.port}/ws"
    boss_url = f"{base}?token={served.server.experimenter_token}"

    async def scenario() -> dict[str, object]:
        seen: dict[str, object] = {}
        async with aiohttp.ClientSession() as client:
            boss = await client.ws_connect(boss_url)
            seen["role"] = (await receive_until(boss, "role"))["role"]
            for message in (
                '{"type": "pause"}',
                '{"type": "note", "text": "early"}',
                '{"type": "dance"}',
                '{"type": "note", "text": "  "}',
                "[" * 3000,
            ):
                await boss.send_str(message)
                seen.setdefault("refused", []).append(  # type: ignore[union-attr]
                    (await receive_until(boss, "error"))["message"]
                )
            participant = await client.ws_connect(base)
            seen["participant_role"] = (await receive_until(participant, "role"))["role"]
            await wait_phase(participant, "instructions")
            await participant.send_str('{"type": "start"}')
            await wait_phase(participant, "waiting_for_gesture")
            await boss.send_str('{"type": "next_block"}')
            seen["next"] = (await receive_until(boss, "done"))["command"]
            while (await receive_until(participant, "status"))["block_number"] != 2:
                pass
            await wait_phase(participant, "instructions")
            await participant.send_str('{"type": "start"}')
            await wait_phase(participant, "waiting_for_gesture")
            await boss.send_str('{"type": "end"}')
            seen["end"] = (await receive_until(boss, "done"))["command"]
            await participant.close()
            await boss.close()
        return seen

    seen = run_async(scenario())
    assert served.wait_over(60) == "ended"
    assert seen["role"] == "experimenter" and seen["participant_role"] == "control"
    refused = seen["refused"]
    assert refused[0] == "pause: no block is running now (waiting)"
    assert refused[1].startswith("note: this block has not started")
    assert refused[2] == ("unknown command 'dance'; valid: pause, resume, end, next_block, note")
    assert refused[3] == "note: write some text first"
    assert refused[4].startswith("a command is a JSON object")
    assert seen["next"] == "next_block" and seen["end"] == "end"
    for block in ("b1", "b2"):
        summary = json.loads((tmp_path / "live" / "P01" / block / "summary.json").read_text())
        assert summary["status"] == "ended", (block, summary["status"])
