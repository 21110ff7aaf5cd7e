"""Questionnaires over the sockets: answered by the participant, skipped by the experimenter."""

from __future__ import annotations

import asyncio
import json
import logging
from pathlib import Path

import aiohttp
import pytest
from page_driver import run_async
from test_web_socket import receive_until, wait_phase

from robin_sim.live.questionnaires import load_questionnaires
from robin_sim.live.session import LiveConfig
from robin_sim.live.tabs import MAX_DROPS_LOGGED, RATE_LIMIT

pytestmark = pytest.mark.slow
EASE = {"name": "ease", "points": 5, "items": [{"id": "clear", "text": "Robin understood me."}]}


FLOOD = 2000  # messages sent at once during the questionnaire: nearly all over the rate limit


def test_answers_are_kept_and_next_block_skips_the_questionnaire(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
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
                        '{"type": "answers", "questionnaire": "ease", "answers": {"clear": 5}, '
                        '"mood": "fine"}'
                    )
                    refused.append((await receive_until(participant, "error"))["message"])
                    for _ in range(FLOOD):  # none waits for its reply
                        await participant.send_str('{"type": "thumb", "value": "up"}')
                    await asyncio.sleep(1.2)  # the rate limit's second is over
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

    caplog.set_level(logging.WARNING, "robin_sim.live.server")
    refused = run_async(scenario())
    assert served.wait_over(60) == "ended"
    assert refused[0].startswith("thumb: a questionnaire is shown; answer it first")
    assert refused[1] == "ease.clear: expected a whole number from 1 to 5 in steps of 1, got '9'"
    assert refused[2].startswith("answers: unknown field(s) 'mood'; an answer takes 'type'")
    assert refused[3] == refused[0]
    # the flood: a few log lines and a count, not one line a message
    dropped = [r.getMessage() for r in caplog.records if "rate limit" in r.getMessage()]
    dropped += [r.getMessage() for r in caplog.records if "dropped a message" in r.getMessage()]
    assert len(dropped) <= MAX_DROPS_LOGGED + 2, dropped[:10]
    total = int(next(m for m in dropped if m.endswith("in all")).split()[1])
    assert FLOOD - RATE_LIMIT <= total <= FLOOD
    # every message of the questionnaire is in the block's inputs.jsonl, refused ones with why
    inputs = [json.loads(line) for line in (tmp_path / "live/P01/b1/inputs.jsonl").open()]
    late = [e for e in inputs if e["raw"] != '{"type": "end"}' and e["raw"] != {"type": "end"}]
    over = [e for e in late if e["error"].startswith("too many messages")]
    assert len(over) == total and not any(e["accepted"] for e in over)
    answers = [e for e in late if "answers" in str(e["raw"])]
    assert [e["error"][:24] for e in answers] == [
        "ease.clear: expected a w",
        "answers: unknown field(s",
        "",
    ]
    assert answers[-1]["accepted"] and not (tmp_path / "live/P01/b1/states.npz").exists()
    folder = tmp_path / "live" / "P01"
    saved = [json.loads(line) for line in (folder / "b1" / "questionnaires.jsonl").open()]
    assert [(e["questionnaire"], e["answers"], e["block"]) for e in saved] == [
        ("ease", {"clear": 5}, 1)
    ]
    assert not (folder / "b2" / "questionnaires.jsonl").exists()  # skipped: nothing made up
