"""The five actions in physics: grasps hold, releases land, undos restore, far targets refused.

Nothing here writes an object's state: legs move only through contacts with the hand or the
table. Tolerances are stated next to each check.
"""

from __future__ import annotations

import numpy as np
import pytest

from pil.types import Action, Hand
from robin_sim.control.trajectory import pose, through
from robin_sim.model import names
from robin_sim.robot.actions import CloseAction, MoveAction, OpenAction, leg_offset_in_site
from robin_sim.robot.planning import CLEARANCE_Z
from robin_sim.robot.targets import UnreachableTargetError, grasp_goal, release_goal
from robin_sim.robot.world import PhysicalWorld

SLIP_LIMIT = 0.005  # m, leg displacement in the hand frame while carried at the default speed
RETURN_LIMIT = 0.005  # m, grasp site after an undo vs before the action
ARM_RETURN_LIMIT = 0.01  # rad, each arm joint after an undo vs before
LEG_STILL = 0.002  # m, a leg the action should not touch


def _leg_axis(world: PhysicalWorld, leg: int) -> np.ndarray:
    return world.data.xmat[world.model.body(names.leg_body(leg)).id].reshape(3, 3)[:, 0]


def _object(world: PhysicalWorld, leg: int) -> MoveAction:
    goal = grasp_goal(
        world.legs.position(leg), _leg_axis(world, leg), world.sim.commanded_site_pose(), 0.0
    )
    return MoveAction(Action.OBJECT, f"leg {leg}", goal, CLEARANCE_Z)


def _grasp(world: PhysicalWorld, leg: int) -> None:
    move = _object(world, leg)
    move.prepare(world.ctx)
    assert move.run(world.ctx).succeeded
    assert CloseAction().run(world.ctx).succeeded
    assert world.held_leg() == leg and world.hand() is Hand.OCCUPIED


def _lift(world: PhysicalWorld, height: float) -> None:
    here = world.sim.commanded_site_pose()
    up = pose(here.translation() + np.array([0.0, 0.0, height]), here.rotation().wxyz)
    world.sim.execute(world.sim.plan(through([here, up])))


def _stop_after(world: PhysicalWorld, seconds: float):  # type: ignore[no-untyped-def]
    """A ``stop`` that says stop from ``seconds`` of simulated time on (a thumb down)."""
    at = world.time + seconds
    return lambda: world.time >= at - 1e-9


def _track_excursion(world: PhysicalWorld, value) -> list[float]:
    """Largest ``value(world)`` seen at any tick from now on."""
    worst = [0.0]
    world.sim.add_observer(lambda _: worst.__setitem__(0, max(worst[0], value(world))))
    return worst


@pytest.mark.slow
@pytest.mark.parametrize("leg", [0, 1, 2, 3])
def test_grasp_lifts_and_carries_each_leg(leg: int) -> None:
    world = PhysicalWorld()
    resting = world.legs.position(leg)
    _grasp(world, leg)
    _lift(world, 0.20)
    assert world.held_leg() == leg
    assert world.legs.position(leg)[2] - resting[2] == pytest.approx(0.20, abs=0.01)
    carried = leg_offset_in_site(world.ctx, leg)
    slip = _track_excursion(
        world, lambda w: float(np.linalg.norm(leg_offset_in_site(w.ctx, leg) - carried))
    )
    far = np.array([0.62, -0.05, 0.85])  # across the table, down to near palm height
    goal = release_goal(far, carried, world.sim.commanded_site_pose().rotation())
    move = MoveAction(Action.HUMAN, "a point across the table", goal, CLEARANCE_Z)
    move.prepare(world.ctx)
    result = move.run(world.ctx)
    assert result.succeeded and world.held_leg() == leg
    assert slip[0] <= SLIP_LIMIT
    assert result.measurements["slip_m"] <= SLIP_LIMIT


@pytest.mark.slow
def test_open_over_spot_leaves_leg_lying_there() -> None:
    world = PhysicalWorld()
    _grasp(world, 1)
    spot = np.array([*world.layout.spots[0], 0.75])
    centre = spot + np.array([0.0, 0.0, 0.02 + 0.012])
    rotation = world.sim.commanded_site_pose().rotation()
    move = MoveAction(
        Action.LOCATION,
        "spot 0",
        release_goal(centre, leg_offset_in_site(world.ctx, 1), rotation),
        CLEARANCE_Z,
    )
    move.prepare(world.ctx)
    assert move.run(world.ctx).succeeded
    result = OpenAction(spot, tolerance=0.02, place="spot 0").run(world.ctx)
    assert result.succeeded, result.detail
    assert world.hand() is Hand.FREE
    lying = world.legs.position(1)
    assert np.linalg.norm(lying[:2] - spot[:2]) <= 0.02  # m
    assert lying[2] == pytest.approx(0.77, abs=0.003)  # on the table top
    assert world.legs.speed(1) < 0.01  # m/s, at rest


def test_unreachable_target_is_refused_before_anything_moves() -> None:
    world = PhysicalWorld()
    before = (world.data.qpos.tobytes(), world.data.ctrl.tobytes(), world.time)
    far = pose([1.0, -0.5, 0.77], world.sim.commanded_site_pose().rotation().wxyz)
    move = MoveAction(Action.OBJECT, "leg 7", far, CLEARANCE_Z)
    with pytest.raises(UnreachableTargetError, match=r"leg 7 at \(1\.000, -0\.500, 0\.770\)"):
        move.prepare(world.ctx)
    assert (world.data.qpos.tobytes(), world.data.ctrl.tobytes(), world.time) == before
    with pytest.raises(UnreachableTargetError, match="reachable: top-down"):
        move.run(world.ctx)


