"""Replay Table I of the paper (23 steps, three handover types) through the Learner API.

The table's exploratory choices were random, so the recorded actions are fed back with
``feedback``; the checks are the facts the paper states about steps 3, 10, 12, 17 and 21.
"""

from __future__ import annotations

import pytest

from pil import Action, Learner, State
from pil.validity import is_valid

# t, detected gesture, previous action, hand, action, OK?
TABLE_ONE = [
    (1, "pointing", "open", "free", "close", False),
    (2, "pointing", "open", "free", "open", False),
    (3, "pointing", "open", "free", "object", True),
    (4, "grasp", "object", "free", "open", False),
    (5, "grasp", "object", "free", "close", True),
    (6, "give me", "close", "occupied", "location", False),
    (7, "give me", "close", "occupied", "human", True),
    (8, "release", "human", "occupied", "object", False),
    (9, "release", "human", "occupied", "open", True),
    (10, "pointing", "open", "free", "object", True),
    (11, "grasp", "object", "free", "close", True),
    (12, "pointing", "close", "occupied", "close", False),
    (13, "pointing", "close", "occupied", "human", False),
    (14, "pointing", "close", "occupied", "location", True),
    (15, "release", "location", "occupied", "open", True),
    (16, "pointing", "open", "free", "object", True),
    (17, "pointing", "object", "free", "open", False),
    (18, "pointing", "object", "free", "object", True),
    (19, "grasp", "object", "free", "close", True),
    (20, "give me", "close", "occupied", "human", True),
    (21, "pointing", "human", "occupied", "object", False),
    (22, "pointing", "human", "occupied", "location", True),
    (23, "release", "location", "occupied", "open", True),
]


def _replay(learner: Learner, until: int) -> None:
    """Feed rows 1 .. until-1 (each through ``decide`` first, like the real loop)."""
    for t, gesture, previous, hand, action, ok in TABLE_ONE:
        if t >= until:
            return
        decision = learner.decide(gesture, previous, hand)
        assert decision.state == State(gesture, previous, hand)
        assert decision.action is not None
        learner.feedback(decision.state, action, ok)


def test_rows_follow_each_other() -> None:
    """Sanity of the transcription: a_t is the last OK'd action, h_t follows close/open."""
    previous, hand = "open", "free"
    for _, gesture, prev, h, action, ok in TABLE_ONE:
        assert (prev, h) == (previous, hand)
        assert is_valid(State(gesture, prev, h))
        if ok:
            previous = action
            hand = {"close": "occupied", "open": "free"}.get(action, hand)
    assert sum(ok for *_, ok in TABLE_ONE) == 14  # 14 instruction gestures, 3 legs


@pytest.mark.parametrize("seed", range(5))
def test_after_step_three_object_is_certain(seed: int) -> None:
    learner = Learner(seed)
    _replay(learner, until=4)
    state = State("pointing", "open", "free")
    assert learner.table.probabilities(state)[Action.OBJECT] == 1.0
    assert learner.table.best(state) is Action.OBJECT


@pytest.mark.parametrize("seed", range(5))
def test_step_ten_exploits_object(seed: int) -> None:
    learner = Learner(seed)
    _replay(learner, until=10)
    decision = learner.decide("pointing", "open", "free")
    assert decision.action is Action.OBJECT
    assert decision.exploited and not decision.corrected
    assert decision.reason == "unique best"
    assert learner.choose(State("pointing", "open", "free")) is Action.OBJECT


@pytest.mark.parametrize("seed", range(10))
def test_step_twelve_next_choice_is_not_close(seed: int) -> None:
    state = State("pointing", "close", "occupied")
    learner = Learner(seed)  # next-best: never the action just rejected
    _replay(learner, until=13)  # t = 12 fed: close got not-OK
    assert learner.choose(state) is not Action.CLOSE
    learner = Learner(seed, exploration="untried-first")
    _replay(learner, until=13)
    for _ in range(4):  # untried-first: the rest of the step never returns to close
        action = learner.choose(state)
        assert action is not Action.CLOSE
        learner.feedback(state, action, False)


@pytest.mark.parametrize("seed", range(5))
def test_step_seventeen_is_unseen_and_uniform(seed: int) -> None:
    learner = Learner(seed)
    _replay(learner, until=17)
    state = State("pointing", "object", "free")
    assert learner.table.probabilities(state) == dict.fromkeys(Action, 0.2)
    assert learner.table.best(state) is None
    decision = learner.decide("pointing", "object", "free")
    assert not decision.exploited
    assert decision.reason == "explore at random"


@pytest.mark.parametrize("seed", range(5))
def test_step_twenty_one_corrects_grasp_to_release(seed: int) -> None:
    learner = Learner(seed)
    _replay(learner, until=21)
    assert learner.last_ok_state == State("give me", "close", "occupied")
    misread = State("grasp", "human", "occupied")
    assert not is_valid(misread)
    expected = State("release", "human", "occupied")
    assert learner.correct(misread, learner.last_ok_state) == expected
    decision = learner.decide("grasp", "human", "occupied")
    assert decision.corrected
    assert decision.detected_state == misread
    assert decision.state == expected
    assert decision.action is Action.OPEN
    assert decision.reason.startswith("corrected grasp->release")
    # Without correction the person has to repeat the gesture.
    manual = Learner(seed, table=learner.table.copy(), correction=False)
    refused = manual.decide("grasp", "human", "occupied")
    assert refused.action is None and refused.state is None
    assert "manual repetition" in refused.reason


def test_full_replay_counts() -> None:
    learner = Learner(0)
    _replay(learner, until=24)
    table = learner.table
    assert table.total() == 14
    assert table.count(State("pointing", "open", "free"), "object") == 3
    assert table.count(State("grasp", "object", "free"), "close") == 3
    assert table.count(State("give me", "close", "occupied"), "human") == 2
    assert table.count(State("release", "location", "occupied"), "open") == 2
    assert table.rejected(State("pointing", "close", "occupied")) == {Action.CLOSE, Action.HUMAN}
    assert table.transitions(State("give me", "close", "occupied")) == {
        State("release", "human", "occupied"): 1,
        State("pointing", "human", "occupied"): 1,
    }
    assert learner.last_ok_state == State("release", "location", "occupied")
