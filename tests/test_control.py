"""The mink arm IK, joint plans, the hand controller and the control loop, on the real scene."""

from __future__ import annotations

import mink
import mujoco
import numpy as np
import pytest

from robin_sim.control.ik import (
    ORIENTATION_TOLERANCE,
    POSITION_TOLERANCE,
    ArmIK,
    arm_kinematic_model,
    home_arm_q,
)
from robin_sim.control.simulator import HandTargets, Simulator
from robin_sim.control.trajectory import lift_traverse_descend, pose, through
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import build_spec

SIDE = names.ACTIVE_SIDE
LIMITS = dict(zip(names.arm_joints(SIDE), spec.ARM_VELOCITY_LIMITS, strict=True))
TARGETS = HandTargets(np.array(spec.HAND_OPEN_CTRL), np.array(spec.HAND_CLOSED_CTRL))


@pytest.fixture(scope="module")
def scene_spec() -> mujoco.MjSpec:
    return build_spec()


@pytest.fixture(scope="module")
def model(scene_spec: mujoco.MjSpec) -> mujoco.MjModel:
    return scene_spec.compile()


def _sim(model: mujoco.MjModel, scene_spec: mujoco.MjSpec) -> Simulator:
    return Simulator(model, TARGETS, spec=scene_spec, velocity_limits=LIMITS)


def _reach_path(sim: Simulator, offset: tuple[float, float, float] = (0.08, 0.1, -0.1)):
    start = sim.commanded_site_pose()
    goal = pose(start.translation() + np.array(offset), start.rotation().wxyz)
    return lift_traverse_descend(start, goal, clearance_z=start.translation()[2] + 0.03)


def test_kinematic_model_keeps_only_the_arm_and_its_kinematics(scene_spec, model) -> None:
    arm = arm_kinematic_model(scene_spec, SIDE)
    assert arm.nv == 7 and arm.nq == 7
    assert [arm.joint(i).name for i in range(arm.njnt)] == list(names.arm_joints(SIDE))
    full_data, arm_data = mujoco.MjData(model), mujoco.MjData(arm)
    q = home_arm_q(model, SIDE) + 0.1
    full_data.qpos[[model.joint(j).qposadr[0] for j in names.arm_joints(SIDE)]] = q
    arm_data.qpos[:] = q
    mujoco.mj_kinematics(model, full_data)
    mujoco.mj_kinematics(arm, arm_data)
    site = names.grasp_site(SIDE)
    assert arm_data.site(site).xpos == pytest.approx(full_data.site(site).xpos, abs=1e-12)
    assert arm_data.site(site).xmat == pytest.approx(full_data.site(site).xmat, abs=1e-12)


def test_reduced_ik_matches_full_model_ik_with_frozen_dofs(scene_spec, model) -> None:
    home = home_arm_q(model, SIDE)
    reduced = ArmIK(arm_kinematic_model(scene_spec, SIDE), SIDE, LIMITS, posture_q=home)
    full = ArmIK(model, SIDE, LIMITS, posture_q=home)
    assert not reduced.constraints and full.constraints  # the full model freezes 49 DoFs
    start = full.site_pose()
    path = through(
        [start, pose(start.translation() + np.array([0.05, 0.05, -0.1]), start.rotation().wxyz)]
    )
    q_before = full.configuration.q.copy()
    plan_full, plan_reduced = full.plan(path, 0.02), reduced.plan(path, 0.02)
    assert plan_full.q == pytest.approx(plan_reduced.q, abs=1e-6)
    moved = np.flatnonzero(np.abs(full.configuration.q - q_before) > 1e-12)
    arm_adr = {model.joint(j).qposadr[0] for j in names.arm_joints(SIDE)}
    assert set(moved.tolist()) <= arm_adr


def test_plan_reaches_goal_within_velocity_limits(model, scene_spec) -> None:
    sim = _sim(model, scene_spec)
    path = _reach_path(sim)
    plan = sim.plan(path)
    assert plan.position_error < 1e-3 and plan.orientation_error < 1e-2
    rates = np.abs(np.diff(np.vstack([sim.arm_command, plan.q]), axis=0)) / plan.dt
    assert np.all(rates <= np.array(spec.ARM_VELOCITY_LIMITS) + 1e-6)
    assert sim.arm_command == pytest.approx(sim.data.ctrl[sim.arm_actuators])  # nothing moved


