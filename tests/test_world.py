"""``PhysicalWorld`` with the person's body: handovers, placements, rejections, new tables.

The person's part (gestures, palm, thumbs, the bin) is played by :class:`PhysicalBody` through
``tests/person_steps.py``, in the runner's order; the world itself never moves the person.
"""

from __future__ import annotations

import numpy as np
import pytest
from person_steps import Acted
from person_steps import intent as _intent

from pil.errors import RobinPilError
from pil.task.world import Target, World
from pil.types import Action, Gesture, Hand
from robin_sim.control.trajectory import pose
from robin_sim.model import robot_spec as spec
from robin_sim.person.body import PERSON_CLEAR_X
from robin_sim.robot.planning import HANDOVER_TOLERANCE, PLACEMENT_TOLERANCE
from robin_sim.robot.world import PhysicalWorld


def _in_bin(world: PhysicalWorld, position: np.ndarray) -> bool:
    """Inside the bin's walls (inner half size 0.18 m) and below their top (0.26 m)."""
    inner = np.array(spec.BIN_INNER_SIZE[:2]) / 2
    return bool(np.all(np.abs(position[:2] - world.layout.bin) <= inner) and position[2] < 0.26)


POINT_LEG0 = _intent("pointing", "object", Target("leg", 0))
GRASP = _intent("grasp", "close")
GIVE = _intent("give me", "human")
RELEASE = _intent("release", "open")


@pytest.mark.slow
def test_handover_type_a_with_a_rejected_action_in_the_middle() -> None:
    acted = Acted(seed=3)
    world: World = acted.world
    assert isinstance(world, PhysicalWorld)
    world.start_table(0)
    seen: list[tuple[Action, np.ndarray]] = []
    world.add_result_hook(lambda r: seen.append((r.action, world.legs.position(0))))
    steps = [
        (Action.OBJECT, POINT_LEG0, Hand.FREE),
        (Action.CLOSE, GRASP, Hand.OCCUPIED),
        (Action.LOCATION, GIVE, Hand.OCCUPIED),  # unwanted: the person stops it, it is undone
        (Action.HUMAN, GIVE, Hand.OCCUPIED),
        (Action.OPEN, RELEASE, Hand.FREE),
    ]
    for action, intent, hand in steps:
        outcome = acted.act(action, intent)
        wanted = action is intent.action
        assert outcome.succeeded is wanted, (action, outcome.detail)
        assert outcome.undone is not wanted and outcome.interrupted is not wanted
        assert world.hand() is hand, action  # read from contacts
    released = world.last_result
    assert released is not None and released.action is Action.OPEN
    assert released.measurements["release_error_m"] <= HANDOVER_TOLERANCE  # 3 cm
    assert released.measurements["leg_speed_mps"] < 0.01  # at rest on the palm
    assert world.delivered == [0]
    assert [a for a, _ in seen] == [Action.OBJECT, Action.CLOSE, Action.HUMAN, Action.OPEN]
    on_palm = seen[-1][1]  # the hook ran before the person took the leg away
    assert world.last_release is not None and world.last_release.kind == "palm"
    assert np.linalg.norm(on_palm[:2] - world.last_release.point[:2]) <= HANDOVER_TOLERANCE
    assert _in_bin(world, world.legs.position(0))  # the person carried it off and tipped it in
    assert world.human.pose().translation() == pytest.approx(world.human.rest_pose.translation())
    assert [r.action for r in world.history] == [s[0] for s in steps]
    assert [w.number for w in world.data.warning] == [0] * len(
        world.data.warning
    )  # no MuJoCo warning


@pytest.mark.slow
def test_placement_on_a_pointed_spot() -> None:
    acted = Acted()
    world = acted.world
    acted.act(Action.OBJECT, _intent("pointing", "object", Target("leg", 2)))
    acted.act(Action.CLOSE, GRASP)
    spot = Target("spot", 1)
    outcome = acted.act(Action.LOCATION, _intent("pointing", "location", spot))
    assert outcome.succeeded
    assert acted.act(Action.OPEN, RELEASE).succeeded
    lying = world.legs.position(2)
    assert np.linalg.norm(lying[:2] - np.array(world.layout.spots[1])) <= PLACEMENT_TOLERANCE
    assert lying[2] == pytest.approx(0.77, abs=0.003)  # on the table top
    assert world.hand() is Hand.FREE


@pytest.mark.slow
def test_start_table_lays_the_legs_out_again_only_with_an_empty_hand() -> None:
    acted = Acted()
    world = acted.world
    acted.act(Action.OBJECT, _intent("pointing", "object", Target("leg", 1)))
    acted.act(Action.CLOSE, GRASP)
    with pytest.raises(RobinPilError, match="still holds leg 1"):
        world.start_table(1)
    acted.act(Action.LOCATION, _intent("pointing", "location", Target("spot", 0)))
    acted.act(Action.OPEN, RELEASE)
    assert np.linalg.norm(world.legs.position(1)[:2] - world.layout.legs[1][:2]) > 0.1
    world.start_table(1)
    laid = world.legs.positions()
    expected = np.array([[x, y, 0.77] for x, y, _ in world.layout.legs])
    assert np.abs(laid - expected).max() < 0.002  # m
    assert world.hand() is Hand.FREE


def test_bad_targets_name_the_valid_choices() -> None:
    world = PhysicalWorld()
    before = world.data.qpos.tobytes()
    with pytest.raises(
        RobinPilError, match=rf"leg 9 does not exist; valid: 0\.\.{world.legs.count - 1}"
    ):
        world.execute(Action.OBJECT, Target("leg", 9))
    last = len(world.layout.spots) - 1
    with pytest.raises(RobinPilError, match=rf"spot 9 does not exist; valid: 0\.\.{last}"):
        world.execute(Action.LOCATION, Target("spot", 9))
    with pytest.raises(RobinPilError, match="valid: 'leg', 'spot'"):
        world.execute(Action.OBJECT, Target("box", 0))
    assert world.data.qpos.tobytes() == before


