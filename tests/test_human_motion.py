"""The person's mocap hand: poses reached exactly, smooth bounded motion, tipping over the bin."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from robin_sim.control.human_hand import HAND_SPEED, SLIDE_IN, TIP_ANGLE, HumanHand
from robin_sim.control.simulator import HandTargets, Simulator
from robin_sim.control.trajectory import rotation_angle
from robin_sim.model import robot_spec as spec
from robin_sim.model.robot_spec import POINT_OFFSET
from robin_sim.model.scene import SceneLayout, build_model


@pytest.fixture(scope="module")
def model() -> mujoco.MjModel:
    return build_model()


@pytest.fixture
def rig(model: mujoco.MjModel) -> tuple[Simulator, HumanHand]:
    targets = HandTargets(np.array(spec.HAND_OPEN_CTRL), np.array(spec.HAND_CLOSED_CTRL))
    sim = Simulator(model, targets)
    hand = HumanHand(model, sim.data)
    hand.attach(sim)
    return sim, hand


def _record(sim: Simulator, hand: HumanHand) -> list[np.ndarray]:
    poses: list[np.ndarray] = []
    sim.add_observer(lambda _: poses.append(hand.pose().translation()))
    return poses


def test_palm_is_held_out_exactly_at_the_handover_point(rig) -> None:
    sim, hand = rig
    goal = np.array(SceneLayout().handover)
    positions = _record(sim, hand)
    duration = hand.hold_out_palm(goal, sim.time)
    assert hand.busy(sim.time)
    sim.run(duration + 0.04)
    assert not hand.busy(sim.time)
    assert hand.palm_centre() == pytest.approx(goal, abs=1e-9)
    assert rotation_angle(hand.pose(), hand.rest_pose) == pytest.approx(0.0, abs=1e-9)
    steps = np.linalg.norm(np.diff(np.array(positions), axis=0), axis=1)
    assert steps.max() <= HAND_SPEED * sim.control_dt * 1.01  # peak speed respected
    above = goal - hand.palm_offset + np.array([0.0, 0.0, 0.05])  # comes down onto the spot
    assert min(np.linalg.norm(p - above) for p in positions) < 1e-6


def test_rest_and_pointing_poses(rig) -> None:
    sim, hand = rig
    rest = hand.rest_pose.translation()
    leg = np.array([0.52, 0.22, 0.77])
    sim.run(hand.point_at(leg, sim.time) + 0.04)
    assert hand.pose().translation() == pytest.approx(leg + POINT_OFFSET, abs=1e-9)
    assert POINT_OFFSET[0] > 0 and POINT_OFFSET[2] > 0  # toward the person, and above
    sim.run(hand.rest(sim.time) + 0.04)
    assert hand.pose().translation() == pytest.approx(rest, abs=1e-9)


def test_take_away_carries_along_x_tips_over_the_bin_and_comes_back(rig) -> None:
    sim, hand = rig
    handover = np.array(SceneLayout().handover)
    sim.run(hand.hold_out_palm(handover, sim.time) + 0.04)
    held_out = hand.pose().translation()
    bin_position = np.array([*SceneLayout().bin, 0.0])
    angles: list[float] = []
    sim.add_observer(lambda _: angles.append(rotation_angle(hand.pose(), hand.rest_pose)))
    positions = _record(sim, hand)
    sim.run(hand.take_away(bin_position, sim.time) + 0.04)
    tipping = int(np.argmax(np.array(angles) > 1e-9))  # first tick with the palm turning
    carried = np.array(positions[:tipping])
    assert np.abs(carried[:, 1] - held_out[1]).max() < 1e-9  # no sideways motion: no rolling
    assert carried[-1] == pytest.approx([bin_position[0], held_out[1], held_out[2] - 0.03])
    assert max(angles) == pytest.approx(TIP_ANGLE, abs=1e-4)
    assert hand.pose().translation() == pytest.approx(hand.rest_pose.translation(), abs=1e-9)


def test_withdraw_draws_the_hand_straight_back(rig) -> None:
    sim, hand = rig
    sim.run(hand.point_at(np.array([0.44, 0.16, 0.77]), sim.time) + 0.04)
    here = hand.pose().translation()
    sim.run(hand.withdraw(0.95, sim.time) + 0.04)
    assert hand.pose().translation() == pytest.approx([0.95, here[1], here[2]], abs=1e-9)
    assert hand.withdraw(0.95, sim.time) == 0.0  # already clear: no motion


def test_a_raised_hand_comes_down_on_the_persons_side_before_sliding_under(rig) -> None:
    """From a thumb shown drawn back and raised, the palm comes down on the person's side
    first, slides in 4 cm low and rises into place: between the slide-in point and the palm's
    place it is never higher, so the fingers never sweep down past a leg held over the palm."""
    sim, hand = rig
    goal = np.array(SceneLayout().handover)
    sim.run(hand.hold_out_palm(goal, sim.time) + 0.04)
    sim.run(hand.withdraw(0.95, sim.time, 0.20) + 0.04)
    start = hand.pose().translation()
    positions = _record(sim, hand)
    sim.run(hand.slide_under(goal, sim.time) + 0.04)
    under = hand.hand_pose_for_palm(goal).translation()
    low_z = under[2] - 0.04
    # above the slide-in height the hand is straight below where it was, or rising into place
    high = [p for p in positions if p[2] > low_z + 1e-3 and p[0] > under[0] + 1e-3]
    assert high and all(abs(p[0] - start[0]) < 1e-3 for p in high)
    assert min(p[2] for p in positions) == pytest.approx(low_z, abs=1e-3)
    assert max(p[0] for p in positions if p[2] < low_z + 1e-3) >= under[0] + SLIDE_IN - 1e-3
    assert hand.palm_centre() == pytest.approx(goal, abs=1e-3)
