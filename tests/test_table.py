"""The association table T (pil.table): eq. 2-4, merging, copying."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pil import AssociationTable, Feedback, State
from pil.errors import InvalidChoiceError
from pil.types import ACTIONS, Action
from pil.validity import ALL_STATES

S = State("pointing", "open", "free")
S2 = State("grasp", "object", "free")

states = st.sampled_from(ALL_STATES)
actions = st.sampled_from(ACTIONS)
feedbacks = st.sampled_from([True, False, Feedback.OK, Feedback.NOT_OK, Feedback.NONE])
updates = st.lists(st.tuples(states, actions, feedbacks), max_size=60)


def _build(sequence: list[tuple[State, Action, object]]) -> AssociationTable:
    table = AssociationTable()
    for state, action, ok in sequence:
        table.update(state, action, ok)  # type: ignore[arg-type]
    return table


def test_only_approval_increments() -> None:
    table = AssociationTable()
    assert table.is_empty()
    table.update(S, Action.CLOSE, False)
    table.update(S, Action.OPEN, Feedback.NOT_OK)
    assert table.is_empty()
    assert table.count(S, "close") == 0
    assert table.rejected(S) == {Action.CLOSE, Action.OPEN}
    table.update(S, "object", True)
    table.update(S, Action.OBJECT, Feedback.NONE)  # no feedback counts as OK
    table.update(S, Action.OBJECT, "ok")
    assert table.count(S, Action.OBJECT) == 3
    assert not table.is_empty()
    assert table.total() == 3
    assert table.states() == [S]
    assert table.probabilities(S)[Action.OBJECT] == 1.0
    assert table.best(S) is Action.OBJECT


def test_unseen_state_is_uniform_and_has_no_best() -> None:
    table = AssociationTable()
    table.update(S, Action.OBJECT, True)
    assert table.probabilities(S2) == dict.fromkeys(ACTIONS, 0.2)
    assert table.best(S2) is None
    table.update(S2, Action.OPEN, False)  # a rejection alone leaves the row at zero
    assert table.probabilities(S2) == dict.fromkeys(ACTIONS, 0.2)
    assert table.best(S2) is None


def test_tie_has_no_best_and_equal_probabilities() -> None:
    table = AssociationTable()
    table.update(S, Action.OBJECT, True)
    table.update(S, Action.CLOSE, True)
    assert table.best(S) is None
    probabilities = table.probabilities(S)
    assert probabilities[Action.OBJECT] == probabilities[Action.CLOSE] == 0.5
    table.update(S, Action.CLOSE, True)
    assert table.best(S) is Action.CLOSE
    assert table.probabilities(S)[Action.CLOSE] == pytest.approx(2 / 3)


def test_states_accept_text_keys_and_bad_names_raise() -> None:
    table = AssociationTable()
    table.update("give me|close|occupied", "human", True)  # type: ignore[arg-type]
    assert table.count(State("give me", "close", "occupied"), Action.HUMAN) == 1
    with pytest.raises(InvalidChoiceError, match="valid choices"):
        table.update(S, "jump", True)
    with pytest.raises(InvalidChoiceError, match="valid choices"):
        table.count(State("pointing", "open", "free"), "fly")
    with pytest.raises(TypeError):
        table.count(("pointing", "open", "free"), Action.OPEN)  # type: ignore[arg-type]


def test_merge_adds_counts_and_unites_rejections() -> None:
    a, b = AssociationTable(), AssociationTable()
    a.update(S, Action.OBJECT, True)
    a.update(S, Action.CLOSE, False)
    a.record_transition(None, S)
    b.update(S, Action.OBJECT, True)
    b.update(S, Action.OPEN, True)
    b.update(S2, Action.CLOSE, True)
    b.update(S, Action.HUMAN, False)
    b.record_transition(None, S)
    b.record_transition(S, S2)
    merged = a.merge(b)
    assert merged.count(S, Action.OBJECT) == 2
    assert merged.count(S, Action.OPEN) == 1
    assert merged.count(S2, Action.CLOSE) == 1
    assert merged.total() == a.total() + b.total() == 4
    assert merged.rejected(S) == {Action.CLOSE, Action.HUMAN}
    assert merged.transitions(None) == {S: 2}
    assert merged.transitions(S) == {S2: 1}
    assert merged.best(S) is Action.OBJECT
    # the inputs are untouched
    assert a.count(S, Action.OBJECT) == 1 and b.count(S, Action.OBJECT) == 1
    assert merged == b.merge(a)


def test_copy_is_independent_and_equal() -> None:
    table = AssociationTable()
    table.update(S, Action.OBJECT, True)
    table.record_transition(None, S)
    clone = table.copy()
    assert clone == table
    clone.update(S, Action.OBJECT, True)
    assert clone != table
    assert table.count(S, Action.OBJECT) == 1
    assert table != "not a table"


def test_counts_never_decrease_via_add_or_transitions() -> None:
    table = AssociationTable()
    with pytest.raises(ValueError, match="never decrease"):
        table.add(S, Action.OPEN, -1)
    with pytest.raises(ValueError, match="never decrease"):
        table.record_transition(S, S2, -2)


@settings(max_examples=200, deadline=None)
@given(updates, states)
def test_probabilities_sum_to_one(sequence, probe: State) -> None:
    table = _build(sequence)
    for state in [probe, *table.states()]:
        probabilities = table.probabilities(state)
        assert set(probabilities) == set(ACTIONS)
        assert abs(sum(probabilities.values()) - 1.0) <= 1e-12
        assert all(0.0 <= p <= 1.0 for p in probabilities.values())


@settings(max_examples=200, deadline=None)
@given(updates)
def test_counts_never_decrease(sequence) -> None:
    table = AssociationTable()
    previous = {(s, a): 0 for s in ALL_STATES for a in ACTIONS}
    for state, action, ok in sequence:
        table.update(state, action, ok)
        for (s, a), before in previous.items():
            now = table.count(s, a)
            assert now >= before
            expected = (
                before + 1
                if (s, a) == (state, action)
                and ok
                not in (
                    False,
                    Feedback.NOT_OK,
                )
                else before
            )
            assert now == expected
            previous[(s, a)] = now


@settings(max_examples=200, deadline=None)
@given(updates, states)
def test_unseen_is_uniform_and_best_is_none_iff_tie_or_unseen(sequence, probe: State) -> None:
    table = _build(sequence)
    for state in {probe, *table.states()}:
        counts = [table.count(state, a) for a in ACTIONS]
        unseen = sum(counts) == 0
        top = max(counts)
        tie = counts.count(top) > 1
        if unseen:
            assert table.probabilities(state) == dict.fromkeys(ACTIONS, 1 / len(ACTIONS))
            assert state not in table.states()
        assert (table.best(state) is None) == (unseen or tie)
        if not (unseen or tie):
            assert table.best(state) is ACTIONS[counts.index(top)]


@settings(max_examples=100, deadline=None)
@given(updates, updates)
def test_merge_equals_replaying_both(first, second) -> None:
    assert _build(first).merge(_build(second)) == _build(first + second)


def test_no_module_reaches_into_the_table_privately() -> None:
    """Only pil/table.py touches AssociationTable's private fields (issue 8)."""
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    private = re.compile(r"\._(counts|best|rejected|transitions|total|approve|follow|reject)\b")
    offenders = [
        f"{path.relative_to(root)}:{n}"
        for folder in ("pil", "robin_sim", "bench")
        for path in sorted((root / folder).rglob("*.py"))
        if path.name != "table.py" or path.parent.name != "pil"
        for n, line in enumerate(path.read_text().splitlines(), 1)
        if private.search(line)
    ]
    assert offenders == []


