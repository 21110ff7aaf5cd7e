"""The step loop: counts, deliveries, hand state from the world, corrections, determinism."""

from __future__ import annotations

import json

import pytest

from pil.learner import Learner
from pil.task.detector import Detector
from pil.task.person import ScriptedPerson
from pil.task.runner import MAX_ACTIONS_PER_GESTURE, RunnerError, StepRecord, run, steps
from pil.task.scenario import SCENARIOS_DIR, Scenario, load_scenario
from pil.task.watching import InstantWatcher
from pil.task.world import Intent, Outcome, SymbolicWorld, Target, Watcher
from pil.types import Action, Feedback, Gesture, Hand


@pytest.fixture(scope="module")
def scenario() -> Scenario:
    return load_scenario()


def parts(scenario: Scenario, rate: float, seed: int, handovers: int = 20, **options: object):  # type: ignore[no-untyped-def]
    types = scenario.draw_types(handovers, seed)
    person = ScriptedPerson.for_types(scenario, types, seed)
    detector = Detector(rate, seed + 1, deck_size=len(person.script), **options)  # type: ignore[arg-type]
    return Learner(seed + 2), person, detector


class WatchedWorld(SymbolicWorld):
    """A symbolic world that remembers the hand state at every execute call."""

    def __init__(self) -> None:
        super().__init__()
        self.hands: list[Hand] = []
        self.tables: list[int] = []

    def execute(
        self, action: Action, target: Target | None, watcher: Watcher | None = None
    ) -> Outcome:
        self.hands.append(self.hand())
        return super().execute(action, target, watcher)

    def start_table(self, table: int) -> None:
        self.tables.append(table)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_full_rate_needs_exactly_the_scripted_gestures(scenario: Scenario, seed: int) -> None:
    learner, person, detector = parts(scenario, 1.0, seed)
    world = WatchedWorld()
    records = list(steps(learner, person, detector, world))
    assert records[-1].gesture_count == len(person.script) == 110
    assert all(r.action is not None for r in records)  # no repeat requests
    assert records[-1].legs_delivered == 20
    assert sum(r.delivered for r in records) == 20
    assert world.tables == [0, 1, 2, 3, 4]
    # the state's hand is the world's hand at the moment of acting
    assert [r.state.hand for r in records] == world.hands  # type: ignore[union-attr]
    approved = [r for r in records if r.feedback is Feedback.OK]
    assert len(approved) == 110
    assert [r.action for r in approved] == [r.intended_action for r in approved]


def test_table_one_passes_through_the_papers_states() -> None:
    scenario = load_scenario(SCENARIOS_DIR / "table_one.yaml")
    types = scenario.draw_types(3, 0)
    person = ScriptedPerson.for_types(scenario, types)
    records = list(steps(Learner(7), person, Detector(1.0, 0, deck_size=14), SymbolicWorld()))
    approved = [r.state_key for r in records if r.feedback is Feedback.OK]
    assert approved[:4] == [
        "pointing|open|free",
        "grasp|object|free",
        "give me|close|occupied",
        "release|human|occupied",
    ]
    assert approved[11:13] == ["give me|close|occupied", "pointing|human|occupied"]
    assert records[-1].legs_delivered == 3 and records[-1].gesture_count == 14


def test_rejected_action_leaves_previous_action_unchanged(scenario: Scenario) -> None:
    learner, person, detector = parts(scenario, 1.0, 3)
    records = list(steps(learner, person, detector, SymbolicWorld()))
    previous = Action.OPEN
    for record in records:
        assert record.state is not None and record.state.previous_action is previous
        if record.feedback is not Feedback.NOT_OK:
            previous = record.action  # type: ignore[assignment]


def test_lower_rate_corrects_and_still_delivers_every_leg(scenario: Scenario) -> None:
    learner, person, detector = parts(scenario, 0.6, 4, handovers=40)
    stats = run(learner, person, detector, SymbolicWorld())
    assert stats.legs == 40 == stats.handovers
    assert stats.corrections > 0
    assert stats.misdetections > 0
    assert stats.gestures == stats.scripted_gestures + stats.repeats > 220
    assert stats.actions == 220 + stats.rejected  # one approval per scripted gesture


def test_same_seed_same_records(scenario: Scenario) -> None:
    first = list(steps(*parts(scenario, 0.6, 9), SymbolicWorld()))
    second = list(steps(*parts(scenario, 0.6, 9), SymbolicWorld()))
    other = list(steps(*parts(scenario, 0.6, 10), SymbolicWorld()))
    assert first == second
    assert first != other


def test_repeat_requests_and_json_records(scenario: Scenario) -> None:
    records = list(
        steps(*parts(scenario, 0.4, 2, discard=1.0), SymbolicWorld(), repeat_discarded=True)
    )
    repeats = [r for r in records if r.is_repeat]
    assert repeats and all(r.detected_gesture is None and r.feedback is None for r in repeats)
    line = json.dumps(records[0].to_dict())
    assert json.loads(line)["true_gesture"] == records[0].true_gesture.value


def test_manual_repetition_acts_only_on_correct_readings(scenario: Scenario) -> None:
    learner, person, detector = parts(scenario, 0.5, 5)
    records = list(steps(learner, person, detector, SymbolicWorld(), manual=True))
    acted = [r for r in records if not r.is_repeat]
    assert all(r.detected_gesture is r.true_gesture for r in acted)
    assert all(r.corrected_gesture is None for r in acted)
    misread = len(records) - len(acted)
    assert records[-1].gesture_count == 110 + misread
    assert abs(misread - 110) <= 12  # at 50 % about as many misses as scripted gestures


