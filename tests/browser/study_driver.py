"""A study's participants in headless chromium: consent, demographics, practice, blocks with
their questionnaires, and the debrief, each through the page (keys where a participant would
use them), as ``robin-pil live --study DIR`` serves them."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from conftest import start_server
from page_driver import TYPE_A, leg_pixels, play_steps, wait_status

from robin_sim.lab.run import StudyRun, prepare
from robin_sim.live.config import LiveConfig

VIEWPORT = {"width": 1100, "height": 820}


def fast_base(speed: float, video: bool) -> LiveConfig:
    """What every session of a test study shares: sped up, a small stream."""
    return LiveConfig(speed=speed, fps=2.0, eye_inset=False, video=video, feedback_window=6.0)


def run_participant(
    browser: Any, folder: Path, base: LiveConfig, *, decline: bool = False, age: int = 30
) -> tuple[StudyRun, str]:
    """One participant of the study in ``folder`` through the page; (their run, the outcome)."""
    run = prepare(folder, None, base)
    study = run.study
    served = start_server(
        run.configs,
        questionnaires=study.protocol.questionnaires,
        screens=study.screens,
        journal=run.journal,
    )
    try:
        page = browser.new_page(viewport=VIEWPORT)
        page.goto(served.url("/"))
        wait_status(page, "s.phase === 'consent'")
        assert page.locator("#page-screen").is_visible()
        if decline:
            page.locator("#ps-decline").focus()
            page.keyboard.press("Enter")
            wait_status(page, "s.phase === 'done'")
            page.close()
            return run, served.wait_over(30)
        page.keyboard.press("Enter")  # the agree button has the focus
        demographics(page, age)
        leg = leg_pixels("one_handover")[0]
        for number, config in enumerate(run.configs, 1):
            wait_status(
                page, f"s.phase === 'instructions' && !s.starting && s.block_number === {number}"
            )
            page.keyboard.press("Enter")
            if config.practice:
                continue  # it ends by its time cap
            approved, _ = play_steps(page, TYPE_A, leg)
            assert approved == len(TYPE_A)
            questionnaire(page, config.block or 0, age)
        wait_status(page, "s.phase === 'debrief'")
        page.keyboard.press("Enter")  # Finish has the focus
        wait_status(page, "s.phase === 'done'")
        page.close()
        return run, served.wait_over(60)
    finally:
        served.server.stop_soon()
        served.thread.join(60)


def demographics(page: Any, age: int) -> None:
    """The demographics form: one item left open first (refused on the page), then sent."""
    wait_status(page, "s.phase === 'questionnaire' && s.questionnaire.name === 'demographics'")
    page.locator('input[name="demographics-age"]').fill(str(age))
    page.locator("#q-send").click()
    assert "Please answer every question" in page.locator("#q-error").inner_text()
    page.locator('input[name="demographics-hand"][value="right"]').check()
    page.locator('textarea[name="demographics-remarks"]').fill("no remarks, thank you")
    page.locator("#q-send").click()


def questionnaire(page: Any, block: int, seed: int) -> None:
    """The block's questionnaire: radio buttons (answers that differ by participant and
    block) and the slider moved with the keyboard."""
    wait_status(page, "s.phase === 'questionnaire' && s.questionnaire.name === 'ease'")
    answers = {"clear": 1 + (seed + block) % 5, "slow": 1 + seed % 3, "check": 4}
    for item, value in answers.items():
        page.locator(f'input[name="ease-{item}"][value="{value}"]').check()
    slider = page.locator('input[name="ease-liking"]')
    slider.focus()
    for _ in range(1 + block):
        page.keyboard.press("ArrowRight")  # 50 -> 51, 52: set with keys
    page.locator("#q-send").click()
