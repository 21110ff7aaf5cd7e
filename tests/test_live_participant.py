"""The live participant in the step loop, without the session: real physics, inputs per tick.

A participant who makes the scripted person's gestures and gives a thumb at once (up for the
wanted action, down for any other, in the first tick) leads the learner to exactly the
decisions of the learner-only study, the proactive robot's anticipations included: the
participant's interface keeps the loop's semantics.
"""

from __future__ import annotations

import pytest

from pil.task.assemble import assemble
from pil.task.records import StepRecord
from pil.task.runner import steps
from pil.task.spec import parse_run_spec
from pil.task.world import SymbolicWorld
from pil.types import Feedback
from robin_sim.live.participant import Gesturing, LiveParticipant
from robin_sim.person.body import PhysicalBody
from robin_sim.robot.world import PhysicalWorld

DECISION_KEYS = (
    "t",
    "gesture_count",
    "true_gesture",
    "state",
    "action",
    "feedback",
    "proactive",
    "delivered",
    "legs_delivered",
    "handover",
    "step",
)


class ActsAtOnce:
    """Per tick: the script's next gesture when asked; the thumb in the action's first tick."""

    def __init__(self, participant: LiveParticipant, script: tuple) -> None:
        self.participant = participant
        self.by_step = {(s.intent.handover, s.step): s.intent for s in script}
        self.action = None  # the action the robot has decided on (a StepObserver's view)
        self.offered = []

    def decided(self, record: StepRecord) -> None:
        self.action = record.action

    def answered(self, record: StepRecord) -> None:
        self.action = None

    def received(self, record: StepRecord) -> None:
        pass

    def __call__(self, _: object) -> None:
        person = self.participant
        wanted = self.by_step[person.instruction]
        if person.phase == "waiting_for_gesture" and not person.gesture_pending:
            self.offered.append(wanted.gesture)
            person.offer(Gesturing(wanted.gesture, wanted.target))
        elif person.judging and person.thumb is None and self.action is not None:
            person.offer(Feedback.OK if self.action is wanted.action else Feedback.NOT_OK)
        person.poll()


@pytest.mark.slow
def test_live_decisions_equal_the_studys_with_the_proactive_robot() -> None:
    seed = 1  # the proactive robot anticipates in this one table (test_proactive_episode)
    spec = parse_run_spec(system="proactive", rate=1.0, seed=seed, params={"tables": 1})
    scenario = spec.scenario
    study = assemble(spec)
    expected = [
        r.to_dict()
        for r in steps(
            study.learner, study.person, study.detector, SymbolicWorld(), **study.options
        )
    ]
    assert any(e["proactive"] for e in expected)
    world = PhysicalWorld()
    body = PhysicalBody(world, seed=seed)
    parts = assemble(spec, body=body)
    script = parts.person.script
    types = [scenario.type_named(s.handover_type) for s in script if s.step == 0]

    def anticipates(previous, hand) -> bool:  # what the session gives the participant
        return parts.learner.anticipate(previous, hand) is not None

    participant = LiveParticipant(body, types, scenario.legs_per_table, 1.0, anticipates)
    brain = ActsAtOnce(participant, script)
    world.sim.add_observer(brain)
    got = []
    for record in steps(
        parts.learner, participant, parts.detector, world, observer=brain, **parts.options
    ):
        participant.legs_delivered = record.legs_delivered
        got.append(record.to_dict())
    assert [{k: e[k] for k in DECISION_KEYS} for e in got] == [
        {k: e[k] for k in DECISION_KEYS} for e in expected
    ]
    # every gesture the robot read was made by the participant, and none was made in vain:
    # the robot went first exactly when it anticipated, and each let-stand one saved a gesture
    anticipated_ok = sum(e["proactive"] and e["feedback"] != "not ok" for e in got)
    assert anticipated_ok >= 1
    assert len(brain.offered) == got[-1]["gesture_count"] == len(script) - anticipated_ok
    assert participant.legs_delivered == 4