@pytest.mark.slow
def test_same_seed_same_physics_other_seed_other_palm() -> None:
    def run(seed: int) -> tuple[bytes, np.ndarray]:
        acted = Acted(seed=seed)
        for action, meant in ((Action.OBJECT, POINT_LEG0), (Action.CLOSE, GRASP)):
            acted.act(action, meant)
        acted.act(Action.HUMAN, GIVE)
        return acted.world.data.qpos.tobytes(), acted.world.human.palm_centre()

    first, again, other = run(5), run(5), run(6)
    assert first[0] == again[0]
    assert np.linalg.norm(first[1] - other[1]) > 1e-4  # the person's palm is jittered by seed


def test_person_points_at_a_leg_and_rests_again() -> None:
    acted = Acted()
    world = acted.world
    rest = world.human.pose().translation()
    took = acted.body.point_at(Target("leg", 2))
    assert took > 0.5 and world.time == pytest.approx(took, abs=0.02)
    hand = world.human.pose().translation()
    assert np.linalg.norm(hand[:2] - world.legs.position(2)[:2]) < 0.15  # m, right above it
    assert hand[2] > world.legs.position(2)[2] + 0.1
    acted.body.rest()
    assert world.human.pose().translation() == pytest.approx(rest, abs=1e-9)


@pytest.mark.slow
def test_a_whole_table_four_handovers_in_a_row() -> None:
    acted = Acted(seed=11)
    world = acted.world
    world.start_table(0)
    for leg in range(4):
        point = _intent("pointing", "object", Target("leg", leg))
        for action, intent in (
            (Action.OBJECT, point),
            (Action.CLOSE, GRASP),
            (Action.HUMAN, GIVE),
            (Action.OPEN, RELEASE),
        ):
            outcome = acted.act(action, intent)
            assert outcome.succeeded, (leg, action, outcome.detail)
        assert world.last_result.measurements["release_error_m"] <= HANDOVER_TOLERANCE
        assert world.hand() is Hand.FREE
        waiting = world.legs.positions()[leg + 1 :]  # legs still on the table stay put
        expected = np.array([[x, y, 0.77] for x, y, _ in world.layout.legs[leg + 1 :]])
        assert len(waiting) == 0 or np.abs(waiting - expected).max() < 0.005  # m
    assert world.delivered == [0, 1, 2, 3]
    assert all(_in_bin(world, p) for p in world.legs.positions())


def test_object_without_a_pointed_target_goes_to_the_nearest_leg() -> None:
    world = PhysicalWorld()
    site = world.sim.site_pose().translation()
    nearest = int(np.argmin(np.linalg.norm(world.legs.positions() - site, axis=1)))
    outcome = world.execute(Action.OBJECT, None)  # nobody watching: it runs to its end
    assert outcome.succeeded and outcome.detail == f"reached leg {nearest}"


@pytest.mark.slow
def test_the_pointing_hand_draws_back_before_the_arm_moves() -> None:
    acted = Acted()
    world = acted.world
    acted.body.point_at(Target("leg", 0))  # the palm hovers right above the leg
    assert world.human.pose().translation()[0] < PERSON_CLEAR_X
    acted.body.perform(POINT_LEG0.gesture, POINT_LEG0.target)  # point, hold, draw back
    assert world.human.pose().translation()[0] == pytest.approx(PERSON_CLEAR_X)
    outcome = world.execute(Action.OBJECT, POINT_LEG0.target)
    assert outcome.succeeded, outcome.detail
    assert world.last_result.measurements["site_error_m"] < 0.005  # m


@pytest.mark.slow
def test_open_over_the_palm_needs_the_palm_under_the_leg() -> None:
    acted = Acted(seed=2)
    world = acted.world
    for action, intent in (
        (Action.OBJECT, POINT_LEG0),
        (Action.CLOSE, GRASP),
        (Action.HUMAN, GIVE),
    ):
        assert acted.act(action, intent).succeeded
    assert not world.palm_is_out()  # the thumb up was shown drawn back, out of Robin's way
    acted.body.perform(Gesture.GIVE_ME, None)  # the palm slides back under the held leg
    assert world.palm_is_out() and world.held_leg() == 0
    palm = world.human.palm_centre()
    wants_spot = _intent("pointing", "location", Target("spot", 0))  # meant, not yet shown
    for action in (Action.OBJECT, Action.LOCATION):  # stopped moves leave the palm out
        watcher = acted.body.watch(_intent("release", "open"), 0.5)
        outcome = world.execute(action, wants_spot.target, watcher)
        assert outcome.interrupted and outcome.undone, (action, outcome.detail)
        assert world.palm_is_out()
    here = world.human.pose().translation()  # the person points away: back, down, then over
    away = [
        pose(here + np.array([0.15, 0.0, -0.06])),
        pose(world.legs.position(1) + np.array([0.12, 0.0, 0.16])),
    ]
    world.run(world.human.follow(away, world.time))
    assert world.held_leg() == 0
    assert not world.palm_is_out()
    outcome = acted.act(Action.OPEN, RELEASE)  # performing release, the palm comes back under
    assert outcome.succeeded, outcome.detail
    assert world.last_result.measurements["height_above_surface_m"] == pytest.approx(0.02, abs=0.01)
    assert np.linalg.norm(world.last_result.measurements["leg_x"] - palm[0]) <= HANDOVER_TOLERANCE
    assert world.delivered == [0]
