"""A study's screens over the sockets: every message checked on the server, a decline that
keeps nothing, and a run the experimenter ends early marked unfinished in the registry.
No session starts here (the screens come before the first block)."""

from __future__ import annotations

import json
from pathlib import Path

import aiohttp
from conftest import start_server
from page_driver import run_async
from test_web_socket import receive_until, wait_phase

from robin_sim.lab.run import prepare
from robin_sim.live.config import LiveConfig

STUDY = """\
name: screens
protocol: reactive_vs_proactive
consent: {text: You will teach a robot., agree: "Yes", decline: "No"}
demographics:
  items:
    - {id: age, text: Age, kind: number, min: 18, max: 99}
practice: {types: [A], block_seconds: 5}
"""


def serve(folder: Path):
    run = prepare(folder, None, LiveConfig(video=False))
    served = start_server(
        run.configs,
        questionnaires=run.study.protocol.questionnaires,
        screens=run.study.screens,
        journal=run.journal,
    )
    return run, served


def test_junk_is_refused_on_every_screen_and_a_decline_keeps_nothing(tmp_path: Path) -> None:
    folder = tmp_path / "study"
    folder.mkdir()
    (folder / "study.yaml").write_text(STUDY)
    run, served = serve(folder)

    async def decline() -> list[str]:
        refused = []
        async with aiohttp.ClientSession() as client:
            page = await client.ws_connect(f"ws://127.0.0.1:{served.port}/ws")
            shown = await wait_phase(page, "consent")
            assert shown["consent"]["agree"] == "Yes"
            for junk in (
                '{"type": "start"}',
                '{"type": "consent", "value": "maybe"}',
                '{"type": "finish"}',
                '{"type": "answers", "questionnaire": "demographics", "answers": {"age": 30}}',
            ):
                await page.send_str(junk)
                refused.append((await receive_until(page, "error"))["message"])
            await page.send_str('{"type": "consent", "value": "decline"}')
            done = await wait_phase(page, "done")
            assert done["status"] == "declined"
        return refused

    refused = run_async(decline())
    assert served.wait_over(30) == "declined"
    assert refused[0] == "start: the consent screen is shown; send consent (agree or decline)"
    assert "unknown value 'maybe'; valid choices: 'agree', 'decline'" in refused[1]
    assert refused[2].startswith("finish: the consent screen is shown")
    assert "message type 'answers' is unknown" in refused[3]
    assert run.registry.entry(run.participant)["status"] == "declined"
    assert not (folder / "sessions").exists()

    run, served = serve(folder)  # the next participant agrees, then the experimenter ends

    async def agree() -> list[str]:
        refused = []
        async with aiohttp.ClientSession() as client:
            boss = await client.ws_connect(
                f"ws://127.0.0.1:{served.port}/ws?token={served.server.experimenter_token}"
            )
            page = await client.ws_connect(f"ws://127.0.0.1:{served.port}/ws")
            await wait_phase(page, "consent")
            await page.send_str('{"type": "consent", "value": "agree"}')
            form = await wait_phase(page, "questionnaire")
            assert form["questionnaire"]["name"] == "demographics"
            for answers in ({"age": 7}, {"age": "old"}, {"years": 30}):
                message = {"type": "answers", "questionnaire": "demographics", "answers": answers}
                await page.send_str(json.dumps(message))
                refused.append((await receive_until(page, "error"))["message"])
            await page.send_str(
                '{"type": "answers", "questionnaire": "demographics", "answers": {"age": 30}}'
            )
            shown = await wait_phase(page, "instructions")
            assert shown["practice"] and shown["block_number"] == 1
            await boss.send_str('{"type": "end"}')
            await wait_phase(page, "done")
        return refused

    refused = run_async(agree())
    assert served.wait_over(30) == "ended"
    assert "demographics.age: expected a whole number from 18 to 99" in refused[0]
    assert "got 'old'" in refused[1] and "unknown item 'years'; items: age" in refused[2]
    entry = run.registry.entry(run.participant)
    assert (run.participant, entry["status"], entry["outcome"]) == ("P02", "unfinished", "ended")
    saved = (folder / "sessions" / "P02" / "demographics.jsonl").read_text()
    assert json.loads(saved)["answers"] == {"age": 30}
