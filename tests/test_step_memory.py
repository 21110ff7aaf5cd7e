"""The within-step memory (pil.step_memory): one option that acts alike on every learner."""

from __future__ import annotations

from dataclasses import replace

import pytest
from learner_rows import learner_row

from pil import Action, State
from pil.agents import AGENTS, BanditAgent, TamerAgent
from pil.agents.tamer import STEP_SIZE, STEP_SIZE_RANGE
from pil.errors import InvalidChoiceError
from pil.learner import Learner
from pil.step_memory import STEP_MEMORY, step_memory_on
from pil.task.params import PARAMS, ParamError
from pil.task.spec import parse_run_spec
from pil.types import ACTIONS
from robin_sim.cli.main import main

S = State("pointing", "open", "free")
# Each learner's settings for the script: greedy (no epsilon), a slow TAMER step so that
# one refusal leaves a learnt action on top.
SETTINGS = {"pil": {}, "bandit": {"epsilon": 0.0}, "tamer": {"step_size": 0.25}}


def _refusals_in_one_step(learner: str, memory: str, seed: int) -> list[Action]:
    """Learn OBJECT in S (ten approvals), then refuse the first six choices of a new step."""
    settings = parse_run_spec(params={**SETTINGS[learner], "step_memory": memory}).learner
    agent = AGENTS[learner](seed, None, settings)
    for _ in range(10):
        agent.feedback(S, Action.OBJECT, True)
    chosen = []
    for _ in range(6):
        action = agent.choose(S)
        chosen.append(action)
        agent.feedback(S, action, False)
    return chosen


@pytest.mark.parametrize("learner", sorted(SETTINGS))
def test_with_the_memory_no_learner_repeats_a_refusal_until_all_five_were_refused(
    learner: str,
) -> None:
    for seed in range(10):
        chosen = _refusals_in_one_step(learner, "on", seed)
        assert chosen[0] is Action.OBJECT  # the learnt action first
        assert set(chosen[:5]) == set(ACTIONS)  # five refusals: each action once
        assert chosen[5] is Action.OBJECT  # then the memory starts over: the learnt one again


@pytest.mark.parametrize("learner", sorted(SETTINGS))
def test_without_it_every_learner_repeats_a_refused_action_within_the_step(learner: str) -> None:
    repeats = 0
    for seed in range(10):
        chosen = _refusals_in_one_step(learner, "off", seed)
        assert chosen[0] is Action.OBJECT
        repeats += len(set(chosen[:5])) < 5  # an action refused in this step came back
    if learner == "pil":  # next-best's random draw avoids only the action just refused
        assert repeats >= 5
    else:  # greedy: the learnt action is still the best after one refusal
        assert repeats == 10


def test_the_default_is_each_learners_own_setting() -> None:
    assert PARAMS["step_memory"].default == "per-learner"
    assert PARAMS["step_memory"].choices == tuple(STEP_MEMORY)
    default = parse_run_spec().learner
    assert not AGENTS["pil"](0, None, default).step_memory and not Learner().step_memory
    assert AGENTS["bandit"](0, None, default).step_memory
    assert AGENTS["tamer"](0, None, default).step_memory
    assert AGENTS["pil"](0, None, replace(default, step_memory="on")).step_memory
    assert not AGENTS["tamer"](0, None, replace(default, step_memory="off")).step_memory
    with pytest.raises(InvalidChoiceError, match="'per-learner', 'on', 'off'"):
        step_memory_on("sometimes", True)


def test_in_runs_the_memory_changes_next_best_but_not_untried_first() -> None:
    def actions(**params: object) -> int:
        return learner_row("pil", 0.6, seed=2, tables=3, **params)["total_actions"]

    assert actions(exploration="untried-first", step_memory="on") == actions(
        exploration="untried-first", step_memory="off"
    )
    assert actions(step_memory="per-learner") == actions(step_memory="off")
    assert actions(step_memory="on") < actions(step_memory="off")  # fewer blind repeats
    assert actions(exploration="with-replacement", step_memory="on") == actions(
        exploration="avoid-last", step_memory="on"
    )  # both draw among the actions not refused in this step
    tamer = learner_row("tamer", 0.6, seed=2, tables=3)
    assert tamer == learner_row("tamer", 0.6, seed=2, tables=3, step_memory="on") | {
        "step_memory": "per-learner"
    }


def test_step_size_has_one_range_the_registry_and_tamer_agree() -> None:
    spec = PARAMS["step_size"]
    assert (spec.low, spec.high) == STEP_SIZE_RANGE and spec.default == STEP_SIZE
    assert TamerAgent().step_size == STEP_SIZE
    with pytest.raises(ParamError, match=r"parameter 'step_size' must be a number in \[0, 1\]"):
        spec.parse(1.5)
    with pytest.raises(ParamError, match=r"'step_size' must be a number in \[0, 1\]"):
        learner_row("tamer", 0.6, seed=0, step_size=1.5)  # refused before the run
    assert TamerAgent(step_size=1.0).step_size == 1.0  # the top of the range is allowed
    for name, agent in (("epsilon", BanditAgent()), ("epsilon_decay", BanditAgent())):
        assert PARAMS[name].default == getattr(agent, name)


def test_a_bad_step_size_on_the_command_line_exits_2(tmp_path, capsys) -> None:
    out = tmp_path / "sweep"
    code = main(
        [
            "sweep",
            "--systems",
            "tamer",
            "--param",
            "step_size=0.5,1.5",
            "--out",
            str(out),
            "--quiet",
        ]
    )
    assert code == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and "step_size must be a number in [0, 1], got '1.5'" in error
    assert not out.exists()
