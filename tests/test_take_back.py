"""The scripted person takes back a wrong move the robot let stand (issue 38, item 3).

The thumbs pass through the benchmark's teacher noise (:class:`pil.bench.noise.FeedbackChannel`:
a thumb down misread, missed or late lets a wrong move stand); a person with ``take_back``
says "that was wrong" at the loop's safe point, the loop calls
:meth:`pil.task.step_phases.StepPhases.take_back` and the next record's reason says so.
"""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pil.bench.noise import FeedbackChannel
from pil.bench.tracks import TableWorld
from pil.learner import Learner
from pil.table import state_id
from pil.task.detector import Detector
from pil.task.params import PARAMS, ParamError
from pil.task.person import ScriptedPerson
from pil.task.records import StepRecord
from pil.task.runner import steps
from pil.task.scenario import load_scenario
from pil.types import ACTIONS, Feedback

SCENARIO = load_scenario()


def noisy_run(
    seed: int,
    handovers: int = 12,
    *,
    thumbs: dict[str, float] | None = None,
    rate: float = 0.8,
    **person: Any,
) -> tuple[list[StepRecord], ScriptedPerson, Learner]:
    """A symbolic run whose thumbs pass through ``thumbs`` (the teacher's noise), the stop of a
    wrong action too (the benchmark's world)."""
    types = SCENARIO.draw_types(handovers, seed)
    scripted = ScriptedPerson.for_types(SCENARIO, types, seed, **person)
    detector = Detector(rate, seed + 1, deck_size=len(scripted.script))
    reader = FeedbackChannel(detector, {"misread": 0.3} if thumbs is None else thumbs, seed + 3)
    learner = Learner(seed + 2)
    world = TableWorld(lambda table: None, reader)  # a stop passes through the thumbs' noise
    records = list(steps(learner, scripted, reader, world))
    return records, scripted, learner


def stood_wrong(record: StepRecord) -> bool:
    """The robot took the action as approved although the person's thumb was down."""
    return (
        record.action is not None
        and record.feedback is Feedback.NOT_OK
        and record.feedback_read is not Feedback.NOT_OK
    )


def taken_back(records: list[StepRecord]) -> list[int]:
    """Indices of the records whose reason says an approval was taken back."""
    return [k for k, r in enumerate(records) if r.reason.startswith("taken back: ")]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_every_wrong_move_let_stand_is_taken_back_before_the_next_gesture(seed: int) -> None:
    records, person, learner = noisy_run(seed, take_back=1.0)
    wrong = [k for k, r in enumerate(records) if stood_wrong(r)]
    assert wrong, "the noise let no wrong move stand: the test tests nothing"
    said = taken_back(records)
    assert len(said) == len(wrong) == person.taken_back_count
    for k, note in zip(wrong, said, strict=True):
        # the next record is the next gesture's first: it says which action was taken back
        assert note == k + 1, (k, note)
        action = records[k].action
        assert action is not None
        assert records[note].reason.startswith(f"taken back: {action.value} taken back")
    assert records[-1].handover == 11  # the run goes on to its end
    # every approval left in the table is one the person meant: the wrong ones were withdrawn
    meant = {(r.state, r.action) for r in records if r.feedback is not Feedback.NOT_OK}
    for state in {r.state for r in records if r.state is not None}:
        row = learner.table.row(state_id(state))
        if row is None:
            continue
        for action, count in zip(ACTIONS, row, strict=True):
            assert count <= 0 or (state, action) in meant, (state, action, count)


def test_without_wrong_moves_a_willing_person_changes_nothing() -> None:
    """Right thumbs: nothing stands against the person, so nothing is taken back and the run is
    the one of a person who never takes back (the take-back's draws are its own)."""
    right: dict[str, float] = {}
    base, _, _ = noisy_run(4, thumbs=right)
    willing, person, _ = noisy_run(4, thumbs=right, take_back=1.0, take_back_delay=2)
    assert willing == base and person.taken_back_count == 0


def test_a_delayed_take_back_comes_after_the_actions_it_waits_for() -> None:
    records, person, _ = noisy_run(5, take_back=1.0, take_back_delay=2)
    wrong = [k for k, r in enumerate(records) if stood_wrong(r)]
    said = taken_back(records)
    assert said and person.taken_back_count == len(said)
    for note in said:
        before = [k for k in wrong if k < note]
        assert before, note  # said only after a wrong move stood
        actions = sum(1 for r in records[before[-1] + 1 : note] if r.action is not None)
        assert actions >= 2, (before[-1], note)  # it watched two more actions first


def test_the_parameters_are_checked_where_they_enter() -> None:
    assert PARAMS["take_back"].parse("0.25") == 0.25
    assert PARAMS["take_back_delay"].parse("3") == 3
    with pytest.raises(ParamError, match="take_back"):
        PARAMS["take_back"].parse("1.5")
    with pytest.raises(ParamError, match="take_back_delay"):
        PARAMS["take_back_delay"].parse("-1")


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    chance=st.floats(0.0, 1.0),
    delay=st.integers(0, 3),
    misread=st.floats(0.0, 0.3),
    late=st.floats(0.0, 0.3),
    missed=st.floats(0.0, 0.3),
)
def test_take_backs_at_any_rate_and_delay_never_stop_a_run(
    seed: int, chance: float, delay: int, misread: float, late: float, missed: float
) -> None:
    thumbs = {"misread": misread, "late": late, "missed": missed, "silence": 0.2}
    records, person, _ = noisy_run(seed, 4, thumbs=thumbs, take_back=chance, take_back_delay=delay)
    assert records[-1].handover == 3  # the script's end (a misread last OK delivers nothing)
    assert len(taken_back(records)) == person.taken_back_count
    assert [r.t for r in records if r.action is not None] == list(
        range(1, 1 + sum(r.action is not None for r in records))
    )
