"""The proactive robot: the anticipation rule on hand-built tables, the loop, the study."""

from __future__ import annotations

import pytest
from learner_rows import learner_row

from pil.anticipation import anticipate, can_anticipate
from pil.errors import RobinPilError
from pil.experiments.study import StudyConfig, csv_text, run_study, summary_text
from pil.learner import Learner
from pil.table import AssociationTable, state_id
from pil.task.counting import RunStats
from pil.task.detector import Detector
from pil.task.person import ScriptedPerson
from pil.task.runner import steps
from pil.task.scenario import load_scenario
from pil.task.systems import PAPER_SYSTEMS, SYSTEM_SPECS
from pil.task.world import Outcome, SymbolicWorld, Target, Watcher
from pil.types import Action, Feedback, Gesture, Hand, State
from pil.validity import ALL_STATES, is_valid

POINT = State(Gesture.POINTING, Action.OPEN, Hand.FREE)  # approved: object
GRASP = State(Gesture.GRASP, Action.OBJECT, Hand.FREE)  # approved: close
POINT_AGAIN = State(Gesture.POINTING, Action.OBJECT, Hand.FREE)  # approved: object


def _context(previous: Action, hand: Hand) -> frozenset[int]:
    return frozenset(
        i
        for i, s in enumerate(ALL_STATES)
        if is_valid(s) and (s.previous_action, s.hand) == (previous, hand)
    )


def _table(grasps: int, points: int) -> AssociationTable:
    """After POINT: GRASP followed ``grasps`` times, POINT_AGAIN ``points`` times."""
    table = AssociationTable()
    table.add(POINT, Action.OBJECT, 5)
    table.add(GRASP, Action.CLOSE, 4)
    table.add(POINT_AGAIN, Action.OBJECT, 2)
    table.record_transition(POINT, GRASP, grasps)
    table.record_transition(POINT, POINT_AGAIN, points)
    return table


AFTER_OBJECT = _context(Action.OBJECT, Hand.FREE)


def test_a_likely_next_state_is_anticipated_with_its_best_action() -> None:
    guess = anticipate(_table(4, 0), state_id(POINT), AFTER_OBJECT, 0.8, 3)
    assert guess is not None
    assert guess.state == GRASP and guess.action is Action.CLOSE
    assert guess.share == 1.0 and guess.evidence == 4


def test_the_share_must_reach_the_threshold() -> None:
    at = anticipate(_table(4, 1), state_id(POINT), AFTER_OBJECT, 0.8, 3)  # 4/5 = 0.8
    assert at is not None and at.share == pytest.approx(0.8) and at.evidence == 5
    assert anticipate(_table(4, 2), state_id(POINT), AFTER_OBJECT, 0.8, 3) is None  # 4/6
    assert anticipate(_table(4, 2), state_id(POINT), AFTER_OBJECT, 0.6, 3) is not None


def test_too_little_evidence_or_a_tie_anticipates_nothing() -> None:
    assert anticipate(_table(2, 0), state_id(POINT), AFTER_OBJECT, 0.8, 3) is None
    assert anticipate(_table(2, 0), state_id(POINT), AFTER_OBJECT, 0.8, 2) is not None
    assert anticipate(_table(3, 3), state_id(POINT), AFTER_OBJECT, 0.5, 3) is None  # tie
    tied = _table(4, 0)
    tied.add(GRASP, Action.HUMAN, 4)  # eq. 4 has no unique best action
    assert anticipate(tied, state_id(POINT), AFTER_OBJECT, 0.8, 3) is None


def test_only_the_states_possible_now_count() -> None:
    """Transitions to a state of another context neither count nor get anticipated."""
    table = _table(4, 0)
    other = State(Gesture.RELEASE, Action.LOCATION, Hand.OCCUPIED)
    table.add(other, Action.OPEN, 3)
    table.record_transition(POINT, other, 50)
    guess = anticipate(table, state_id(POINT), AFTER_OBJECT, 0.8, 3)
    assert guess is not None and guess.state == GRASP and guess.evidence == 4
    after_location = _context(Action.LOCATION, Hand.OCCUPIED)
    guess = anticipate(table, state_id(POINT), after_location, 0.8, 3)
    assert guess is not None and guess.state == other and guess.action is Action.OPEN


