"""The dm_env environment takes what its own specs make, and says what is wrong otherwise."""

from __future__ import annotations

import numpy as np
import pytest
from absl.testing import absltest
from dm_env import test_utils

from pil.env.assembly import AssemblyEnv
from pil.errors import RobinPilError
from pil.types import ACTIONS


class TestZeroDimActions(test_utils.EnvironmentTestMixin, absltest.TestCase):
    """The conformance mixin with its own default actions: 0-d arrays from the action spec."""

    def make_object_under_test(self) -> AssemblyEnv:
        return AssemblyEnv(rate=0.6, seed=1, tables=1)

    def make_action_sequence(self):  # type: ignore[no-untyped-def]
        rng = np.random.default_rng(0)
        spec = self.environment.action_spec()
        for _ in range(400):  # 0-d int64 arrays, each checked by the spec first
            action = np.array(rng.integers(len(ACTIONS)), dtype=spec.dtype)
            spec.validate(action)
            yield action


def test_a_0d_array_action_is_the_same_as_its_index() -> None:
    by_array, by_index = AssemblyEnv(seed=3, tables=1), AssemblyEnv(seed=3, tables=1)
    by_array.reset(), by_index.reset()
    for k in [2, 0, 4, 1, 3, 2, 2]:
        action = np.array(k)
        by_array.action_spec().validate(action)
        a, b = by_array.step(action), by_index.step(k)
        assert a.reward == b.reward and a.step_type == b.step_type
    with pytest.raises(RobinPilError, match="out of range"):
        by_array.step(np.array(7))
    with pytest.raises(RobinPilError, match="action must be an index"):
        by_array.step(np.array([1, 2]))


def test_state_before_reset_is_a_clear_error() -> None:
    env = AssemblyEnv(seed=0, tables=1)
    with pytest.raises(RobinPilError, match=r"call reset\(\) before state\(\)"):
        env.state()
    env.reset()
    assert env.state() is not None


def test_the_largest_seed_runs_many_episodes() -> None:
    env = AssemblyEnv(seed=2**63 - 1, tables=1)
    first = [env.reset().observation["gesture"] for _ in range(3)]
    assert len(first) == 3 and env.run_seed(1) == 0 and env.run_seed(0) == 2**63 - 1
    assert AssemblyEnv(seed=5).run_seed(2) == 7  # ordinary seeds: seed + episode, as before
    with pytest.raises(RobinPilError, match="from 0 to"):
        AssemblyEnv(seed=2**63)


def test_a_world_factory_returning_no_world_is_named() -> None:
    env = AssemblyEnv(world=lambda: None, seed=0, tables=1)
    with pytest.raises(TypeError, match=r"world\(\) must return a World .* got None"):
        env.reset()


@pytest.mark.parametrize("value", ["no", "yes", 1, 0, None])
def test_one_hot_takes_true_or_false_only(value: object) -> None:
    with pytest.raises(RobinPilError, match="one_hot must be True or False"):
        AssemblyEnv(one_hot=value, tables=1)  # type: ignore[arg-type]
    assert AssemblyEnv(one_hot=True, tables=1).one_hot is True
