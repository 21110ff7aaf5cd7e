"""The PIL agent (pil.learner): choice order, step memory, correction, determinism."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

from pil import Action, AssociationTable, Decision, Feedback, Gesture, Hand, Learner, State
from pil.errors import InvalidChoiceError, RobinPilError
from pil.types import ACTIONS, GESTURES

S = State("pointing", "close", "occupied")

# Table I's three handover types as (gesture performed, action the person wants).
HANDOVERS = (
    (("pointing", "object"), ("grasp", "close"), ("give me", "human"), ("release", "open")),
    (("pointing", "object"), ("grasp", "close"), ("pointing", "location"), ("release", "open")),
    (
        ("pointing", "object"),
        ("pointing", "object"),
        ("grasp", "close"),
        ("give me", "human"),
        ("pointing", "location"),
        ("release", "open"),
    ),
)


def simulate(learner: Learner, seed: int, legs: int, detection: float) -> list[Decision | str]:
    """A small scripted person: returns every decision and every feedback, in order."""
    rng = random.Random(seed)
    log: list[Decision | str] = []
    previous, hand = Action.OPEN, Hand.FREE
    for leg in range(legs):
        for gesture_name, wanted_name in HANDOVERS[leg % len(HANDOVERS)]:
            gesture, wanted = Gesture(gesture_name), Action(wanted_name)
            done = False
            while not done:
                assert len(log) < 10_000
                if rng.random() < detection:
                    detected: Gesture | None = gesture
                else:
                    detected = rng.choice([None, *(g for g in GESTURES if g is not gesture)])
                decision = learner.decide(detected, previous, hand)
                log.append(decision)
                if decision.action is None:
                    continue  # the person repeats the gesture
                action = decision.action
                while action is not wanted:
                    assert len(log) < 10_000, "the learner never offers the wanted action"
                    learner.feedback(decision.state, action, False)
                    log.append(f"not ok {action}")
                    action = learner.choose(decision.state)
                    log.append(f"next {action} {learner.last_reason}")
                learner.feedback(decision.state, action, Feedback.NONE)
                previous = action
                hand = {Action.CLOSE: Hand.OCCUPIED, Action.OPEN: Hand.FREE}.get(action, hand)
                done = True
    return log


def test_same_seed_same_decisions() -> None:
    runs = [simulate(Learner(seed), seed=11, legs=12, detection=0.6) for seed in (4, 4)]
    assert runs[0] == runs[1]
    others = {
        tuple(map(str, simulate(Learner(s), seed=11, legs=12, detection=0.6))) for s in range(5)
    }
    assert len(others) > 1, "the seed has no effect on exploration"


def test_learns_table_one_types_and_then_only_exploits() -> None:
    learner = Learner(0)
    simulate(learner, seed=1, legs=6, detection=1.0)
    expected = {
        ("pointing", "open", "free"): "object",
        ("grasp", "object", "free"): "close",
        ("give me", "close", "occupied"): "human",
        ("release", "human", "occupied"): "open",
        ("pointing", "close", "occupied"): "location",
        ("release", "location", "occupied"): "open",
        ("pointing", "object", "free"): "object",
        ("pointing", "human", "occupied"): "location",
    }
    for parts, action in expected.items():
        assert learner.table.best(State(*parts)) is Action(action), parts
    log = simulate(learner, seed=2, legs=3, detection=1.0)
    assert all(isinstance(d, Decision) and d.exploited for d in log)
    assert len(log) == sum(len(h) for h in HANDOVERS)


@pytest.mark.parametrize("seed", range(8))
def test_no_repeat_within_a_step_until_all_five_were_tried(seed: int) -> None:
    learner = Learner(seed, exploration="untried-first")
    learner.feedback(S, Action.LOCATION, True)  # something learnt, so the order is mixed
    learner.feedback(S, Action.OBJECT, False)  # and something rejected in an earlier step
    learner.feedback(State("pointing", "open", "free"), Action.OBJECT, True)  # ends the step
    for _ in range(3):  # three rounds of five
        tried = []
        for _ in range(len(ACTIONS)):
            action = learner.choose(S)
            assert action not in tried
            tried.append(action)
            learner.feedback(S, action, False)
        assert set(tried) == set(ACTIONS)
        assert learner.tried_in_step(S) == set(ACTIONS)


@pytest.mark.parametrize("seed", range(8))
def test_order_learnt_then_untried_then_rejected(seed: int) -> None:
    table = AssociationTable()
    for _ in range(3):
        table.update(S, Action.LOCATION, True)
    table.update(S, Action.HUMAN, True)
    table.update(S, Action.CLOSE, False)  # rejected in an earlier step
    learner = Learner(seed, table=table, exploration="untried-first")
    order, exploited = [], []
    for _ in range(len(ACTIONS)):
        action = learner.choose(S)
        order.append(action)
        exploited.append(learner.last_exploited)
        learner.feedback(S, action, False)
    assert order[:2] == [Action.LOCATION, Action.HUMAN]  # highest P first
    assert set(order[2:4]) == {Action.OBJECT, Action.OPEN}  # never tried here
    assert order[4] is Action.CLOSE  # rejected in an earlier step: last
    assert exploited == [True, False, False, False, False]


def test_learnt_ties_are_broken_at_random() -> None:
    table = AssociationTable()
    table.update(S, Action.LOCATION, True)
    table.update(S, Action.HUMAN, True)
    firsts = set()
    for seed in range(30):
        learner = Learner(seed, table=table.copy())
        first = learner.choose(S)
        assert first in (Action.LOCATION, Action.HUMAN)
        assert not learner.last_exploited and learner.last_reason == "tie among learnt"
        firsts.add(first)
        learner.feedback(S, first, False)
        assert learner.choose(S) in {Action.LOCATION, Action.HUMAN} - {first}
    assert firsts == {Action.LOCATION, Action.HUMAN}


def test_ok_ends_the_step_and_counts_the_transition() -> None:
    learner = Learner(0)
    start = State("pointing", "open", "free")
    learner.feedback(start, Action.CLOSE, False)
    assert learner.tried_in_step(start) == {Action.CLOSE}
    learner.feedback(start, Action.OBJECT, Feedback.OK)
    assert learner.tried_in_step(start) == frozenset()
    assert learner.last_ok_state == start
    nxt = State("grasp", "object", "free")
    learner.feedback(nxt, "close", Feedback.NONE)
    assert learner.table.transitions(None) == {start: 1}
    assert learner.table.transitions(start) == {nxt: 1}
    learner.restart()
    assert learner.last_ok_state is None


def test_empty_table_explores_even_an_invalid_state() -> None:
    learner = Learner(0)
    decision = learner.decide("grasp", "open", "free")  # invalid, but T is empty (line 5)
    assert decision.action is not None and decision.state == State("grasp", "open", "free")
    assert decision.reason.startswith("explore")
    discarded = learner.decide(None, "open", "free")
    assert discarded.action is None and discarded.state is None


def test_invalid_state_correction_on_and_off() -> None:
    table = AssociationTable()
    give = State("give me", "close", "occupied")
    release = State("release", "human", "occupied")
    pointing = State("pointing", "human", "occupied")
    table.update(release, Action.OPEN, True)
    table.update(pointing, Action.LOCATION, True)
    table.record_transition(give, release, 3)
    table.record_transition(give, pointing, 1)
    table.record_transition(give, State("grasp", "human", "occupied"), 9)  # invalid: ignored
    learner = Learner(0, table=table)
    learner.feedback(give, Action.HUMAN, True)  # the last OK state is now <give me, close, occ>
    decision = learner.decide(Gesture.GRASP, Action.HUMAN, Hand.OCCUPIED)
    assert (decision.state, decision.action, decision.corrected) == (release, Action.OPEN, True)
    # a discarded gesture is corrected the same way
    assert learner.decide(None, "human", "occupied").state == release
    # no valid follower with the same previous action and hand: no action
    assert learner.correct(State("grasp", "location", "occupied"), give) is None
    # correction off: the person has to repeat
    manual = Learner(0, table=learner.table.copy(), correction=False)
    refused = manual.decide("grasp", "human", "occupied")
    assert refused == Decision(
        None,
        State("grasp", "human", "occupied"),
        None,
        False,
        False,
        "invalid: grasp while occupied; no correction (manual repetition)",
    )
    assert manual.decide(None, "human", "occupied").action is None


def test_correction_ties_are_random_but_seeded() -> None:
    table = AssociationTable()
    give = State("give me", "close", "occupied")
    table.update(give, Action.HUMAN, True)
    for follower in (State("release", "human", "occupied"), State("pointing", "human", "occupied")):
        table.record_transition(give, follower, 2)
    picks = [
        Learner(seed, table=table).correct(State("grasp", "human", "occupied"), give)
        for seed in range(20)
    ]
    assert set(picks) == {
        State("release", "human", "occupied"),
        State("pointing", "human", "occupied"),
    }
    again = [
        Learner(seed, table=table).correct(State("grasp", "human", "occupied"), give)
        for seed in range(20)
    ]
    assert picks == again


def test_saved_and_loaded_learner_decides_identically(tmp_path: Path) -> None:
    trained = Learner(5)
    simulate(trained, seed=3, legs=8, detection=0.5)
    path = trained.save(tmp_path / "trained.json")
    in_memory = Learner(9, table=trained.table.copy())
    from_file = Learner.load(path, seed=9)
    assert from_file.table == in_memory.table
    first = simulate(in_memory, seed=21, legs=8, detection=0.5)
    second = simulate(from_file, seed=21, legs=8, detection=0.5)
    assert first == second
    assert any(isinstance(d, Decision) and d.corrected for d in first)


def test_names_are_parsed_and_bad_ones_raise() -> None:
    learner = Learner(0)
    learner.feedback(State("pointing", "open", "free"), "object", "ok")
    decision = learner.decide("Pointing", "OPEN", "free")
    assert decision.action is Action.OBJECT and decision.exploited
    assert learner.decide("give_me", "close", "occupied").state == State(
        "give me", "close", "occupied"
    )
    with pytest.raises(InvalidChoiceError, match="valid choices: 'pointing', 'give me'"):
        learner.decide("wave", "open", "free")
    with pytest.raises(InvalidChoiceError, match="unknown hand"):
        learner.decide(None, "open", "full")
    with pytest.raises(RobinPilError, match="unknown action 'fly'"):
        learner.feedback(State("pointing", "open", "free"), "fly", True)
    with pytest.raises(RobinPilError, match="unknown feedback"):
        learner.feedback(State("pointing", "open", "free"), "object", "maybe")


@pytest.mark.parametrize("table", ["x", {"counts": {}}, 3])
def test_learner_refuses_a_table_that_is_not_one(table: object) -> None:
    with pytest.raises(RobinPilError, match=r"table must be an AssociationTable.*load_table"):
        Learner(table=table)  # type: ignore[arg-type]


@pytest.mark.parametrize("seed", range(8))
def test_next_best_ranks_learnt_then_draws_all_but_the_action_just_rejected(seed: int) -> None:
    table = AssociationTable()
    for _ in range(3):
        table.update(S, Action.LOCATION, True)
    table.update(S, Action.HUMAN, True)
    learner = Learner(seed, table=table)  # next-best is the default
    assert learner.exploration == "next-best"
    order = []
    for _ in range(40):
        action = learner.choose(S)
        if len(order) >= 2:
            assert action is not order[-1], "repeated the action just rejected"
        order.append(action)
        learner.feedback(S, action, False)
    assert order[:2] == [Action.LOCATION, Action.HUMAN]
    assert set(order[2:]) == set(ACTIONS), "earlier rejections must be explored again"


@pytest.mark.parametrize("rule", ["avoid-last", "with-replacement"])
def test_random_rules_exploit_once_then_draw(rule: str) -> None:
    table = AssociationTable()
    table.update(S, Action.LOCATION, True)
    repeats = 0
    for seed in range(10):
        learner = Learner(seed, table=table.copy(), exploration=rule)
        assert learner.choose(S) is Action.LOCATION and learner.last_exploited
        learner.feedback(S, Action.LOCATION, False)
        previous, seen = Action.LOCATION, {Action.LOCATION}
        for _ in range(20):
            action = learner.choose(S)
            if learner.last_exploited:  # only once all five were tried: the step starts over
                assert seen == set(ACTIONS) and action is Action.LOCATION
                seen = set()
            seen.add(action)
            repeats += action is previous
            learner.feedback(S, action, False)
            previous = action
    if rule == "avoid-last":
        assert repeats == 0
    else:
        assert repeats > 0, "with replacement must sometimes draw the rejected action again"


@pytest.mark.parametrize("rule", ["next-best", "avoid-last", "with-replacement", "untried-first"])
def test_every_rule_is_seeded(rule: str) -> None:
    runs = [simulate(Learner(4, exploration=rule), seed=11, legs=8, detection=0.6) for _ in (0, 1)]
    assert runs[0] == runs[1]


def test_unknown_exploration_rule_lists_the_valid_ones() -> None:
    """Checked once, where it enters (the registry); the Learner takes it as given."""
    from pil.task.spec import parse_run_spec

    with pytest.raises(RobinPilError, match="'next-best', 'avoid-last', 'with-replacement'"):
        parse_run_spec(params={"exploration": "greedy"})