def test_actions_that_need_the_person_are_never_anticipated() -> None:
    assert not can_anticipate(GRASP, Action.OBJECT)
    assert not can_anticipate(GRASP, Action.LOCATION)
    assert not can_anticipate(State(Gesture.GIVE_ME, Action.CLOSE, Hand.OCCUPIED), Action.HUMAN)
    release_on_palm = State(Gesture.RELEASE, Action.HUMAN, Hand.OCCUPIED)
    release_on_spot = State(Gesture.RELEASE, Action.LOCATION, Hand.OCCUPIED)
    assert not can_anticipate(release_on_palm, Action.OPEN)
    assert can_anticipate(release_on_spot, Action.OPEN)
    assert can_anticipate(GRASP, Action.CLOSE)
    table = AssociationTable()  # the likely follower of POINT would be another pointing
    table.add(POINT_AGAIN, Action.OBJECT, 4)
    table.record_transition(POINT, POINT_AGAIN, 4)
    assert anticipate(table, state_id(POINT), AFTER_OBJECT, 0.8, 3) is None


def test_the_learner_anticipates_only_when_proactive() -> None:
    for proactive, expected in ((False, None), (True, Action.CLOSE)):
        learner = Learner(0, table=_table(4, 0), proactive=proactive)
        learner.feedback(POINT, Action.OBJECT, True)  # POINT is the last approved state
        guess = learner.anticipate(Action.OBJECT, Hand.FREE)
        assert (None if guess is None else guess.action) is expected


@pytest.mark.parametrize(
    ("threshold", "count"), [(0.0, 3), (1.5, 3), (True, 3), ("x", 3), (0.8, 0), (0.8, 2.5)]
)
def test_bad_threshold_or_count_is_one_clear_error(threshold: object, count: object) -> None:
    """Checked once, where they enter (the registry); the Learner takes them as given."""
    from pil.task.spec import parse_run_spec

    given = {"proactive": True, "proactive_threshold": threshold, "proactive_min_count": count}
    with pytest.raises(RobinPilError, match="proactive_"):
        parse_run_spec(params=given)


class SeeingWorld(SymbolicWorld):
    """A symbolic world that remembers each action's target and the watcher's intent."""

    def __init__(self) -> None:
        super().__init__()
        self.seen: list[tuple[Action, Target | None, object]] = []

    def execute(
        self, action: Action, target: Target | None, watcher: Watcher | None = None
    ) -> Outcome:
        self.seen.append((action, target, getattr(watcher, "intent", None)))
        return super().execute(action, target, watcher)


def _proactive_run(rate: float, seed: int):  # type: ignore[no-untyped-def]
    scenario = load_scenario()
    person = ScriptedPerson.for_types(scenario, scenario.draw_types(40, seed), seed)
    detector = Detector(rate, seed + 1, deck_size=len(person.script))
    learner = Learner(seed + 2, proactive=True)
    world = SeeingWorld()
    return person, learner, world, list(steps(learner, person, detector, world))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_an_anticipation_let_happen_saves_exactly_its_gesture(seed: int) -> None:
    person, _learner, world, records = _proactive_run(1.0, seed)
    stats = RunStats.for_script(person.script)
    for record in records:
        stats.add(record)
    assert stats.anticipated >= stats.anticipated_ok > 0
    assert stats.gestures == stats.scripted_gestures - stats.anticipated_ok
    assert stats.legs == 40
    for before, record, after in zip(records, records[1:], records[2:], strict=False):
        if not record.proactive:
            continue
        assert record.gesture_count == before.gesture_count  # no gesture performed for it
        assert record.detected_gesture is None and record.exploited
        if record.feedback.approves:  # type: ignore[union-attr]
            assert (after.handover, after.step) != (record.handover, record.step)
        else:  # stopped: the person performs the instruction's gesture as usual
            assert record.interrupted
            assert (after.handover, after.step) == (record.handover, record.step)
            assert after.gesture_count == record.gesture_count + 1 and not after.proactive
    # the robot acts without a pointed target; the person watches with their next intent
    anticipated = [seen for seen, r in zip(world.seen, records, strict=True) if r.proactive]
    assert all(target is None for _a, target, _i in anticipated)
    assert [i.action for _a, _t, i in anticipated] == [  # type: ignore[union-attr]
        r.intended_action for r in records if r.proactive
    ]


