"""Property: whatever the teacher does, the robot always has a way forward (issue 38, item 1).

An adversarial teacher drives the real step loop (:func:`pil.task.runner.steps`, the scripted
person, a symbolic world whose stops pass through the teacher, as the benchmark's
:class:`pil.bench.tracks.TableWorld`): every time the loop reads something, hypothesis chooses
what the robot gets, at that moment (a stateful strategy, ``st.data()``):

* a gesture: read right, discarded, or misread as any other gesture;
* a thumb down that stops a wrong action: seen, or not (the wrong action runs on);
* a thumb after an action: as given, flipped (a wrong approval or a right action refused),
  missed (silence), or late (silence now, landing on the next action instead).

Asserted for each PIL rule (``pil-paper``, ``pil-next-best``, ``pil-robust``):

* **the robot acts within** :data:`BOUND` **gestures**: at most ``ASK_AFTER_REPEATS - 1`` = 9
  repeat requests come in a row; the next gesture gets an action (after 10 requests in a row
  the loop proposes one, :mod:`pil.task.asking`, and the state it proposes from is grounded
  in the hand, :mod:`pil.task.grounding`, so a valid state always exists);
* **every run ends for a recorded reason**: the person's script is done (the goal), or the
  loop stops with a :class:`RunnerError` whose text says why, or the run reaches this test's
  cap; every record without an action says why the robot asked for a repeat.

The regression test is the dead end of issue 38: a wrong approval (an empty hand moved to the
person, let stand) and the person pointing at a leg again; the robot must act.
"""

from __future__ import annotations

from collections.abc import Callable

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from pil.bench.tracks import TableWorld
from pil.learner import Learner
from pil.robust import RobustLearner
from pil.table import action_index, state_id
from pil.task.person import ScriptedPerson
from pil.task.runner import ASK_AFTER_REPEATS, RunnerError, StepRecord, steps
from pil.task.scenario import load_scenario
from pil.task.script import plan_script
from pil.types import GESTURES, Action, Feedback, Gesture, Hand, State

BOUND = ASK_AFTER_REPEATS  # gestures in a row within which the robot acts
GESTURE_CAP = 150  # this test's cap on the person's gestures (a short script; see CAP_REASON)
CAP_REASON = f"this test's cap of {GESTURE_CAP} gestures"
LEARNERS: dict[str, Callable[[int], Learner]] = {
    "pil-paper": lambda seed: Learner(seed, exploration="avoid-last"),
    "pil-next-best": lambda seed: Learner(seed),
    "pil-robust": lambda seed: RobustLearner(seed),
}
# what the teacher does, drawn per reading; the first choice (0) is the right one, so a
# shrunk example is the one with the fewest adversarial moves
GESTURE_MOVES = ("right", "discarded", "misread")
THUMB_MOVES = ("as given", "flipped", "missed", "late")


class AdversarialTeacher:
    """A gesture and thumb reader whose every reading hypothesis chooses (module docstring)."""

    rate = 0.5

    def __init__(self, draw: Callable[[st.SearchStrategy[int]], int]) -> None:
        self._draw = draw
        self._late: Feedback | None = None

    def _pick(self, moves: tuple[str, ...], right_weight: int) -> str:
        """One move, the first ``right_weight`` times likelier than each other one."""
        index = self._draw(st.integers(0, right_weight + len(moves) - 2))
        return moves[max(0, index - right_weight + 1)]

    def detect(self, gesture: Gesture) -> Gesture | None:
        move = self._pick(GESTURE_MOVES, 4)
        if move == "discarded":
            return None
        if move == "misread":
            others = [g for g in GESTURES if g is not gesture]
            return others[self._draw(st.integers(0, len(others) - 1))]
        return gesture

    def read_stop(self) -> Feedback:
        """The stop of a wrong action: seen, or not (the action runs on)."""
        return Feedback.NONE if self._draw(st.integers(0, 3)) == 3 else Feedback.NOT_OK

    def read_feedback(self, feedback: Feedback) -> Feedback:
        move = self._pick(THUMB_MOVES, 4)
        given = feedback
        if move == "flipped" and feedback is not Feedback.NONE:
            given = Feedback.OK if feedback is Feedback.NOT_OK else Feedback.NOT_OK
        elif move == "missed":
            given = Feedback.NONE
        if self._late is not None:  # a late thumb lands on this action
            given, self._late = self._late, None
        elif move == "late" and given is not Feedback.NONE:
            self._late, given = given, Feedback.NONE
        return given


