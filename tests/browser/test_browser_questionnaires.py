"""Questionnaires between protocol blocks, answered in headless chromium, in the report.

A two-block protocol (pil, then proactive) of the one-handover scenario: block 1 is played to
the end through the page, block 2 ended at once; after each, the NASA-TLX form and a one-item
Likert form are answered with real clicks. ``robin-pil report`` on the sessions folder then
shows the raw TLX score and the Likert item per condition.
"""

from __future__ import annotations

import json

import pytest
from page_driver import TYPE_A, leg_pixels, play_steps, read_jsonl, wait_status

pytestmark = pytest.mark.slow
SPEED = 3.0
VIEWPORT = {"width": 1100, "height": 820}
TLX = ("mental", "physical", "temporal", "performance", "effort", "frustration")
PROTOCOL = """\
name: rated
scenario: one_handover
conditions: [pil, proactive]
order: fixed
blocks:
  - types: [A]
instructions: "Block {block} of {blocks}"
questionnaires:
  - nasa-tlx
  - name: ease
    points: 5
    items:
      - {id: clear, text: Robin understood what I meant.}
"""


def answer(page, name: str, values: dict[str, int]) -> None:
    """Tick each item's answer on the shown form and send it."""
    wait_status(page, f"s.phase === 'questionnaire' && s.questionnaire.name === '{name}'")
    for item, value in values.items():
        page.locator(f'input[name="{name}-{item}"][value="{value}"]').check()
    page.locator("#q-send").click()


def test_answers_given_on_the_page_appear_in_the_report(browser, tmp_path, capsys) -> None:
    from conftest import start_server

    from robin_sim.cli.live import questionnaires_of, session_configs
    from robin_sim.cli.main import build_parser, main

    path = tmp_path / "protocol.yaml"
    path.write_text(PROTOCOL)
    out = tmp_path / "live"
    args = build_parser("live").parse_args(
        [
            "live",
            "--protocol",
            str(path),
            "--participant",
            "P01",
            "--out",
            str(out),
            "--speed",
            str(SPEED),
            "--no-video",
        ]
    )
    served = start_server(session_configs(args), questionnaires=questionnaires_of(args))
    try:
        page = browser.new_page(viewport=VIEWPORT)
        page.on("dialog", lambda dialog: dialog.accept())
        page.goto(served.url("/"))
        wait_status(page, "s.phase === 'instructions'")
        page.locator("#start").click()
        approved, _ = play_steps(page, TYPE_A, leg_pixels("one_handover")[0])
        assert approved == len(TYPE_A)
        shown = wait_status(page, "s.phase === 'questionnaire'")
        assert shown["questionnaire"]["name"] == "nasa-tlx" and shown["questionnaires"] == 2
        token = served.server.experimenter_token  # the experimenter's view says so too
        boss = browser.new_page(viewport=VIEWPORT)
        boss.goto(f"http://127.0.0.1:{served.port}/experimenter?token={token}")
        wait_status(boss, "s.phase === 'questionnaire'")
        assert boss.locator("#turn").inner_text() == "Questionnaire"  # not "Your turn"
        boss.close()
        assert page.locator("#questionnaire").is_visible()
        assert page.locator(".q-item").count() == 6
        assert page.locator("#controls button[data-send='give_me']").is_disabled()
        # one item left open: the page asks for it and nothing is sent
        for item in TLX[:-1]:
            page.locator(f'input[name="nasa-tlx-{item}"][value="30"]').check()
        page.locator("#q-send").click()
        assert "Please answer every question" in page.locator("#q-error").inner_text()
        assert page.locator(".q-item.missing").count() == 1
        answer(page, "nasa-tlx", {"frustration": 30})
        answer(page, "ease", {"clear": 4})
        wait_status(page, "s.phase === 'instructions' && s.block_number === 2")
        assert not page.locator("#questionnaire").is_visible()
        page.locator("#start").click()
        wait_status(page, "s.phase === 'waiting_for_gesture'")
        page.keyboard.press("e")  # block 2 ended at once: still rated
        answer(page, "nasa-tlx", dict(zip(TLX, (50, 60, 70, 80, 40, 75), strict=True)))
        answer(page, "ease", {"clear": 2})
        wait_status(page, "s.phase === 'done'")
        page.close()
        assert served.wait_over(60) == "ended"
    finally:
        served.server.stop_soon()
        served.thread.join(60)
    saved = read_jsonl(out / "P01" / "block1-pil" / "questionnaires.jsonl")
    assert [(e["questionnaire"], e["scores"]) for e in saved] == [
        ("nasa-tlx", {"raw_tlx": 30.0}),
        ("ease", {"clear": 4.0, "mean": 4.0}),
    ]
    summary = json.loads((out / "P01" / "block1-pil" / "summary.json").read_text())
    assert summary["status"] == "finished"
    capsys.readouterr()
    assert main(["report", str(out), "--out", str(tmp_path / "report")]) == 0
    printed = capsys.readouterr().out
    assert str(tmp_path / "report" / "questionnaires.md") in printed
    text = (tmp_path / "report" / "questionnaires.md").read_text()
    assert "| nasa-tlx | raw_tlx | pil | 1 | 30.00 |" in text
    assert "| nasa-tlx | raw_tlx | proactive | 1 | 62.50 |" in text
    assert "| ease | clear | pil | 1 | 4.00 |" in text
    assert "| ease | clear | proactive | 1 | 2.00 |" in text
