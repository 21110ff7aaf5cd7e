"""A gesture the robot cannot read is no dead end: after repeated repeats it proposes an action."""

from __future__ import annotations

import pytest

from pil.learner import Learner
from pil.task.asking import context_states, guesses
from pil.task.detector import Detector
from pil.task.person import ScriptedPerson
from pil.task.runner import ASK_AFTER_REPEATS, steps
from pil.task.scenario import load_scenario
from pil.task.world import SymbolicWorld
from pil.types import Action, Feedback, Gesture, Hand


class BlindTo:
    """Reads every gesture right but ``blind``, which it always discards (a dim room)."""

    rate = 1.0

    def __init__(self, blind: Gesture) -> None:
        self.blind = blind
        self.discarded = 0

    def detect(self, gesture: Gesture) -> Gesture | None:
        if gesture is self.blind:
            self.discarded += 1
            return None
        return gesture

    def read_feedback(self, feedback: Feedback) -> Feedback:
        return feedback


@pytest.mark.parametrize("blind", [Gesture.GRASP, Gesture.GIVE_ME, Gesture.RELEASE])
@pytest.mark.parametrize("exploration", ["next-best", "avoid-last"])
def test_a_gesture_never_read_is_answered_by_proposals(blind: Gesture, exploration: str) -> None:
    scenario = load_scenario()
    types = scenario.draw_types(8, 1)
    person = ScriptedPerson.for_types(scenario, types, 1)
    detector = BlindTo(blind)
    records = list(steps(Learner(3, exploration=exploration), person, detector, SymbolicWorld()))
    assert records[-1].legs_delivered == 8
    assert person.next_step(Hand.FREE) is None
    in_a_row = 0
    proposals = 0
    for record in records:
        in_a_row = in_a_row + 1 if record.action is None else 0
        assert in_a_row < ASK_AFTER_REPEATS  # never more repeats in a row than that
        if record.action is not None and "cannot read the gesture" in record.reason:
            proposals += 1
            assert record.detected_gesture is None and record.true_gesture is blind
    assert detector.discarded > 0 and proposals > 0


def test_the_guesses_put_the_correction_first() -> None:
    learner = Learner(0)
    for gesture, action in (("pointing", "object"), ("grasp", "close")):
        decision = learner.decide(gesture, "open" if gesture == "pointing" else "object", "free")
        learner.feedback(decision.state, action, True)
    learner.feedback(learner.decide("give me", "close", "occupied").state, "human", True)
    learner.feedback(learner.decide("release", "human", "occupied").state, "open", True)
    learner.feedback(learner.decide("pointing", "open", "free").state, "object", True)
    # after <pointing, open, free> came <grasp, object, free>: the correction's choice
    ranked = guesses(learner, Action.OBJECT, Hand.FREE)
    assert ranked[0].gesture is Gesture.GRASP
    assert set(ranked) == set(context_states(Action.OBJECT, Hand.FREE))


def test_the_paper_study_never_asks() -> None:
    """At the study's lowest rate ten repeats in a row are too rare to change a run."""
    scenario = load_scenario()
    for seed in range(5):
        types = scenario.draw_types(40, seed)
        person = ScriptedPerson.for_types(scenario, types, seed)
        detector = Detector(0.4, seed + 1, deck_size=len(person.script))
        records = list(steps(Learner(seed + 2), person, detector, SymbolicWorld()))
        assert not any("cannot read the gesture" in r.reason for r in records)