def test_some_anticipations_are_stopped() -> None:
    records = [r for seed in (0, 1) for r in _proactive_run(1.0, seed)[3] if r.proactive]
    assert any(r.feedback is Feedback.NOT_OK and r.action is not r.intended_action for r in records)


def test_an_anticipation_updates_the_table_like_any_feedback() -> None:
    _person, learner, _world, records = _proactive_run(1.0, 0)
    approved = [r for r in records if r.feedback is not None and r.feedback.approves]
    for state in {r.state for r in approved}:
        counts = learner.table.counts(state)  # type: ignore[arg-type]
        for action in counts:
            assert counts[action] == sum(
                1 for r in approved if r.state == state and r.action is action
            )


def test_proactive_is_a_registered_study_system_with_the_flag_set() -> None:
    assert SYSTEM_SPECS["proactive"].params == {"proactive": True}
    assert "proactive" not in PAPER_SYSTEMS
    row = learner_row("proactive", 0.8, 3, tables=2)
    assert row["proactive"] is True and row["anticipated"] >= row["anticipated_ok"]
    assert learner_row("pil", 0.8, 3, tables=2)["anticipated"] == 0
    with pytest.raises(RobinPilError, match="proactive_threshold"):
        learner_row("proactive", 0.8, 3, tables=2, proactive_threshold=2)


def test_the_study_with_proactive_is_deterministic_and_leaves_the_other_rows_alone() -> None:
    both = StudyConfig(reps=3, systems=("pil", "proactive", *PAPER_SYSTEMS[1:]))
    rows = run_study(both)
    assert csv_text(rows) == csv_text(run_study(both))
    paper = run_study(StudyConfig(reps=3))
    assert csv_text(paper) == csv_text([r for r in rows if r["system"] != "proactive"])
    text = summary_text(rows, both)
    assert "## Proactive vs reactive PIL" in text
    section = text.split("## Proactive vs reactive PIL")[1]
    assert section.count("\n| 0.") == 3 and "\n| 1 |" in section  # one line per rate
    assert "## Proactive vs reactive PIL" not in summary_text(paper, StudyConfig(reps=3))


class GesturesFirst(ScriptedPerson):
    """A person who holds a proactive robot back (as a live participant whose watchdog
    stepped in): their gesture comes first."""

    def lets_robot_go_first(self) -> bool:
        return False


def test_a_person_who_gestures_first_is_never_overtaken() -> None:
    """Found by the live soak: a watchdog that held the robot back let the participant make
    the gesture, and the loop anticipated anyway and dropped it (13 actions on one gesture).
    The loop asks the person first: the gesture is performed, every instruction gets one."""
    scenario = load_scenario()
    person = GesturesFirst.for_types(scenario, scenario.draw_types(12, 0), 0)
    detector = Detector(1.0, 1, deck_size=len(person.script))
    learner = Learner(2, proactive=True)
    records = list(steps(learner, person, detector, SymbolicWorld()))
    assert not [r for r in records if r.proactive]
    assert records[-1].gesture_count == len(person.script)
    plain = ScriptedPerson.for_types(scenario, scenario.draw_types(12, 0), 0)
    again = Detector(1.0, 1, deck_size=len(plain.script))
    plainly = list(steps(Learner(2, proactive=True), plain, again, SymbolicWorld()))
    assert [r for r in plainly if r.proactive]  # the robot would have gone first
