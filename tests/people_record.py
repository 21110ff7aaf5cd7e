"""Record the live sessions that ``robin-pil people --from-sessions`` fits people to.

    python tests/people_record.py [--out tests/data/fitted_people] [--speed 5]

No real participant can be recorded here, so two **scripted stand-ins** take their place: each
runs a real study (``robin_sim.lab``: registered, consent given on the consent screen and
recorded in the study's ``log.jsonl`` and ``registry.json``, the blocks, the debrief) through the
live run's :class:`~robin_sim.live.conductor.Conductor`, and every block is a real
:class:`~robin_sim.live.session.LiveSession` (physics paced at ``--speed`` x real time, no
video). A stand-in acts only on what the page shows (the status: whose turn, the guide's
instruction, the action Robin runs) and sends what a page sends (clicks on the leg's pixel,
gesture keys, thumbs), with its own human-like timing drawn in simulated seconds.

The stand-ins are not the fitted model: they think longer at a new leg, judge a right action
from its end (not its start), get quicker in their second block, and their timing carries the
wall clock's jitter. Two study folders are written:

* ``stand_ins/``: P01 (brisk, strict) and P02 (hesitant, lax), two blocks each of the paper's
  Table I (types A, B, C; one table of three legs), the figures of ``docs/people.md``;
* ``tiny/``: the same two people, one block of type A each (one leg), for the command's tests.

Each block's folder keeps ``summary.json``, ``inputs.jsonl``, ``events.jsonl`` and
``log.jsonl``; the ``states.npz`` that a replay needs is left out (it is large).
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import json
import math
import random
import shutil
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from robin_sim.render.gl_backend import ensure_gl_backend  # noqa: E402

ensure_gl_backend()  # before mujoco is imported

from robin_sim.lab.run import prepare  # noqa: E402
from robin_sim.live.conductor import Conductor  # noqa: E402
from robin_sim.live.config import LiveConfig  # noqa: E402
from robin_sim.live.inputs import LiveInputError  # noqa: E402
from robin_sim.live.session import LiveSession  # noqa: E402
from robin_sim.model import names  # noqa: E402

# m from a leg's centre where a stand-in may click it (along the table's axes)
AXES = [np.array(v, float) for v in ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0))]
OFFSETS = [axis * d for d in (0.0, 0.04, 0.08, 0.12) for axis in AXES]
FINGERS = ("close", "open")
GIVE_UP = 3  # gestures handed back in a row after which a stand-in ends the block
KEPT = ("summary.json", "inputs.jsonl", "events.jsonl", "log.jsonl")
STUDY = """\
name: {name}
description: scripted stand-ins for people to fit (tests/people_record.py); not real people
protocol: protocol.yaml
design: within
participants: 2
id_prefix: P
seed: 29
consent:
  title: Taking part
  text: |
    A scripted stand-in, not a person, agrees here: the consent screen and its record are the
    study's own, as for a real participant.
  agree: I agree to take part
  decline: I do not agree
limits:
  block_seconds: 1200
  block_actions: 200
debrief:
  text: Thank you.
"""
PROTOCOL = """\
name: stand_ins
description: reactive PIL, {repeat} block(s) of {types}
scenario: {scenario}
conditions:
  - {{system: pil, label: Robot A}}
order: fixed
blocks:
  - types: [{types}]
    repeat: {repeat}
instructions: Block {{block}} of {{blocks}}.
"""


@dataclass(frozen=True)
class StandIn:
    """A scripted participant's habits (simulated seconds; ``*_median`` and ``*_sigma`` of a
    lognormal). ``new_leg_s``: extra thinking at a new leg's first gesture; ``block_factor``:
    every later block's times are this much of the one before (practice)."""

    gesture_median: float
    gesture_sigma: float
    new_leg_s: float
    down_wrong: float  # P(thumb down | wrong action)
    down_median: float  # s from seeing the move begin
    down_sigma: float
    up_right: float  # P(thumb up | right action)
    up_median: float  # s from the end of the move (the feedback window opening)
    up_sigma: float
    down_right: float  # P(thumb down | right action): a slip
    block_factor: float


