"""Questionnaires over the sockets: answered by the participant, skipped by the experimenter."""

from __future__ import annotations

import json
from pathlib import Path

import aiohttp
import pytest
from page_driver import run_async
from test_web_socket import receive_until, wait_phase

from robin_sim.live.questionnaires import load_questionnaires
from robin_sim.live.session import LiveConfig

pytestmark = pytest.mark.slow
EASE = {"name": "ease", "points": 5, "items": [{"id": "clear", "text": "Robin understood me."}]}


def test_answers_are_kept_and_next_block_skips_the_questionnaire(tmp_path: Path) -> None:
    from conftest import start_server

    options = dict(
        out_root=tmp_path / "live",
        handover_types=("A",),
        speed=3.0,
        video=False,
        protocol="pilot",
        instructions="Hand over the legs.",
    )
    served = start_server(
        [
            LiveConfig(session="b1", block=1, **options),
            LiveConfig(session="b2", block=2, **options),
        ],
        questionnaires=load_questionnaires([EASE], "test"),
    )
    base = f"ws://127.0.0.1:{served.port}/ws"

    async def scenario() -> list[str]:
        refused = []
        async with aiohttp.ClientSession() as client:
            boss = await client.ws_connect(f"{base}?token={served.server.experimenter_token}")
            participant = await client.ws_connect(base)
            for block in (1, 2):
                await wait_phase(participant, "instructions")
                await participant.send_str('{"type": "start"}')
                await wait_phase(participant, "waiting_for_gesture")
                await participant.send_str('{"type": "end"}')
                await wait_phase(participant, "questionnaire")
                await participant.send_str('{"type": "thumb", "value": "up"}')
                refused.append((await receive_until(participant, "error"))["message"])
                if block == 1:
                    await participant.send_str(
                        '{"type": "answers", "questionnaire": "ease", "answers": {"clear": 9}}'
                    )
                    refused.append((await receive_until(participant, "error"))["message"])
                    await participant.send_str(
                        '{"type": "answers", "questionnaire": "ease", "answers": {"clear": 5}}'
                    )
                else:
                    await boss.send_str('{"type": "next_block"}')  # skips the questionnaire
                    await receive_until(boss, "done")
            await wait_phase(participant, "done")
            await participant.close()
            await boss.close()
        return refused

    refused = run_async(scenario())
    assert served.wait_over(60) == "ended"
    assert refused[0].startswith("thumb: a questionnaire is shown; answer it first")
    assert refused[1] == "ease.clear: expected a whole number from 1 to 5 in steps of 1, got '9'"
    assert refused[2] == refused[0]
    folder = tmp_path / "live" / "P01"
    saved = [json.loads(line) for line in (folder / "b1" / "questionnaires.jsonl").open()]
    assert [(e["questionnaire"], e["answers"], e["block"]) for e in saved] == [
        ("ease", {"clear": 5}, 1)
    ]
    assert not (folder / "b2" / "questionnaires.jsonl").exists()  # skipped: nothing made up
