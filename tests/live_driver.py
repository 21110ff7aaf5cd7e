"""A test participant for live sessions: clicks, gestures and thumbs from the test thread.

It acts only on what the page shows (``LiveSession.status()`` and the frames): it waits for its
turn, clicks the pixel where a leg or spot is seen (projected with the picker's camera model),
and judges each robot action by its name in the status, as a participant reads the page.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from robin_sim.live.session import LiveConfig, LiveSession
from robin_sim.model import names

WAIT_S = 120.0  # s of wall time a test waits for the session to reach a state


class Driver:
    """Drives ``session`` like a participant at the page."""

    def __init__(self, session: LiveSession) -> None:
        self.session = session

    def wait(self, done: Callable[[dict[str, Any]], bool], what: str) -> dict[str, Any]:
        """Poll the status until ``done(status)``; fail after :data:`WAIT_S`."""
        end = time.monotonic() + WAIT_S
        while time.monotonic() < end:
            status = self.session.status()
            if done(status):
                return status
            if self.session.done.is_set():
                raise AssertionError(f"session ended waiting for {what}: {status}")
            time.sleep(0.02)
        raise AssertionError(f"timed out waiting for {what}: {self.session.status()}")

    def my_turn(self) -> dict[str, Any]:
        """Wait until the session waits for a gesture (and a frame is there to click on)."""
        return self.wait(
            lambda s: (
                s["phase"] == "waiting_for_gesture" and self.session.latest_frame() is not None
            ),
            "the participant's turn",
        )

    def pixel_of_leg(self, leg: int) -> tuple[float, float]:
        picker = self.session.picker
        return picker.project(picker.data.body(names.leg_body(leg)).xpos)

    def point_at_leg(self, leg: int) -> None:
        x, y = self.pixel_of_leg(leg)
        self.session.receive({"type": "point", "x": x, "y": y})

    def gesture(self, name: str) -> None:
        self.session.receive({"type": "gesture", "gesture": name})

    def judge(self, wanted: str, *, silent: bool = False) -> list[str]:
        """Judge the robot's actions on the gesture just made until one is approved: thumb
        down during the move for any other action, thumb up (or nothing, ``silent``) for
        ``wanted``. Returns the actions seen."""
        seen: list[str] = []
        start = self.session.status()["actions"]
        while True:
            status = self.wait(
                lambda s: (
                    s["action"] is not None
                    or s["phase"] == "waiting_for_thumb"
                    or (s["phase"] == "waiting_for_gesture" and s["actions"] > start + len(seen))
                    or s["phase"] == "done"
                ),
                "a robot action",
            )
            if status["phase"] in ("waiting_for_gesture", "done"):
                return seen
            action = status["action"] or status["last_action"]
            seen.append(action)
            if action != wanted:
                self.session.receive({"type": "thumb", "value": "down"})
            elif not silent:
                self.session.receive({"type": "thumb", "value": "up"})
            logged = start + len(seen)
            self.wait(lambda s, n=logged: s["actions"] >= n, "the action to be logged")
            if action == wanted:
                return seen


SPEED, FPS = 5.0, 5.0  # the pacing never runs ahead; a busy machine only slows the tests


def start_session(tmp_path: Path, **options: Any) -> tuple[LiveSession, Driver]:
    """A started live session without video at the tests' pace, and its driver."""
    config = LiveConfig(out_root=tmp_path, video=False, speed=SPEED, fps=FPS, **options)
    live = LiveSession(config)
    live.start()
    return live, Driver(live)


def read_jsonl(path: Path) -> list[dict[str, Any]]:
    """A session file's JSON lines ([] before it exists)."""
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