STAND_INS = {
    "P01": StandIn(1.0, 0.35, 1.5, 0.95, 0.9, 0.3, 0.85, 0.7, 0.4, 0.02, 0.85),
    "P02": StandIn(2.2, 0.5, 3.0, 0.70, 1.8, 0.5, 0.45, 1.6, 0.6, 0.06, 0.9),
}


def lognormal(rng: random.Random, median: float, sigma: float) -> float:
    return median * math.exp(rng.gauss(0.0, sigma))


class Player:
    """One stand-in at the page of one session (see the module doc)."""

    def __init__(self, session: LiveSession, habits: StandIn, scale: float, seed: str) -> None:
        self.session, self.habits, self.scale = session, habits, scale
        self.rng = random.Random(seed)
        self.gesture_at: float | None = None  # sim time the next gesture is made
        self.wanted = ""  # the action the last gesture meant
        self.judged = 0  # the robot actions judged so far (the logged count + 1)
        self.thumb_at: float | None = None
        self.thumb = ""
        self.up_pending = False  # a thumb up to give once the move ends
        self.last_leg = -1
        self.actions_at_gesture = -1  # the logged actions when the last gesture was made
        self.stuck = 0  # gestures in a row that Robin handed back

    def draw(self, median: float, sigma: float) -> float:
        return self.scale * lognormal(self.rng, median, sigma)

    def play(self) -> None:
        session = self.session
        while not session.done.is_set():
            status = session.status()
            if status["phase"] == "done":
                return
            if not status["paused"] and status["sim_time"] is not None:
                self.step(status)
            time.sleep(0.01)

    def step(self, status: dict[str, Any]) -> None:
        now, phase = float(status["sim_time"]), status["phase"]
        if phase == "waiting_for_gesture" and self.session.latest_frame() is not None:
            self.thumb_at, self.up_pending = None, False
            if self.gesture_at is None:
                if status["actions"] == self.actions_at_gesture:
                    self.stuck += 1  # handed back without an action: Robin could not act
                if self.stuck >= GIVE_UP:
                    with contextlib.suppress(LiveInputError):  # a person gives up here
                        self.session.receive({"type": "end"})
                    return
                leg = status["guide"]["leg"]["index"]
                extra = self.habits.new_leg_s if leg != self.last_leg else 0.0
                self.last_leg = leg
                wait = self.draw(self.habits.gesture_median, self.habits.gesture_sigma)
                self.gesture_at = now + wait + self.scale * extra
            elif now >= self.gesture_at:
                self.gesture_at = None
                self.make_gesture(status)
            return
        self.gesture_at = None
        acting = phase == "robot_acting" and status["action"] is not None
        if (acting or phase == "waiting_for_thumb") and status["actions"] + 1 > self.judged:
            self.judged = status["actions"] + 1
            self.plan_thumb(status["action"] or status["last_action"], now)
        if self.up_pending and phase == "waiting_for_thumb":
            self.up_pending = False
            self.thumb_at = now + self.draw(self.habits.up_median, self.habits.up_sigma)
        if self.thumb_at is not None and now >= self.thumb_at:
            self.thumb_at = None
            # a thumb too late is refused by the page (logged): silence approved
            with contextlib.suppress(LiveInputError):
                self.session.receive({"type": "thumb", "value": self.thumb})

    def plan_thumb(self, action: str, now: float) -> None:
        habits, roll = self.habits, self.rng.random()
        self.thumb_at, self.up_pending = None, False
        down = now + self.draw(habits.down_median, habits.down_sigma)
        if action != self.wanted:
            # a wrong move of the arm is always seen; a wrong finger motion may be missed
            if action not in FINGERS or roll < habits.down_wrong:
                self.thumb, self.thumb_at = "down", down
        elif roll < habits.down_right:
            self.thumb, self.thumb_at = "down", down
        elif roll < habits.down_right + habits.up_right:
            self.thumb, self.up_pending = "up", True

    def make_gesture(self, status: dict[str, Any]) -> None:
        if status["actions"] != self.actions_at_gesture:
            self.stuck = 0
        self.actions_at_gesture = status["actions"]
        guide, task = status["guide"], status["task"]
        gesture, _, wanted = task["handover_steps"][guide["step"]].partition(" -> ")
        self.wanted = wanted
        try:
            if gesture != "pointing":
                self.session.receive({"type": "gesture", "gesture": gesture.replace(" ", "_")})
                return
            picker = self.session.picker
            assert picker is not None
            if wanted == "object":
                x, y = leg_pixel(picker, guide["leg"]["index"])
            else:
                x, y = picker.spot_pixels()[task["handover"] % len(picker.spot_pixels())]
            self.session.receive({"type": "point", "x": x, "y": y})
        except LiveInputError:
            pass  # not the turn after all (logged): the next look tries again


