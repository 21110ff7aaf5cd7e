"""The closed loop in physics: the person watches, recognises, reacts; consequences are physical.

Nothing is teleported: legs move only by contact. The person's body (``PhysicalBody``) watches
with a fixed reaction time; the robot never learns what the person wants, only the thumb down.
"""

from __future__ import annotations

import numpy as np
import pytest
from person_steps import Acted, intent

from pil.task.world import Target
from pil.types import Action, Hand
from robin_sim.control.trajectory import pose, through
from robin_sim.model import robot_spec as spec
from robin_sim.robot.actions import leg_offset_in_site

LIFT = 0.15  # m the held leg is raised above the table before the unwanted open
IN_HAND = 0.005  # m, a leg that stays held moves at most this much in the hand
RETURN_LIMIT = 0.005  # m, grasp site after an undo vs before the action (the 5 mm)
COAST_LIMIT = 0.01  # m the arm may coast after it halts (its stopping distance)
TICK = 0.02  # s, one control tick


def _holding_leg_in_the_air(reaction: float) -> Acted:
    """Leg 0 grasped (approved) and lifted ``LIFT`` above the table."""
    acted = Acted(reaction=reaction)
    world = acted.world
    assert acted.act(Action.OBJECT, intent("pointing", "object", Target("leg", 0))).succeeded
    assert acted.act(Action.CLOSE, intent("grasp", "close")).succeeded
    here = world.sim.commanded_site_pose()
    up = pose(here.translation() + np.array([0.0, 0.0, LIFT]), here.rotation().wxyz)
    world.sim.execute(world.sim.plan(through([here, up])))
    assert world.held_leg() == 0
    return acted


@pytest.mark.slow
def test_a_slow_person_rejecting_an_open_while_holding_sees_the_leg_drop() -> None:
    acted = _holding_leg_in_the_air(reaction=2.0)
    world = acted.world
    high = world.legs.position(0)[2]
    outcome = acted.act(Action.OPEN, intent("give me", "human"))  # the person wants "human"
    assert outcome.interrupted and outcome.dropped == 0
    assert world.hand() is Hand.FREE and world.held_leg() is None  # read from contacts
    world.run(1.0)
    low = world.legs.position(0)
    assert high - low[2] > LIFT - 0.02  # it fell where physics took it: onto the table top
    assert low[2] == pytest.approx(spec.TABLE_TOP_Z + spec.LEG_RADIUS, abs=0.005)
    watcher = acted.body.last_watcher
    assert watcher is not None and watcher.why == "the fingers move"
    assert watcher.stopped_at - watcher.recognized_at == pytest.approx(2.0, abs=TICK + 1e-6)


@pytest.mark.slow
def test_a_fast_person_stops_the_open_before_the_leg_slips_out() -> None:
    acted = _holding_leg_in_the_air(reaction=0.2)
    world = acted.world
    offset = leg_offset_in_site(world.ctx, 0)
    outcome = acted.act(Action.OPEN, intent("give me", "human"))
    assert outcome.interrupted and outcome.undone and outcome.dropped is None
    assert world.held_leg() == 0 and world.hand() is Hand.OCCUPIED
    assert np.linalg.norm(leg_offset_in_site(world.ctx, 0) - offset) <= IN_HAND


@pytest.mark.slow
@pytest.mark.parametrize("reaction", [0.3, 0.8])
def test_an_interrupted_move_stops_one_reaction_later_and_goes_back(reaction: float) -> None:
    acted = Acted(reaction=reaction)
    world = acted.world
    start = world.sim.site_pose().translation()
    track: list[tuple[float, np.ndarray]] = []
    world.sim.add_observer(lambda s: track.append((s.time, s.site_pose().translation())))
    # The person points at leg 3 and means "object"; the robot heads for the person's palm.
    outcome = acted.act(Action.HUMAN, intent("pointing", "object", Target("leg", 3)))
    watcher = acted.body.last_watcher
    assert watcher is not None and outcome.interrupted and outcome.undone
    assert watcher.why == "the hand heads elsewhere"
    assert watcher.stopped_at - watcher.recognized_at == pytest.approx(reaction, abs=TICK + 1e-6)
    halted = next(p for t, p in track if t >= watcher.stopped_at - 1e-9)
    settled = next(p for t, p in track if t >= watcher.stopped_at + 0.2 - 1e-9)
    assert np.linalg.norm(settled - halted) <= COAST_LIMIT  # it stopped where it was
    result = world.last_result
    assert result is not None and result.measurements["stop_coast_m"] <= COAST_LIMIT
    assert result.measurements["return_error_m"] <= RETURN_LIMIT
    assert np.linalg.norm(world.sim.site_pose().translation() - start) <= RETURN_LIMIT
    assert world.person_contacts.events == 0


@pytest.mark.slow
def test_a_wrong_result_is_rejected_at_its_end_and_taken_back() -> None:
    """ "object" to the pointed spot while holding stops 10 cm above it; the person wanted
    "location" (the leg on the spot): the motion looked right, the result does not."""
    acted = Acted(reaction=0.4)
    world = acted.world
    assert acted.act(Action.OBJECT, intent("pointing", "object", Target("leg", 1))).succeeded
    assert acted.act(Action.CLOSE, intent("grasp", "close")).succeeded
    before = world.sim.site_pose().translation()
    outcome = acted.act(Action.OBJECT, intent("pointing", "location", Target("spot", 1)))
    assert outcome.interrupted and outcome.undone and "rejected at its end" in outcome.detail
    assert acted.body.last_watcher.why == "the hand stays too high"
    assert world.held_leg() == 1
    assert np.linalg.norm(world.sim.site_pose().translation() - before) <= RETURN_LIMIT
    outcome = acted.act(Action.LOCATION, intent("pointing", "location", Target("spot", 1)))
    assert outcome.succeeded and not outcome.interrupted  # the meant action is let stand
