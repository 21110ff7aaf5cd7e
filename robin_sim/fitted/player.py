"""A fitted person at a live participant's place: gestures and thumbs from the physics tick.

:class:`FittedPlayer` plays a :class:`~pil.experiments.people_fit.FittedPerson` in a simulated
session (:mod:`robin_sim.fitted.session`): it is a
:class:`~robin_sim.control.simulator.Simulator` observer, so it acts between two control
ticks, in simulated time, as the page's messages reach a live session between two ticks. It
hands the :class:`~robin_sim.live.participant.LiveParticipant` what a page would send, so the
session runs through the live engine unchanged (the guide, the feedback window, silence, the
hand-backs, the watchdog):

* **its turn**: the gesture the guide asks for (pointing at its leg, or at spot ``handover``),
  one drawn gesture latency after Robin last gave the turn back (a step logged or handed back,
  or the start), or at once if that moment has passed;
* **each robot action** (the step loop's ``decided``): a thumb down with the fitted rate (a
  wrong arm move, a wrong finger motion, a right action: each its own rate), else on a right
  action a thumb up with its rate, else nothing; the thumb comes one drawn latency after the
  action began. A thumb after the feedback window is refused as the page refuses it (logged):
  silence has approved the action;
* **giving up**: after :data:`GIVE_UP` gestures in a row handed back without a robot action
  (an approved wrong action can leave Robin where no gesture is valid), it ends the block, as
  the recorded stand-ins do.

Everything it sends is written to ``inputs.jsonl`` as a live session logs a page's messages.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from pil.experiments.people_fit import FittedPerson
from pil.task.records import StepRecord
from pil.task.world import Target
from pil.types import Feedback, Gesture
from robin_sim.control.simulator import Simulator
from robin_sim.live.participant import Gesturing, LiveParticipant

GIVE_UP = 3  # gestures handed back in a row after which the person ends the block
LATE_ERROR = (  # the page's refusal of a thumb with no action to judge
    "There is no robot action to judge now: give a thumb while Robin moves or just after."
)
InputLog = Callable[[dict[str, Any], str, float], None]  # raw message, error, sim time


class FittedPlayer:
    """``person`` at ``participant``'s place (see the module doc); ``rng`` draws its dice."""

    def __init__(
        self,
        person: FittedPerson,
        participant: LiveParticipant,
        rng: np.random.Generator,
        log_input: InputLog,
    ) -> None:
        self.person, self.participant, self.rng = person, participant, rng
        self.log_input = log_input
        self.turn_from = 0.0  # sim time Robin last gave the turn back
        self.gesture_at: float | None = None  # when this turn's gesture is made
        self.offered = False  # this turn's gesture is made
        self.thumb: tuple[Feedback, float] | None = None  # the planned thumb and its time
        self.stuck = 0  # gestures in a row handed back without an action
        spots = len(participant.body.world.layout.spots)
        self.spots = max(spots, 1)

    @property
    def now(self) -> float:
        return float(self.participant.body.world.time)

    # --- told by the session ---------------------------------------------------------------
    def decided(self, record: StepRecord) -> None:
        """The robot begins ``record``'s action: plan the thumb."""
        self.stuck = 0
        action = None if record.action is None else record.action.value
        meant = None if record.intended_action is None else record.intended_action.value
        verdict = self.person.verdict(action, meant, self.rng)
        self.thumb = None if verdict is None else (verdict[0], self.now + verdict[1])

    def gave_turn(self) -> None:
        """Robin gave the turn back (a step logged, or a gesture handed back)."""
        self.turn_from, self.gesture_at, self.offered = self.now, None, False

    def handed_back(self) -> None:
        self.stuck += 1
        self.gave_turn()

    # --- every control tick ----------------------------------------------------------------
    def __call__(self, sim: Simulator) -> None:
        participant, now = self.participant, self.now
        if self.thumb is not None and now >= self.thumb[1]:
            feedback, _ = self.thumb
            self.thumb = None
            raw = {"type": "thumb", "value": "up" if feedback is Feedback.OK else "down"}
            if participant.judging and participant.thumb is None:
                participant.offer(feedback)
                self.log_input(raw, "", now)
            else:
                self.log_input(raw, LATE_ERROR, now)
        if participant.phase != "waiting_for_gesture" or self.offered:
            return
        if self.stuck >= GIVE_UP:
            self.offered = True
            participant.offer("end")
            self.log_input({"type": "end"}, "", now)
            return
        if self.gesture_at is None:
            self.gesture_at = self.turn_from + self.person.gesture_latency.draw(self.rng)
        if now >= self.gesture_at:
            self.offered = True
            gesturing, raw = self._gesture()
            participant.offer(gesturing)
            self.log_input(raw, "", now)

    def _gesture(self) -> tuple[Gesturing, dict[str, Any]]:
        """The gesture the guide asks for, and the message a page would have sent."""
        participant = self.participant
        guide: Any = participant.guide()
        task: Any = participant.task()
        step = str(task["handover_steps"][int(guide["step"])])  # e.g. "pointing -> object"
        name, _, meant = step.partition(" -> ")
        gesture = Gesture(name)
        if gesture is not Gesture.POINTING:
            return Gesturing(gesture), {"type": "gesture", "gesture": name.replace(" ", "_")}
        if meant == "object":
            target = Target("leg", int(guide["leg"]["index"]))
        else:
            target = Target("spot", int(task["handover"]) % self.spots)
        return Gesturing(gesture, target), {
            "type": "point",
            "target": {"kind": target.kind, "index": target.index},
        }
