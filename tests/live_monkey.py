"""Random and adversarial live participants, and the audit of what their sessions did.

Shared by ``tests/test_live_property.py`` (a hypothesis state machine over the session engine)
and ``tests/live_soak.py`` (whole sessions in a row). A participant's moves are what a page can
send: clicks on legs, spots or anywhere, the gesture keys, thumbs at any moment (early, during
a move, late: after the feedback window closed), wrong moves let stand (a thumb up, or no
thumb, for an action the guide did not ask for), "That was wrong" (take-backs, right after a
wrong move stood or at random), idle periods, junk, End, and with a webcam the tracker's
readings of the real footage (``tests/data/hands``). :class:`Audit` then reads the session's
files and physics and counts lock-ups (the robot's turn lasting longer than any step can, or
the participant stranded: more gestures in a row handed back than the watchdog allows, or a
gesture the guide asked for handed back), loops (the robot making a gesture again by itself,
or acting past its watchdog) and lost or doubled steps (steps not numbered 1, 2, 3, ... once
each, an executed action not logged, a take-back of a step that was not logged as let stand,
or take-backs the summary does not count).
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
from robin_sim.live.limits import WatchdogLimits
from robin_sim.live.session import LiveSession
from robin_sim.model import names

JUNK: tuple[Any, ...] = ("{", "[]", '{"type": "dance"}', '{"type": "thumb", "value": 9}', "x" * 300)
GESTURES = ("give_me", "grasp", "release")
# A robot's turn longer than this (sim s) with nothing changing is a lock-up: the longest step
# is the watchdog's limit plus one action and its feedback window.
STALL_S = 200.0
HANDED_BACK = WatchdogLimits().handed_back  # gestures in a row the watchdog lets go back


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
    guided: dict[int, str] = field(default_factory=dict)  # gesture number -> the guide's sent
    taking_back: bool = False  # a take-back was sent and the page has not shown it done
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

    def take_back(self) -> bool:
        """ "That was wrong" (refused outside its window: that is part of the test)."""
        taken = self.send("take_back", {"type": "take_back"})
        self.taking_back = self.taking_back or taken  # the guide changes once it is done
        return taken

    def late_thumb(self) -> None:
        """A thumb after the feedback window of the action now judged closed (refused then,
        or landing on Robin's next action)."""
        status = self.look()
        if status["phase"] in ("waiting_for_thumb", "robot_acting"):
            window = self.session.config.feedback_window
            self.idle(window + self.rng.uniform(0.2, 2.0))
        self.thumb("down" if self.rng.random() < 0.7 else "up")

    def let_wrong_stand(self) -> None:
        """Let Robin's action stand although the guide asked for another one (a thumb up, or
        no thumb through the window); then, half the time, take it back at once."""
        status = self.look()
        shown = status["action"] or (
            status["last_action"] if status["phase"] == "waiting_for_thumb" else None
        )
        if shown is None or shown == getattr(self, "meant", None):
            return
        if self.rng.random() < 0.5:
            self.thumb("up")
        actions = status["actions"]
        deadline = time.monotonic() + 30.0
        while time.monotonic() < deadline and not self.session.done.is_set():
            if self.look()["actions"] > actions:  # the move stood (or was judged)
                break
            time.sleep(0.02)
        self.idle(self.rng.uniform(0.0, 1.0))
        if self.rng.random() < 0.5:
            self.take_back()

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
            done = ("took back", "no approved action", "Too late")  # what the page says then
            if self.taking_back and any(text in status["notice"] for text in done):
                self.taking_back = False
            if not self.taking_back:  # the next gesture taken is this one, in this state
                self.guided[status["gestures"] + 1] = gesture
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
        if roll < 0.33:
            self.follow()
            self.idle(self.rng.uniform(0.0, 2.0))
        elif roll < 0.43:
            self.click_leg(self.rng.randrange(4))
        elif roll < 0.46:
            self.click_anywhere()
        elif roll < 0.54:
            self.gesture(self.rng.choice(GESTURES))
        elif roll < 0.63:
            self.thumb("down" if self.rng.random() < 0.6 else "up")
        elif roll < 0.71:
            self.let_wrong_stand()
        elif roll < 0.75:
            self.late_thumb()
        elif roll < 0.79:
            self.take_back()
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
    taken_back: int = 0  # approvals the participant took back
    let_stand: int = 0  # wrong moves the participant let stand (the guide meant another)

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
            if e["accepted"]
            and isinstance(e["raw"], dict)
            and e["raw"].get("type") in ("point", "gesture")
        )
        given += sum(
            1
            for e in inputs
            if e.get("reading", {}).get("acted", "").startswith(("gesture", "point"))
        )
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
        events = read_jsonl(folder / "events.jsonl")
        stranded = _stranded(events, steps, monkey.guided)
        lockups += bool(stranded)
        problems += stranded
        taken = [e for e in events if e["event"] == "take_back" and e.get("done")]
        stood = {s["t"] for s in acted if s["feedback"] != "not ok"}
        if [e["t"] for e in taken if e["t"] not in stood]:
            lost += 1
            problems.append(f"took back steps {[e['t'] for e in taken]}, let stand {stood}")
        if summary.get("live", {}).get("taken_back") != len(taken):
            lost += 1
            problems.append(f"{len(taken)} take-backs, summary {summary.get('live')}")
        asked = [e for e in inputs if e["accepted"] and e["raw"] == {"type": "take_back"}]
        answered = [e for e in events if e["event"] == "take_back"]  # done, or too late
        # unanswered: at most the last, when the session ended before Robin acted again
        pending = asked[len(answered) :]
        acted_after = pending and any(
            e["event"] == "acts" and e["sim_time"] > pending[-1]["sim_time"] for e in events
        )
        if len(answered) > len(asked) or len(pending) > 1 or acted_after:
            lost += 1
            problems.append(f"{len(asked)} take-backs accepted, {len(answered)} answered")
        wrong = sum(
            1 for s in acted if s["feedback"] != "not ok" and s["action"] != s["intended_action"]
        )
        return cls(
            lockups,
            loops,
            lost,
            len(acted),
            performed,
            str(summary.get("status")),
            problems,
            len(taken),
            wrong,
        )


def _stranded(
    events: list[dict[str, Any]], steps: list[dict[str, Any]], guided: dict[int, str]
) -> list[str]:
    """How the participant was stranded: more gestures in a row handed back (no action of
    Robin's between) than the watchdog lets go back, or a gesture the guide asked for (and
    nothing replaced before it was taken) handed back."""
    problems, run, longest = [], 0, 0
    for event in events:
        if event["event"] == "acts":
            run = 0
        elif event["event"] == "handed_back" or event.get("stuck"):
            run += 1
            longest = max(longest, run)
    if longest > HANDED_BACK:
        problems.append(f"{longest} gestures in a row handed back (watchdog {HANDED_BACK})")
    for step in steps:
        if step["action"] is None and step["true_gesture"] == guided.get(step["gesture_count"]):
            problems.append(f"the guide's {step['true_gesture']} handed back: {step['reason']}")
    return problems


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