def test_plan_to_far_target_reports_the_miss(model, scene_spec) -> None:
    sim = _sim(model, scene_spec)
    start = sim.commanded_site_pose()
    far = pose([1.2, -0.5, 0.77], start.rotation().wxyz)
    plan = sim.plan(lift_traverse_descend(start, far, 0.95))
    assert plan.position_error > POSITION_TOLERANCE and not plan.reaches_goal
    assert sim.commanded_site_pose().translation() == pytest.approx(start.translation())


def test_plan_that_reaches_the_point_but_not_the_orientation_misses(model) -> None:
    # An IK that barely weighs orientation gets to a reachable point with the hand turned 1.5 rad
    # the wrong way: that plan does not reach its goal, however close the position is.
    ik = ArmIK(model, SIDE, LIMITS, orientation_cost=1e-3)
    start = ik.site_pose()
    turned = start.rotation() @ mink.SO3.exp(np.array([1.5, 0.0, 0.0]))
    goal = mink.SE3.from_rotation_and_translation(turned, np.array([0.5, 0.25, 0.85]))
    plan = ik.plan(lift_traverse_descend(start, goal, 0.95), 0.02)
    assert plan.position_error <= POSITION_TOLERANCE
    assert plan.orientation_error > ORIENTATION_TOLERANCE
    assert not plan.reaches_goal


def test_prefix_and_reverse_end_at_start_targets(model, scene_spec) -> None:
    sim = _sim(model, scene_spec)
    plan = sim.plan(_reach_path(sim))
    start = sim.arm_command
    shown = plan.prefix(0.3)
    assert len(shown.q) == round(0.3 * len(plan.q))
    back = shown.reversed_from(start)
    assert np.array_equal(back.q[-1], start) and np.array_equal(back.q[0], shown.q[-2])


@pytest.mark.slow
def test_only_the_active_arm_moves_and_reaches(model, scene_spec) -> None:
    sim = _sim(model, scene_spec)
    other = [model.joint(j).qposadr[0] for j in names.arm_joints("r")]
    other_ctrl = [model.actuator(a).id for a in names.arm_actuators("r") + names.HEAD_ACTUATORS]
    q_other, ctrl_other = sim.data.qpos[other].copy(), sim.data.ctrl[other_ctrl].copy()
    path = _reach_path(sim)
    sim.execute(sim.plan(path))
    assert np.array_equal(sim.data.ctrl[other_ctrl], ctrl_other)
    assert np.abs(sim.data.qpos[other] - q_other).max() < 2e-3  # rad, reaction jitter only
    error = np.linalg.norm(sim.site_pose().translation() - path.end.translation())
    assert error < 3e-3  # m, position servo tracking after the 0.4 s settle


@pytest.mark.slow
def test_same_inputs_give_bitwise_identical_trajectory(model, scene_spec) -> None:
    runs = []
    for _ in range(2):
        sim = _sim(model, scene_spec)
        sim.execute(sim.plan(_reach_path(sim)))
        sim.hand.close(sim.time)
        sim.run(0.5)
        runs.append(sim.data.qpos.tobytes() + sim.data.qvel.tobytes())
    assert runs[0] == runs[1]


@pytest.mark.slow
def test_hand_closes_fully_on_nothing_and_opens_again(model, scene_spec) -> None:
    sim = _sim(model, scene_spec)
    sim.hand.close(sim.time)
    sim.run(1.0)
    closed = sim.data.qpos[sim.hand.joint_qadr]
    assert closed[1:] == pytest.approx(spec.HAND_CLOSED_CTRL[1:], abs=0.05)
    sim.hand.open(sim.time)
    sim.run(0.8)
    assert sim.data.qpos[sim.hand.joint_qadr] == pytest.approx(spec.HAND_OPEN_CTRL, abs=0.05)


def test_tick_runs_controllers_before_and_observers_after_physics(model, scene_spec) -> None:
    sim = _sim(model, scene_spec)
    assert sim.substeps == 10 and sim.control_dt == pytest.approx(0.02)
    seen: list[tuple[str, float]] = []
    remove_controller = sim.add_controller(lambda s: seen.append(("before", s.time)))
    sim.add_observer(lambda s: seen.append(("after", s.time)))
    sim.run(0.04)
    assert [kind for kind, _ in seen] == ["before", "after", "before", "after"]
    assert [t for _, t in seen] == pytest.approx([0.0, 0.02, 0.02, 0.04])
    remove_controller()
    sim.tick()
    assert seen[-1][0] == "after" and seen[-2][0] == "after"
    assert sim.step_until(lambda s: s.time >= 0.1 - 1e-9, timeout=1.0)
    assert not sim.step_until(lambda s: False, timeout=0.04)
