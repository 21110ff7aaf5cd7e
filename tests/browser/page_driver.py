"""Driving the live page in headless chromium as a participant would: keys, clicks, thumbs.

Shared by the browser tests and bench/bench_live.py. Everything goes through the page (real
key presses and mouse clicks on the displayed, possibly scaled, canvas); what the page shows is
read from ``window.robinLive``, the page's own record of what it received and drew.
"""

from __future__ import annotations

import base64
import json
from pathlib import Path
from typing import Any

import numpy as np

from pil.task.parts import resolve_scenario
from robin_sim.live.picking import Picker
from robin_sim.model import names

# The keys the page documents on its buttons.
KEY_OF = {"give_me": "g", "grasp": "r", "release": "l", "up": "ArrowUp", "down": "ArrowDown"}
# Handover type A: each gesture and the action the participant means by it.
TYPE_A = [("point", "object"), ("grasp", "close"), ("give_me", "human"), ("release", "open")]


def status(page: Any) -> dict[str, Any]:
    return page.evaluate("() => window.robinLive.status")


def wait_status(page: Any, condition: str, timeout_s: float = 60.0) -> dict[str, Any]:
    """Wait until the page's last status satisfies the JS expression ``condition`` (on ``s``)."""
    page.wait_for_function(
        f"() => {{ const s = window.robinLive.status; return !!s && ({condition}); }}",
        timeout=timeout_s * 1000,
        polling=50,
    )
    return status(page)


def leg_pixels(
    scenario: str | None, width: int = 640, height: int = 480
) -> list[tuple[float, float]]:
    """Each leg's centre as a frame pixel, projected with the engine's picking camera model
    from the scene as it is laid out at the start of a session."""
    from robin_sim.episode.config import EpisodeConfig
    from robin_sim.episode.physical_assembly import layout_of

    layout = layout_of(EpisodeConfig(scenario=scenario, video=False).spec().run.scenario)
    picker = Picker(layout, width, height)
    return [
        picker.project(picker.data.xpos[picker.model.body(names.leg_body(k)).id])
        for k in range(len(layout.legs))
    ]


def click_frame_pixel(page: Any, x: float, y: float, width: int = 640, height: int = 480) -> None:
    """Click the displayed canvas where frame pixel (x, y) is shown (whatever its scale)."""
    box = page.locator("#scene").bounding_box()
    page.mouse.click(
        box["x"] + (x + 0.5) * box["width"] / width, box["y"] + (y + 0.5) * box["height"] / height
    )


def canvas_pixels(page: Any) -> np.ndarray:
    """What the canvas shows, as an (h, w, 3) RGB uint8 array (read back as a PNG)."""
    import cv2

    url = page.evaluate("() => document.getElementById('scene').toDataURL('image/png')")
    png = base64.b64decode(url.split(",", 1)[1])
    bgr = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    return bgr[:, :, ::-1]


def read_jsonl(path: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def scenario_types(scenario: str) -> list[str]:
    return [t.name for t in resolve_scenario(scenario, {}).types]


def play_steps(
    page: Any, steps: list[tuple[str, str]], leg: tuple[float, float], until: int | None = None
) -> tuple[int, int]:
    """Be the participant for ``steps`` (gesture, meant action): make each gesture (a click on
    frame pixel ``leg`` for pointing, else its key), stop a wrong move with thumb down at once,
    approve the meant action with thumb up. Returns (steps approved, thumbs down) once
    ``until`` (default: all) steps are approved."""
    until = len(steps) if until is None else until
    step, judged, downs = 0, set(), 0
    for _ in range(400):  # each pass waits for the page to show something new
        s = wait_status(
            page,
            "s.phase === 'waiting_for_gesture' || s.phase === 'done' || "
            "s.phase === 'waiting_for_thumb' || (s.phase === 'robot_acting' && "
            "!!s.action)",
            timeout_s=90,
        )
        if s["phase"] == "done" or step >= until:
            break
        gesture, meant = steps[step]
        key = (s["actions"], s["gestures"], s.get("action") or s.get("last_action"))
        if s["phase"] == "waiting_for_gesture":
            if gesture == "point":
                click_frame_pixel(page, *leg)
            else:
                page.keyboard.press(KEY_OF[gesture])
            wait_status(page, "s.phase !== 'waiting_for_gesture'")
        elif key in judged:
            page.wait_for_timeout(50)
        elif s["phase"] == "robot_acting" and s["action"] != meant:
            page.keyboard.press(KEY_OF["down"])  # stop the wrong move at once
            judged.add(key)
            downs += 1
        elif s["phase"] == "waiting_for_thumb":
            right = s["last_action"] == meant
            page.keyboard.press(KEY_OF["up" if right else "down"])
            judged.add(key)
            downs += not right
            step += right
            if step >= until:
                break  # at once: the caller may act during what follows (a carry to the bin)
        else:
            page.wait_for_timeout(50)
    return step, downs


def run_async(coroutine: Any) -> Any:
    """``asyncio.run(coroutine)`` in a thread of its own: Playwright's sync API keeps an event
    loop running in the main thread once a browser is up."""
    import asyncio
    import threading

    result: list[Any] = []
    failure: list[BaseException] = []

    def main() -> None:
        try:
            result.append(asyncio.run(coroutine))
        except BaseException as problem:
            failure.append(problem)

    thread = threading.Thread(target=main, name="test-client")
    thread.start()
    thread.join()
    if failure:
        raise failure[0]
    return result[0]