class FailingWorld(SymbolicWorld):
    """Every close that the person lets run fails physically (the grasp slips)."""

    def execute(
        self, action: Action, target: Target | None, watcher: Watcher | None = None
    ) -> Outcome:
        stopped = watcher is not None and watcher.stop_now(action)
        if action is Action.CLOSE and not stopped:
            return Outcome(False, "the leg slipped", undone=True)
        return super().execute(action, target, watcher)


def test_failed_action_gets_not_ok_and_the_guard_stops_the_loop(scenario: Scenario) -> None:
    learner, person, detector = parts(scenario, 1.0, 6)
    records: list[StepRecord] = []
    with pytest.raises(
        RunnerError, match=f"no approved action after {MAX_ACTIONS_PER_GESTURE} actions"
    ):
        for record in steps(learner, person, detector, FailingWorld()):
            records.append(record)
    closes = [r for r in records if r.action is Action.CLOSE and r.intended_action is Action.CLOSE]
    assert closes and all(r.feedback is Feedback.NOT_OK and not r.succeeded for r in closes)
    assert all(r.state.hand is Hand.FREE for r in records)  # type: ignore[union-attr]


def test_a_gesture_never_read_right_stops_with_a_clear_error(scenario: Scenario) -> None:
    learner, person, detector = parts(scenario, 0.0, 1)
    with pytest.raises(RunnerError, match="performed 1000 times"):
        run(learner, person, detector, SymbolicWorld(), manual=True)


def test_the_observer_sees_each_decision_before_the_world_acts(scenario: Scenario) -> None:
    seen: list[StepRecord] = []
    answers: list[StepRecord] = []
    world = WatchedWorld()

    class Observer:
        def decided(self, record: StepRecord) -> None:
            assert len(world.hands) == len(seen)  # the world has not executed it yet
            seen.append(record)

        def answered(self, record: StepRecord) -> None:
            assert len(world.hands) == len(seen)  # right after the world acted
            answers.append(record)

        def received(self, record: StepRecord) -> None:
            assert len(world.hands) == len(seen)  # before the next action
            got.append(record)

    got: list[StepRecord] = []
    records = list(steps(*parts(scenario, 0.6, 11), world, observer=Observer()))
    acted = [r for r in records if not r.is_repeat]
    assert len(seen) == len(acted) == len(answers)
    assert got == acted  # each complete record, as yielded
    assert [a.feedback for a in answers] == [r.feedback for r in acted]
    assert all(s.feedback is None and s.succeeded is None for s in seen)
    answer = {
        "feedback": None,
        "succeeded": None,
        "delivered": False,
        "legs_delivered": 0,
        "interrupted": False,
        "detail": "",
        "feedback_read": None,
    }
    assert [s._replace(**answer) for s in seen] == [r._replace(**answer) for r in acted]
    assert acted[0].target == Target("leg", 0) or acted[0].target == Target("leg", 1)
    assert json.loads(json.dumps(acted[0].to_dict()))["target"]["kind"] == "leg"


class RecordingBody:
    """A person's body that logs what it is asked to do, in order."""

    def __init__(self, events: list[str]) -> None:
        self.events = events

    def start_table(self, table: int) -> None:
        self.events.append(f"table {table}")

    def perform(self, gesture: Gesture, target: Target | None) -> None:
        self.events.append(f"perform {gesture.value}")

    def watch(self, intent: Intent, reaction: float) -> Watcher:
        self.events.append("watch")
        return InstantWatcher(intent)

    def show_feedback(self, feedback: Feedback) -> None:
        self.events.append(f"thumb {feedback.value}")

    def after_feedback(self, feedback: Feedback) -> None:
        self.events.append("after")

    def recover(self, leg: int) -> bool:
        raise AssertionError("nothing is dropped in a symbolic world")

    def put_back_off_table(self, leg: int) -> bool:
        return False  # every leg stays where the robot reaches it in a symbolic world


def test_a_step_goes_gesture_robot_thumb_then_learner(scenario: Scenario) -> None:
    """The person performs, watches the robot act, shows the thumb, and only then does the
    learner receive the feedback; the person's after-thumb act (a carry to the bin) follows,
    then the record is yielded."""
    events: list[str] = []
    learner, person, detector = parts(scenario, 0.8, 3, handovers=4)
    person.body = RecordingBody(events)

    class LoggedWorld(SymbolicWorld):
        def execute(
            self, action: Action, target: Target | None, watcher: Watcher | None = None
        ) -> Outcome:
            events.append(f"robot {action.value}")
            return super().execute(action, target, watcher)

    class LoggedLearner(Learner):
        def feedback(self, state, action, ok):  # type: ignore[no-untyped-def]
            events.append("learner")
            super().feedback(state, action, ok)

    logged = LoggedLearner(learner.seed)
    records = []
    for record in steps(logged, person, detector, LoggedWorld()):
        events.append("record")
        records.append(record)
    assert events[0] == "table 0" and events[1].startswith("perform ")
    robot_at = [i for i, e in enumerate(events) if e.startswith("robot ")]
    assert len(robot_at) == sum(not r.is_repeat for r in records) > 0
    for i in robot_at:
        assert (
            events[i - 1] == "watch"
            and events[i + 1].startswith("thumb ")
            and events[i + 2 : i + 5] == ["learner", "after", "record"]
        )
    thumbs = [e.removeprefix("thumb ") for e in events if e.startswith("thumb ")]
    assert thumbs == [r.feedback.value for r in records if not r.is_repeat]  # type: ignore[union-attr]
    performed = [e for e in events if e.startswith("perform ")]
    assert len(performed) == records[-1].gesture_count  # every performance, repeats included
