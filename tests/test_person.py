"""The scripted person: script with targets, feedback rules, silence and patience."""

from __future__ import annotations

import pytest

from pil.errors import RobinPilError
from pil.task.person import ScriptedPerson
from pil.task.scenario import load_scenario
from pil.task.script import plan_script
from pil.task.world import Outcome, Target
from pil.types import Action, Feedback


@pytest.fixture(scope="module")
def scenario():  # type: ignore[no-untyped-def]
    return load_scenario()


def test_script_follows_the_types_with_legs_tables_and_targets(scenario) -> None:  # type: ignore[no-untyped-def]
    types = [scenario.type_named(n) for n in ("C", "F", "A", "G", "B")]
    script = plan_script(types, legs_per_table=4, spots=4)
    assert len(script) == 6 + 5 + 4 + 6 + 4
    c_steps = script[:6]
    assert [s.intent.target for s in c_steps] == [
        Target("leg", 1),
        Target("leg", 0),
        None,
        None,
        Target("spot", 0),
        None,
    ]
    f_steps = script[6:11]  # leg 1 of table 0: the spot is changed from 2 to 1
    assert [s.intent.target for s in f_steps if s.intent.action is Action.LOCATION] == [
        Target("spot", 2),
        Target("spot", 1),
    ]
    g_steps = script[15:21]  # leg 3, the last of the table: a double point stays on leg 3
    assert g_steps[0].intent.target == Target("leg", 3) == g_steps[1].intent.target
    # ... and a double location stays on spot 3: spots 0-2 may hold legs placed earlier
    g_spots = [s.intent.target for s in g_steps if s.intent.action is Action.LOCATION]
    assert g_spots == [Target("spot", 3), Target("spot", 3)]
    last = script[21]  # the fifth handover starts table 1
    assert last.first_of_table and last.intent.table == 1 and last.intent.handover == 4
    assert [s.first_of_table for s in script].count(True) == 2


def test_feedback_ok_only_for_the_wanted_action_that_worked(scenario) -> None:  # type: ignore[no-untyped-def]
    script = plan_script([scenario.type_named("A")], 4, 4)
    person = ScriptedPerson(script, seed=0)
    intent = script[0].intent  # pointing -> object
    assert person.judge(intent, Action.OBJECT, Outcome(True)) is Feedback.OK
    assert person.judge(intent, Action.CLOSE, Outcome(True)) is Feedback.NOT_OK
    assert person.judge(intent, Action.OBJECT, Outcome(False, "missed")) is Feedback.NOT_OK


def test_silent_ok_replaces_some_approvals_with_silence(scenario) -> None:  # type: ignore[no-untyped-def]
    script = plan_script([scenario.type_named("A")], 4, 4)
    person = ScriptedPerson(script, seed=1, silent_ok=0.3)
    replies = [person.judge(script[0].intent, Action.OBJECT, Outcome(True)) for _ in range(4000)]
    assert Feedback.NOT_OK not in replies
    assert abs(replies.count(Feedback.NONE) / 4000 - 0.3) < 0.03


def test_patience(scenario) -> None:  # type: ignore[no-untyped-def]
    script = plan_script([scenario.type_named("A")], 4, 4)
    assert not ScriptedPerson(script).loses_patience(10)
    patient = ScriptedPerson(script, patience=2)
    assert not patient.loses_patience(1) and patient.loses_patience(2)
    # checked once, where they enter (the registry); the person takes them as given
    from pil.task.spec import parse_run_spec

    with pytest.raises(RobinPilError, match="patience"):
        parse_run_spec(params={"patience": -1})
    with pytest.raises(RobinPilError, match="silent_ok"):
        parse_run_spec(params={"silent_ok": 1.5})