@pytest.mark.slow
def test_a_stopped_move_goes_back_from_where_it_stopped() -> None:
    world = PhysicalWorld()
    world.sim.run(0.2)
    arm, site, legs = world.sim.arm_q, world.sim.site_pose().translation(), world.legs.positions()
    away = _track_excursion(
        world, lambda w: float(np.linalg.norm(w.sim.site_pose().translation() - site))
    )
    move = _object(world, 2)
    move.prepare(world.ctx)
    result = move.run(world.ctx, _stop_after(world, 1.0))
    assert result.interrupted and result.undone and not result.succeeded
    assert result.measurements["stopped_after_s"] == pytest.approx(1.0, abs=0.021)  # one tick
    assert away[0] > 0.03  # m: it visibly moved towards the leg
    assert np.linalg.norm(world.sim.site_pose().translation() - site) <= RETURN_LIMIT
    assert np.abs(world.sim.arm_q - arm).max() <= ARM_RETURN_LIMIT
    assert np.abs(world.legs.positions() - legs).max() <= LEG_STILL
    assert world.hand() is Hand.FREE


@pytest.mark.slow
def test_stopped_moves_and_close_while_holding_keep_the_leg() -> None:
    world = PhysicalWorld()
    _grasp(world, 0)
    _lift(world, 0.1)
    offset, site = leg_offset_in_site(world.ctx, 0), world.sim.site_pose().translation()
    rotation = world.sim.commanded_site_pose().rotation()
    goal = release_goal(np.array([0.62, 0.05, 0.91]), offset, rotation)
    spot = np.array([*world.layout.spots[1], 0.79])
    for action, where in (
        (Action.HUMAN, goal),
        (Action.LOCATION, release_goal(spot, offset, rotation)),
    ):
        move = MoveAction(action, str(action), where, CLEARANCE_Z)
        move.prepare(world.ctx)
        result = move.run(world.ctx, _stop_after(world, 1.2))
        assert result.interrupted and result.undone and result.dropped is None
        assert world.held_leg() == 0
        assert np.linalg.norm(world.sim.site_pose().translation() - site) <= RETURN_LIMIT
        assert np.linalg.norm(leg_offset_in_site(world.ctx, 0) - offset) <= SLIP_LIMIT
    result = CloseAction().run(world.ctx, _stop_after(world, 0.3))  # squeezes, then relaxes
    assert result.interrupted and world.held_leg() == 0
    assert np.linalg.norm(leg_offset_in_site(world.ctx, 0) - offset) <= SLIP_LIMIT


@pytest.mark.slow
def test_a_close_stopped_at_a_leg_reopens_without_taking_it() -> None:
    world = PhysicalWorld()
    move = _object(world, 3)
    move.prepare(world.ctx)
    move.run(world.ctx)
    world.sim.run(0.2)
    fingers, legs = world.sim.data.qpos[world.sim.hand.joint_qadr], world.legs.positions()
    moved = _track_excursion(
        world,
        lambda w: float(np.abs(w.sim.data.qpos[w.sim.hand.joint_qadr] - fingers).max()),
    )
    result = CloseAction().run(world.ctx, _stop_after(world, 0.3))
    assert result.interrupted and result.undone and world.hand() is Hand.FREE
    assert moved[0] > 0.15  # rad: the fingers visibly closed part of the way
    assert np.abs(world.sim.data.qpos[world.sim.hand.joint_qadr] - fingers).max() < 0.05  # rad
    assert np.abs(world.legs.positions() - legs).max() <= 0.005  # m


@pytest.mark.slow
def test_wanted_close_on_nothing_fails_and_reopens() -> None:
    world = PhysicalWorld()
    result = CloseAction().run(world.ctx)
    assert not result.succeeded and result.undone
    assert "nothing" in result.detail
    assert world.hand() is Hand.FREE
    opened = world.sim.data.qpos[world.sim.hand.joint_qadr]
    assert opened[1:] == pytest.approx(world.sim.hand.targets.open[1:], abs=0.05)


@pytest.mark.slow
def test_a_leg_dropped_on_the_way_is_reported_and_the_arm_moves_back() -> None:
    world = PhysicalWorld()
    _grasp(world, 1)
    site = world.sim.site_pose().translation()
    offset = leg_offset_in_site(world.ctx, 1)
    goal = release_goal(
        np.array([0.6, 0.0, 0.91]), offset, world.sim.commanded_site_pose().rotation()
    )
    move = MoveAction(Action.HUMAN, "the person's palm", goal, CLEARANCE_Z)
    move.prepare(world.ctx)
    let_go_at = world.time + 0.5 * move.plan.duration  # the fingers open half way (a fault)
    world.sim.add_controller(
        lambda s: s.hand.open(s.time) if abs(s.time - let_go_at) < s.control_dt / 2 else None
    )
    result = move.run(world.ctx)
    assert not result.succeeded and not result.undone
    assert "leg 1 dropped" in result.detail and "arm moved back" in result.detail
    assert world.held_leg() is None and world.hand() is Hand.FREE
    assert np.linalg.norm(world.sim.site_pose().translation() - site) <= RETURN_LIMIT
