"""Random and adversarial live participants, and the audit of what their sessions did.

Shared by ``tests/test_live_property.py`` (a hypothesis state machine over the session engine)
and ``tests/live_soak.py`` (whole sessions in a row). A participant's moves are what a page can
send: clicks on legs, spots or anywhere, the gesture keys, thumbs at any moment (early, during
a move, late), idle periods, junk, End, and with a webcam the tracker's readings of the real
footage (``tests/data/hands``). :class:`Audit` then reads the session's files and physics and
counts lock-ups (the robot's turn lasting longer than any step can), loops (the robot making
a gesture again by itself, or acting past its watchdog) and lost or doubled steps.
"""

from __future__ import annotations

import json
import random
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from hand_data import footage, message

from robin_sim.live.inputs import LiveInputError
from robin_sim.live.session import LiveSession
from robin_sim.model import names

JUNK: tuple[Any, ...] = ("{", "[]", '{"type": "dance"}', '{"type": "thumb", "value": 9}', "x" * 300)
GESTURES = ("give_me", "grasp", "release")
# A robot's turn longer than this (sim s) with nothing changing is a lock-up: the longest step
# is the watchdog's limit plus one action and its feedback window.
STALL_S = 200.0


def read_jsonl(path: Path) -> list[dict[str, Any]]:
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


@dataclass
class Monkey:
    """One participant's moves on ``session`` (``rng``: its dice)."""

    session: LiveSession
    rng: random.Random
    readings: list[dict[str, Any]] = field(default_factory=list)  # webcam messages to send
    sent: dict[str, int] = field(default_factory=dict)  # move -> times
    stall_s: float = 0.0  # the longest robot's turn seen with nothing changing (sim s)
    _mark: tuple[Any, ...] | None = None
    _mark_at: float = 0.0

    @classmethod
    def with_footage(cls, session: LiveSession, rng: random.Random) -> Monkey:
        """A participant who also shows the real footage's hands to the webcam."""
        data = footage()
        readings = []
        for i in range(len(data["label"])):
            points = data["landmarks"][i]
            points = None if np.isnan(points).any() else points
            raw = message(points, str(data["handedness"][i]), float(data["score"][i]))
            raw["aspect"] = float(data["aspect"][i])
            readings.append(raw)
        return cls(session, rng, readings)

    def sim_time(self) -> float:
        body = self.session.body
        return 0.0 if body is None else body.world.time

    def send(self, move: str, raw: Any) -> bool:
        """Send one message as the page would; False when the session refused it."""
        self.sent[move] = self.sent.get(move, 0) + 1
        try:
            self.session.receive(raw)
        except LiveInputError:
            return False
        return True

    # --- moves ---------------------------------------------------------------------------------
    def click_leg(self, leg: int) -> bool:
        picker = self.session.picker
        if picker is None:
            return False
        x, y = picker.project(picker.data.body(names.leg_body(leg)).xpos)
        return self.send("point", {"type": "point", "x": x, "y": y})

    def click_anywhere(self) -> bool:
        x, y = self.rng.uniform(0, 639), self.rng.uniform(0, 479)
        return self.send("click", {"type": "point", "x": x, "y": y})

    def gesture(self, name: str) -> bool:
        return self.send("gesture", {"type": "gesture", "gesture": name})

    def thumb(self, value: str) -> bool:
        return self.send("thumb", {"type": "thumb", "value": value})

    def junk(self) -> bool:
        return self.send("junk", self.rng.choice(JUNK))

    def show_hand(self, count: int) -> None:
        """``count`` webcam readings in a row, a run of one gesture of the footage."""
        if not self.readings:
            return
        start = self.rng.randrange(len(self.readings))
        for k in range(count):
            self.send("hand", self.readings[(start + k) % len(self.readings)])
            time.sleep(0.05)

    def idle(self, sim_s: float, wall_cap_s: float = 60.0) -> None:
        """Do nothing for ``sim_s`` s of sim time (bounded in wall time), watching the page."""
        until, deadline = self.sim_time() + sim_s, time.monotonic() + wall_cap_s
        while self.sim_time() < until and time.monotonic() < deadline:
            if self.session.done.is_set():
                return
            self.look()
            time.sleep(0.02)

    def wait_turn(self, wall_cap_s: float = 120.0) -> None:
        """Wait until the participant is asked for a gesture (the session has started)."""
        deadline = time.monotonic() + wall_cap_s
        while time.monotonic() < deadline and not self.session.done.is_set():
            if self.look()["phase"] == "waiting_for_gesture":
                return
            time.sleep(0.05)

    def look(self) -> dict[str, Any]:
        """Read the page's status and time how long the robot's turn stands still."""
        status = self.session.status()
        now = self.sim_time()
        mark = (status["phase"], status["actions"], status["gestures"], status["action"])
        robot = status["turn"] == "robot" and status["phase"] != "done" and not status["paused"]
        if mark != self._mark or not robot:
            self._mark, self._mark_at = mark, now
        else:
            self.stall_s = max(self.stall_s, now - self._mark_at)
        return status

    def follow(self) -> None:
        """One move of a cooperative participant: the guide's gesture when asked (the leg it
        names, the first spot), the thumb a person would give (up for the meant action)
        otherwise. Mixed with the adversarial moves, sessions get deep into their handovers."""
        status = self.look()
        task, phase = status.get("task"), status["phase"]
        if task is None or phase == "done":
            return
        step = status["guide"]["step"] if status.get("guide") else 0
        gesture, meant = task["handover_steps"][step].split(" -> ")
        if phase == "waiting_for_gesture":
            self.meant = meant
            if gesture != "pointing":
                self.gesture(gesture.replace("give me", "give_me"))
            elif meant == "object":
                self.click_leg(status["guide"]["leg"]["index"])
            elif self.session.picker is not None:
                x, y = self.session.picker.spot_pixels()[0]
                self.send("point", {"type": "point", "x": x, "y": y})
        elif phase == "waiting_for_thumb" or status["action"] is not None:
            shown = status["action"] or status["last_action"]
            self.thumb("up" if shown == getattr(self, "meant", None) else "down")

    def step(self) -> None:
        """One random move (an adversarial mix: most are out of turn or off target)."""
        roll = self.rng.random()
        status = self.look()
        if roll < 0.35:
            self.follow()
            self.idle(self.rng.uniform(0.0, 2.0))
        elif roll < 0.5:
            self.click_leg(self.rng.randrange(4))
        elif roll < 0.55:
            self.click_anywhere()
        elif roll < 0.65:
            self.gesture(self.rng.choice(GESTURES))
        elif roll < 0.78:
            self.thumb("down" if self.rng.random() < 0.6 else "up")
        elif roll < 0.81:
            self.junk()
        elif roll < 0.87 and self.readings:
            self.show_hand(self.rng.randint(1, 4))
        else:
            self.idle(self.rng.uniform(0.5, 8.0) if status["phase"] != "done" else 0.0)


