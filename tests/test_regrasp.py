"""A dropped leg is grasped again from wherever physics left it on the table, and the close's
verdict is the hand sensor's (what the learner reads).

Physics makes every drop: no leg's state is written. A drop as in the main job: the robot opens
over the handover point with no palm there, the leg falls to the table, and the person stops the
hand while it rises, so the fingers close again on nothing (the hand is empty but closed). Then
"object" goes back to the leg, "close" must hold it, and a carry to a spot must keep it.
"""

from __future__ import annotations

import numpy as np
import pytest

from pil.task.world import Target
from pil.types import Action, Hand
from robin_sim.model.scene import SceneLayout
from robin_sim.robot.actions import OpenAction
from robin_sim.robot.world import PhysicalWorld

pytestmark = pytest.mark.slow


def _carry(world: PhysicalWorld, leg: int, action: Action, target: Target | None) -> None:
    for step, goal in ((Action.OBJECT, Target("leg", leg)), (Action.CLOSE, None), (action, target)):
        assert world.execute(step, goal).succeeded, step


def _drop_and_stop_while_rising(world: PhysicalWorld, leg: int) -> None:
    """Open with the leg over nothing; the person stops the hand as it rises: the fingers
    close again, empty (the main job's step 30)."""
    opening = OpenAction()
    began = world.time
    result = opening.run(world.ctx, stop=lambda: world.time - began > 1.6)
    world.run(1.0)
    assert result.interrupted and "while rising" in result.detail, result.detail
    assert world.held_leg() is None and world.hand() is Hand.FREE
    assert not np.allclose(world.sim.hand.command, world.sim.hand.targets.open)  # closed again


def _regrasp_and_carry(world: PhysicalWorld, leg: int) -> None:
    assert world.legs.graspable(leg), world.legs.position(leg)
    assert world.execute(Action.OBJECT, Target("leg", leg)).succeeded
    close = world.execute(Action.CLOSE, None)
    held = world.hand()
    assert close.succeeded == (held is Hand.OCCUPIED), (close.detail, held)  # one judgement
    assert close.succeeded and world.held_leg() == leg, close.detail
    carry = world.execute(Action.LOCATION, Target("spot", 1))
    assert carry.succeeded and world.held_leg() == leg, carry.detail


@pytest.mark.parametrize("leg", [2, 0])
def test_a_leg_dropped_below_the_handover_point_is_grasped_again(leg: int) -> None:
    world = PhysicalWorld()
    _carry(world, leg, Action.HUMAN, None)  # no palm out: the layout's handover point
    _drop_and_stop_while_rising(world, leg)
    _regrasp_and_carry(world, leg)


def test_a_leg_dropped_above_a_spot_is_grasped_again() -> None:
    world = PhysicalWorld()
    _carry(world, 1, Action.OBJECT, Target("spot", 3))  # with a leg in hand: above the spot
    _drop_and_stop_while_rising(world, 1)
    _regrasp_and_carry(world, 1)


@pytest.mark.parametrize("apart", [0.06, 0.08, 0.10, 0.12])
def test_a_leg_counts_as_graspable_where_it_lies_only_if_the_close_holds_it(apart: float) -> None:
    """Two parallel legs, axes ``apart`` m apart: where the other leg lies in the open fingers'
    way, the close catches nothing (measured: 6 and 8 cm), and the person must not leave such a
    leg for the robot (the stuck episodes: a dropped leg rolled against another, axes 4 cm
    apart, and every close after that closed on nothing)."""
    world = PhysicalWorld(SceneLayout(legs=((0.44, 0.31, 0.0), (0.44, 0.31 + apart, 0.0))))
    world.run(0.5)
    graspable = world.legs.graspable(0)
    assert world.execute(Action.OBJECT, Target("leg", 0)).succeeded
    close = world.execute(Action.CLOSE, None)
    assert graspable == close.succeeded, (apart, graspable, close.detail)
    assert graspable == (apart >= 0.10)
