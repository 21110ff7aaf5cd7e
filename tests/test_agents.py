"""The agent protocol and the baselines (pil.agents): same loop, person, detector, counting."""

from __future__ import annotations

from pathlib import Path

import pytest
from learner_rows import learner_row

from pil import Action, Learner, State, load_table
from pil.agents import AGENTS, Agent, BanditAgent, TamerAgent
from pil.errors import InvalidChoiceError, RobinPilError
from pil.task.spec import parse_run_spec
from pil.task.systems import PAPER_SYSTEMS, SYSTEM_SPECS, SYSTEMS
from pil.types import ACTIONS

S = State("pointing", "open", "free")


@pytest.mark.parametrize("name", sorted(AGENTS))
def test_every_agent_implements_the_protocol(name: str) -> None:
    agent = AGENTS[name](3, None, parse_run_spec().learner)  # the registry's defaults
    assert isinstance(agent, Agent)
    decision = agent.decide("pointing", "open", "free")
    assert decision.state == S and decision.action in ACTIONS
    assert isinstance(agent.last_exploited, bool) and agent.last_reason


@pytest.mark.parametrize("agent", [BanditAgent(0, epsilon=0.0), TamerAgent(0)])
def test_baselines_find_the_wanted_action_and_then_exploit_it(agent: Agent) -> None:
    for _ in range(3):  # three steps asking for object in the same state
        tried = []
        action = agent.choose(S)
        while action is not Action.OBJECT:
            assert action not in tried, "a refused action came back within the step"
            tried.append(action)
            agent.feedback(S, action, False)
            action = agent.choose(S)
        agent.feedback(S, action, True)
    assert agent.choose(S) is Action.OBJECT and agent.last_exploited
    assert agent.table.count(S, Action.OBJECT) == 3


def test_bandit_explores_with_probability_epsilon() -> None:
    agent = BanditAgent(1, epsilon=0.5)
    agent.feedback(S, Action.OBJECT, True)
    picks = [agent.choose(S) for _ in range(400)]
    share = sum(a is not Action.OBJECT for a in picks) / len(picks)
    assert abs(share - 0.5 * 4 / 5) < 0.08  # random half the time, 4 of 5 random picks differ


def test_tamer_generalises_over_shared_features() -> None:
    agent = TamerAgent(0)
    # release -> open approved after human; the same gesture after location was never seen
    for _ in range(3):
        agent.feedback(State("release", "human", "occupied"), Action.OPEN, True)
    assert agent.choose(State("release", "location", "occupied")) is Action.OPEN
    bandit = BanditAgent(0, epsilon=0.0)
    for _ in range(3):
        bandit.feedback(State("release", "human", "occupied"), Action.OPEN, True)
    assert not bandit.last_exploited  # nothing known there yet (a fresh state)


def test_baselines_neither_correct_nor_act_on_a_discarded_gesture(tmp_path: Path) -> None:
    for agent in (BanditAgent(0), TamerAgent(0)):
        assert agent.decide(None, "open", "free").action is None
        invalid = agent.decide("grasp", "open", "free")  # acted on as it is
        assert invalid.state == State("grasp", "open", "free") and not invalid.corrected
        assert agent.correct(invalid.state, None) is None
        agent.feedback(S, Action.OBJECT, True)
        assert load_table(agent.save(tmp_path / f"{type(agent).__name__}.json")) == agent.table


def test_bad_agent_settings_are_refused() -> None:
    """epsilon and step_size are checked once, where they enter (the registry); the agents
    take them as given."""
    from pil.task.spec import parse_run_spec

    with pytest.raises(RobinPilError, match="epsilon"):
        parse_run_spec(system="bandit", params={"epsilon": 1.5})
    with pytest.raises(RobinPilError, match="step_size"):
        parse_run_spec(system="tamer", params={"step_size": -0.1})
    with pytest.raises(RobinPilError, match="table must be an AssociationTable"):
        TamerAgent(table="x")  # type: ignore[arg-type]


@pytest.mark.parametrize("system", ["bandit", "tamer"])
def test_baseline_systems_run_in_the_study_loop_deterministically(system: str) -> None:
    first = learner_row(system, 0.6, seed=4, tables=2)
    assert first == learner_row(system, 0.6, seed=4, tables=2)
    assert first["legs"] == 8 and first["train_actions"] == 0
    assert first["corrections"] == 0
    pil = learner_row("pil", 0.6, seed=4, tables=2)
    assert first["scripted_gestures"] == pil["scripted_gestures"]  # the same script


def test_registry_is_one_source() -> None:
    assert tuple(SYSTEMS) == tuple(SYSTEM_SPECS)
    assert set(PAPER_SYSTEMS) < set(SYSTEMS) and {"bandit", "tamer"} <= set(SYSTEMS)
    assert SYSTEMS["tamer"] == SYSTEM_SPECS["tamer"].description
    with pytest.raises(InvalidChoiceError, match="'bandit', 'tamer'"):
        learner_row("clairvoyant", 0.6, seed=0)  # "proactive" is a system now
    assert isinstance(Learner(), Agent)