def leg_pixel(picker: Any, leg: int) -> tuple[float, float]:
    """A pixel where leg ``leg`` is seen (Robin's hand may hide its centre): the first of a
    few points along it that the picker finds on that leg."""
    centre = np.array(picker.data.body(names.leg_body(leg)).xpos)
    for offset in OFFSETS:
        x, y = picker.project(centre + offset)
        try:
            target = picker.pick(x, y)
        except LiveInputError:
            continue
        if target.kind == "leg" and target.index == leg:
            return x, y
    return picker.project(centre)


def write_study(folder: Path, scenario: str, types: str, repeat: int) -> None:
    folder.mkdir(parents=True)
    (folder / "study.yaml").write_text(STUDY.format(name=folder.name), encoding="utf-8")
    protocol = PROTOCOL.format(scenario=scenario, types=types, repeat=repeat)
    (folder / "protocol.yaml").write_text(protocol, encoding="utf-8")


async def run_participant(folder: Path, who: str, speed: float) -> None:
    base = LiveConfig(video=False, speed=speed, fps=2.0, eye_inset=False)
    study = prepare(folder, who, base)
    conductor = Conductor(study.configs, (), study.study.screens, study.journal)
    loop = asyncio.get_running_loop()
    conductor.attach(loop, lambda frame: None)
    await conductor.participant_arrived()
    await conductor.receive(json.dumps({"type": "consent", "value": "agree"}))
    habits = STAND_INS[who]
    for block in range(len(study.configs)):
        while conductor.phase != "instructions":
            await asyncio.sleep(0.05)
        await conductor.receive(json.dumps({"type": "start"}))
        player = Player(conductor.session, habits, habits.block_factor**block, f"{who}:{block}")
        await loop.run_in_executor(None, player.play)
        while conductor.phase == "running":
            await asyncio.sleep(0.05)
    while conductor.phase != "debrief":
        await asyncio.sleep(0.05)
    await conductor.receive(json.dumps({"type": "finish"}))
    print(who, "->", await conductor.finished(), flush=True)


def prune(folder: Path) -> None:
    """Keep each block's text files only (no states.npz)."""
    for session in (folder / "sessions").glob("*/*"):
        if session.is_dir():
            for path in session.iterdir():
                if path.name not in KEPT:
                    path.unlink()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=ROOT / "tests/data/fitted_people")
    parser.add_argument("--speed", type=float, default=5.0)
    parser.add_argument("--only", choices=("stand_ins", "tiny"), default=None)
    args = parser.parse_args()
    plans = {"stand_ins": ("table_one", "A, B, C", 2), "tiny": ("one_handover", "A", 1)}
    for name, (scenario, types, repeat) in plans.items():
        if args.only not in (None, name):
            continue
        folder = args.out / name
        if folder.exists():
            shutil.rmtree(folder)
        write_study(folder, scenario, types, repeat)
        for who in STAND_INS:
            asyncio.run(run_participant(folder, who, args.speed))
        prune(folder)
        print("wrote", folder)


if __name__ == "__main__":
    main()