def test_id_level_interface_matches_the_named_one() -> None:
    from pil.table import START, action_index, state_id

    table = AssociationTable()
    s = State("pointing", "open", "free")
    sid, obj = state_id(s), action_index(Action.OBJECT)
    assert table.row(sid) is None and table.best_id(sid) == -1
    table.approve_id(sid, obj, 2)
    table.reject_id(sid, action_index(Action.CLOSE))
    table.follow_id(START, sid)
    assert table.row(sid) == tuple(table.counts(s).values())
    assert table.best_id(sid) == obj and table.best(s) is Action.OBJECT
    assert table.rejected_mask(sid) == 1 << action_index(Action.CLOSE)
    assert dict(table.followers(START)) == {sid: 1} and table.transitions(None) == {s: 1}
    with pytest.raises(TypeError):
        table.followers(START)[sid] = 5  # read-only view


@pytest.mark.parametrize("count", [1.5, True, 1.0, "2", -1])
def test_add_refuses_counts_that_are_not_whole_numbers(count: object) -> None:
    from pil.errors import RobinPilError

    table = AssociationTable()
    s = State("pointing", "open", "free")
    with pytest.raises(RobinPilError, match="must be a whole number >= 0"):
        table.add(s, Action.OBJECT, count)  # type: ignore[arg-type]
    with pytest.raises(RobinPilError, match="must be a whole number >= 0"):
        table.record_transition(None, s, count)  # type: ignore[arg-type]
    assert table.is_empty() and table.transitions(None) == {}
