"""MuJoCo island sleeping in the scene: resting legs sleep, a held or carried leg never does.

Measured on real physics: after 2 s at home every leg's tree is asleep (and its contacts leave
``data.contact``); Robin's arms and the person's palm never sleep; grasping a leg wakes it and
the hand state reads it from the contacts; the same actions give bit-identical states.
"""

from __future__ import annotations

import numpy as np
import pytest

from pil.task.world import Target
from pil.types import Action, Hand
from robin_sim.model import names
from robin_sim.model.scene import build_model
from robin_sim.robot.world import PhysicalWorld

pytestmark = pytest.mark.slow


def leg_awake(world: PhysicalWorld, leg: int) -> bool:
    return bool(world.data.body_awake[world.model.body(names.leg_body(leg)).id])


def test_resting_legs_sleep_and_the_arms_and_palm_never_do() -> None:
    world = PhysicalWorld(sleep=True)
    world.sim.run(2.0)
    assert not any(leg_awake(world, k) for k in range(4))
    assert world.data.ncon == 0  # contacts of sleeping legs are not reported
    model = world.model
    bodies = (names.HUMAN_PALM_BODY, names.hand_body("l"), names.hand_body("r"))
    trees = {model.body_treeid[model.body(name).id] for name in bodies}
    assert all(world.data.tree_asleep[t] < 0 for t in trees)  # negative: awake
    assert build_model().opt.enableflags == 0  # off by default (see build_spec)
    assert build_model(sleep=True).opt.enableflags != 0


def _grasp(world: PhysicalWorld) -> None:
    for action, target in ((Action.OBJECT, Target("leg", 1)), (Action.CLOSE, None)):
        outcome = world.execute(action, target)  # nobody watching: each runs to its end
        assert outcome.succeeded, outcome.detail


def test_a_grasped_leg_wakes_and_is_read_from_its_contacts() -> None:
    world = PhysicalWorld(sleep=True)
    world.sim.run(2.0)
    _grasp(world)
    world.sim.run(1.0)  # held still: the arm stays awake, so does the leg in its hand
    assert leg_awake(world, 1) and world.hand() is Hand.OCCUPIED
    assert not leg_awake(world, 3)  # a leg nobody touched sleeps on


def test_sleeping_is_deterministic() -> None:
    one, two = PhysicalWorld(sleep=True), PhysicalWorld(sleep=True)
    for world in (one, two):
        world.sim.run(2.0)
        _grasp(world)
    assert np.array_equal(one.data.qpos, two.data.qpos)
    assert np.array_equal(one.data.qvel, two.data.qvel)