@dataclass
class Audit:
    """What one session did, from its files and physics (see the module doc)."""

    lockups: int
    loops: int
    lost_or_doubled: int
    actions: int
    gestures: int
    status: str
    problems: list[str]

    @classmethod
    def of(cls, session: LiveSession, monkey: Monkey, max_attempts: int) -> Audit:
        folder = session.out_dir
        steps = read_jsonl(folder / "log.jsonl")
        inputs = read_jsonl(folder / "inputs.jsonl")
        summary = json.loads((folder / "summary.json").read_text())
        problems: list[str] = []
        acted = [s for s in steps if s["action"] is not None]
        numbers = [s["t"] for s in acted]
        lost = 0
        if numbers != list(range(1, len(acted) + 1)):
            lost += 1
            problems.append(f"step numbers {numbers[:20]}... are not 1, 2, 3, ... once each")
        body = session.body
        executed = 0 if body is None else len(body.world.history)
        if not len(acted) <= executed <= len(acted) + 1:  # the one under way at the end
            lost += 1
            problems.append(f"{executed} actions executed, {len(acted)} logged")
        if summary.get("actions") not in (None, len(acted)):
            lost += 1
            problems.append(f"summary counts {summary.get('actions')} actions, log {len(acted)}")
        given = sum(
            1
            for e in inputs
            if e["accepted"] and isinstance(e["raw"], dict) and e["raw"].get("type") in
            ("point", "gesture")
        )
        given += sum(1 for e in inputs if e.get("reading", {}).get("acted", "").startswith(
            ("gesture", "point")
        ))
        performed = max((s["gesture_count"] for s in steps), default=0)
        loops = 0
        if performed > given:
            loops += 1
            problems.append(f"{performed} gestures performed for {given} the participant made")
        run: dict[int, int] = {}
        for s in acted:
            run[s["gesture_count"]] = run.get(s["gesture_count"], 0) + 1
        longest = max(run.values(), default=0)
        if longest > max_attempts + 1:
            loops += 1
            problems.append(f"{longest} actions on one gesture (watchdog {max_attempts})")
        lockups = int(monkey.stall_s > STALL_S) + int(summary.get("status") == "failed")
        if lockups:
            problems.append(f"stalled {monkey.stall_s:.0f} s; status {summary.get('status')}")
        return cls(
            lockups,
            loops,
            lost,
            len(acted),
            performed,
            str(summary.get("status")),
            problems,
        )


def play(
    session: LiveSession,
    monkey: Monkey,
    moves: int,
    on_move: Callable[[int], None] | None = None,
) -> None:
    """Let ``monkey`` make ``moves`` moves (or until the session is over), then End."""
    monkey.wait_turn()
    for k in range(moves):
        if session.done.is_set():
            break
        monkey.step()
        if on_move is not None:
            on_move(k)
    monkey.look()
