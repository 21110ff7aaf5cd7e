"""The dm_env interface (pil.env): specs, episodes, the study's counting, the docs example."""

from __future__ import annotations

import random
import re
from pathlib import Path

import dm_env
import numpy as np
import pytest
from absl.testing import absltest
from dm_env import test_utils
from learner_rows import learner_row

from pil import Learner
from pil.env import DISCARDED, AssemblyEnv, observation_state
from pil.errors import RobinPilError
from pil.task.parts import derive_seeds
from pil.task.world import SymbolicWorld
from pil.types import ACTIONS, Action, Hand

README = Path(__file__).resolve().parents[1] / "docs" / "study.md"  # the env example


class TestConformance(test_utils.EnvironmentTestMixin, absltest.TestCase):
    """dm_env's own conformance checks (specs respected, reset/step/last, FIRST after LAST)."""

    def make_object_under_test(self) -> AssemblyEnv:
        return AssemblyEnv(rate=0.6, seed=1, tables=1)

    def make_action_sequence(self):  # type: ignore[no-untyped-def]
        rng = random.Random(0)  # random actions: about 5 per instruction, so episodes end
        return [np.int64(rng.randrange(len(ACTIONS))) for _ in range(400)]


def test_one_hot_observations_match_their_specs() -> None:
    env = AssemblyEnv(rate=0.6, seed=1, tables=1, one_hot=True)
    step = env.reset()
    for key, spec in env.observation_spec().items():
        spec.validate(step.observation[key])
        assert step.observation[key].sum() == 1.0


def test_pil_through_the_environment_decides_like_the_study_loop() -> None:
    env = AssemblyEnv(rate=1.0, seed=3, tables=2)
    learner = Learner(derive_seeds(3)["test_learner"])
    step = env.reset()
    decision = None
    while not step.last():
        state = env.state()
        assert state == observation_state(step.observation)
        if decision is None:
            decision = learner.decide(state.gesture, state.previous_action, state.hand)
            action = decision.action
        else:
            action = learner.choose(decision.state)
        step = env.step(ACTIONS.index(action))
        ok = step.reward > 0
        learner.feedback(decision.state, action, ok)
        if ok:
            decision = None
    row = learner_row("pil", 1.0, seed=3, tables=2)
    assert step.step_type is dm_env.StepType.LAST and step.discount == 0.0
    assert (env.stats.gestures, env.stats.actions) == (row["gestures"], row["actions"])
    assert env.stats.rejected == row["rejected"] and env.stats.approved == row["gestures"]


def test_discarded_readings_are_repeated_or_shown() -> None:
    repeated = AssemblyEnv(rate=0.0, seed=0, tables=1, discard=1.0)
    with pytest.raises(RobinPilError, match="discarded 1000 times in a row"):
        repeated.reset()  # every reading discarded and repeated: a clear error, no hang
    half = AssemblyEnv(rate=0.5, seed=0, tables=1, discard=1.0)
    step = half.reset()
    while not step.last():
        assert int(step.observation["gesture"]) != DISCARDED
        step = half.step(ACTIONS.index(half._item.intent.action))
    assert half.stats.gestures > half.stats.approved  # discarded readings were repeated
    shown = AssemblyEnv(rate=0.0, seed=0, tables=1, discard=1.0, repeat_discarded=False)
    step = shown.reset()
    assert int(step.observation["gesture"]) == DISCARDED and shown.state() is None


def test_any_world_can_be_plugged_in() -> None:
    built: list[SymbolicWorld] = []

    class CountingWorld(SymbolicWorld):
        def __init__(self) -> None:
            super().__init__()
            self.executed = 0
            built.append(self)

        def execute(self, action, intent, wanted):  # type: ignore[no-untyped-def]
            self.executed += 1
            return super().execute(action, intent, wanted)

    env = AssemblyEnv(rate=1.0, seed=0, tables=1, world=CountingWorld)
    rng = random.Random(0)
    for _ in range(2):
        step = env.reset()
        while not step.last():
            step = env.step(rng.randrange(len(ACTIONS)))
    assert len(built) == 2 and built[-1].executed == env.stats.actions


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"rate": 1.5}, "detection rate"),
        ({"seed": -2}, "seed must be"),
        ({"world": SymbolicWorld()}, "world must be a factory"),
        ({"colour": 1}, "parameter"),
    ],
)
def test_bad_settings_are_refused(kwargs: dict, message: str) -> None:
    with pytest.raises(RobinPilError, match=message):
        AssemblyEnv(**kwargs)


def test_bad_actions_are_refused() -> None:
    env = AssemblyEnv(tables=1)
    env.reset()
    with pytest.raises(RobinPilError, match="out of range; valid: 0 open"):
        env.step(5)
    with pytest.raises(RobinPilError, match="must be an index"):
        env.step("open")  # type: ignore[arg-type]


def test_readme_example_trains_a_bandit() -> None:
    text = README.read_text()
    block = re.search(r"<!-- env-example -->\n```python\n(.*?)```", text, re.S)
    assert block is not None, "the environment example in docs/study.md is missing"
    namespace: dict = {}
    exec(compile(block.group(1), "docs example", "exec"), namespace)
    costs = namespace["costs"]
    random_policy = []
    env = AssemblyEnv(rate=0.8, seed=0)
    rng = random.Random(0)
    for _ in range(len(costs)):
        step = env.reset()
        while not step.last():
            step = env.step(rng.randrange(len(ACTIONS)))
        random_policy.append(env.stats.actions)
    assert np.mean(costs) < 0.5 * np.mean(random_policy), (costs, random_policy)
    assert min(costs) >= 220  # every one of the 220 instructions needs an approved action


@pytest.mark.slow
def test_the_physical_world_plugs_in_behind_the_same_interface() -> None:
    """One handover in MuJoCo through the environment: the hand state is read from physics."""
    from robin_sim.person.body import PhysicalBody
    from robin_sim.robot.world import PhysicalWorld

    env = AssemblyEnv(
        rate=1.0, seed=0, scenario="one_handover", world=PhysicalWorld, body=PhysicalBody
    )
    step = env.reset()
    assert step.observation["gesture"] == 0 and step.observation["hand"] == 0  # pointing, free
    step = env.step(ACTIONS.index(Action.CLOSE))  # not what the person means: refused, undone
    assert step.reward == -1.0 and step.observation["hand"] == 0
    hands, rewards = [], []
    for wanted in (Action.OBJECT, Action.CLOSE, Action.HUMAN, Action.OPEN):
        step = env.step(ACTIONS.index(wanted))
        rewards.append(step.reward)
        hands.append(int(step.observation["hand"]))
    assert rewards == [1.0, 1.0, 1.0, 1.0] and step.last()
    assert hands[1] == 1, "after an approved close the physics must read the leg as held"
    assert env.world is not None and env.world.hand() is Hand.FREE  # let go on the palm
    assert (env.stats.actions, env.stats.rejected, env.stats.approved) == (5, 1, 4)