def drive(learner: Learner, handovers: int, teacher: AdversarialTeacher, seed: int) -> str:
    """Run the loop on a short script; check the records as they come; why the run ended."""
    scenario = load_scenario()
    script = plan_script(scenario.draw_types(handovers, seed), 4, scenario.spots)
    person = ScriptedPerson(script, seed)
    world = TableWorld(lambda table: None, teacher)
    in_a_row = 0
    record: StepRecord
    try:
        for record in steps(learner, person, teacher, world):
            assert record.reason, f"a record without a reason: {record}"
            in_a_row = in_a_row + 1 if record.action is None else 0
            assert in_a_row < BOUND, f"{in_a_row} repeat requests in a row: {record.reason}"
            if record.gesture_count >= GESTURE_CAP:
                return CAP_REASON
    except RunnerError as error:
        assert str(error)
        return str(error)
    assert person.next_step(world.hand()) is None  # the loop ended: the script is done
    return "goal"


@pytest.mark.parametrize("name", list(LEARNERS))
@settings(
    max_examples=40,  # per rule: about a second each on these machines
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(data=st.data(), seed=st.integers(0, 2**16), handovers=st.integers(1, 3))
def test_the_robot_always_acts_and_every_run_ends_for_a_reason(
    name: str, data: st.DataObject, seed: int, handovers: int
) -> None:
    teacher = AdversarialTeacher(data.draw)
    why = drive(LEARNERS[name](seed), handovers, teacher, seed)
    event("ended: " + ("goal" if why == "goal" else "cap" if why == CAP_REASON else "error"))
    assert why == "goal" or why == CAP_REASON or "actions for gesture" in why, why


class TeacherThatLetsOneWrongMoveStand:
    """Reads every gesture right; does not see the first stop (the wrong move runs on and is
    let stand: a wrong approval); every other thumb is seen as given."""

    rate = 1.0

    def __init__(self) -> None:
        self.missed_stops = 0

    def detect(self, gesture: Gesture) -> Gesture | None:
        return gesture

    def read_stop(self) -> Feedback:
        self.missed_stops += 1
        return Feedback.NONE if self.missed_stops == 1 else Feedback.NOT_OK

    def read_feedback(self, feedback: Feedback) -> Feedback:
        return Feedback.NONE if self.missed_stops == 1 and feedback is Feedback.NOT_OK else feedback


@pytest.mark.parametrize("name", list(LEARNERS))
def test_after_an_empty_hand_moved_to_the_person_is_let_stand_the_robot_acts(name: str) -> None:
    """Issue 38's dead end: the robot believes "human" (its empty hand at the person) was
    right for the pointing gesture, the move is let stand, and the person points at the leg
    again: before the grounding every gesture was invalid in <human, free> and the robot
    asked for it until the cap; now the robot acts on the next gesture."""
    learner = LEARNERS[name](0)
    pointing = State(Gesture.POINTING, Action.OPEN, Hand.FREE)
    learner.table.add(pointing, Action.HUMAN, 1)  # the wrong belief
    if isinstance(learner, RobustLearner):  # its evidence for it too
        learner.beliefs.add(state_id(pointing), action_index(Action.HUMAN), Feedback.OK)
    scenario = load_scenario()
    bring = next(t for t in scenario.types if t.name == "A")  # to the person's hand
    script = plan_script([bring], 4, scenario.spots)
    teacher = TeacherThatLetsOneWrongMoveStand()
    records = steps(
        learner, ScriptedPerson(script, 0), teacher, TableWorld(lambda t: None, teacher)
    )
    first = next(records)
    assert first.action is Action.HUMAN and first.feedback is Feedback.NOT_OK
    assert first.feedback_read is Feedback.NONE  # let stand: the robot takes it as approved
    after = next(records)  # the person points at the leg again
    assert after.true_gesture is Gesture.POINTING and after.action is not None, after.reason
    assert after.state is not None and after.state.previous_action is Action.OPEN
