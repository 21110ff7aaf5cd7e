"""Robin's gaze (robin_sim.robot.head) in a real PhysicalWorld: where the left eye looks.

Angles are measured from physics, after the head got there: between the left eye camera's
optical axis (``-z`` of its frame in ``data.cam_xmat``) and the direction from the eye to the
point attended.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from person_steps import Acted
from person_steps import intent as _intent

from pil.task.world import Target
from pil.types import Action, Gesture
from robin_sim.control.simulator import Simulator
from robin_sim.model import names
from robin_sim.robot.head import MAX_SPEED
from robin_sim.robot.world import PhysicalWorld

AIM_TOLERANCE_DEG = 5.0  # eye axis to the attended point (the tilt limit costs leg 0 ~4 deg)


def eye_angle_deg(world: PhysicalWorld, point: np.ndarray) -> float:
    """Angle between the left eye's optical axis and the direction from the eye to ``point``."""
    cam = world.model.camera(names.EYE_CAMERA).id
    axis = -world.data.cam_xmat[cam].reshape(3, 3)[:, 2]
    to_point = np.asarray(point) - world.data.cam_xpos[cam]
    cos = axis @ to_point / np.linalg.norm(to_point)
    return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))


class HeadLog:
    """Head joint values and targets of every tick (an observer)."""

    def __init__(self, world: PhysicalWorld) -> None:
        model = world.model
        self.qadr = [model.jnt_qposadr[model.joint(j).id] for j in names.HEAD_JOINTS]
        self.act = [model.actuator(a).id for a in names.HEAD_ACTUATORS]
        self.q: list[np.ndarray] = []
        self.ctrl: list[np.ndarray] = []
        world.sim.add_observer(self)

    def __call__(self, sim: Simulator) -> None:
        self.q.append(sim.data.qpos[self.qadr].copy())
        self.ctrl.append(sim.data.ctrl[self.act].copy())


def test_the_head_looks_at_each_pointed_leg_and_stays_in_its_limits() -> None:
    acted = Acted()
    world, body = acted.world, acted.body
    log = HeadLog(world)
    angles = []
    for leg in range(world.legs.count):
        body.perform(Gesture.POINTING, Target("leg", leg))  # point, hold, draw the hand back
        assert world.head.kind == "pointed"
        angles.append(eye_angle_deg(world, world.legs.position(leg)))
    assert max(angles) < AIM_TOLERANCE_DEG, angles
    q, ctrl = np.array(log.q), np.array(log.ctrl)
    model = world.model
    for i, joint in enumerate(names.HEAD_JOINTS):
        low, high = model.jnt_range[model.joint(joint).id]
        assert low <= ctrl[:, i].min() and ctrl[:, i].max() <= high  # targets inside the limits
        assert low - 1e-3 <= q[:, i].min() and q[:, i].max() <= high + 1e-3  # rad
    target_speed = np.abs(np.diff(ctrl, axis=0)).max() / world.sim.control_dt
    assert target_speed <= MAX_SPEED + 1e-9  # rad/s: smooth, never a jump
    assert np.ptp(ctrl[:, 0]) > 0.4  # rad of pan: it really turned between legs 0 and 3


def test_the_head_watches_the_palm_through_a_handover() -> None:
    acted = Acted()
    world = acted.world
    world.start_table(0)
    acted.act(Action.OBJECT, _intent("pointing", "object", Target("leg", 1)))
    acted.act(Action.CLOSE, _intent("grasp", "close"))
    give = _intent("give me", "human")
    acted.body.perform(give.gesture, None)
    assert world.head.kind == "person hand"
    assert eye_angle_deg(world, world.human.palm_centre()) < AIM_TOLERANCE_DEG
    acted._performed = give
    kinds: list[str] = []
    world.sim.add_observer(lambda _: kinds.append(world.head.kind))
    assert acted.act(Action.HUMAN, give).succeeded
    assert set(kinds) == {"palm"}  # the whole move to the palm
    assert eye_angle_deg(world, world.human.palm_centre()) < AIM_TOLERANCE_DEG
    kinds.clear()
    assert acted.act(Action.OPEN, _intent("release", "open")).succeeded
    assert kinds and kinds[0] == "person hand"  # the release gesture, then the open
    assert "palm" in kinds
    assert world.delivered == [1]


def test_the_head_follows_the_robot_hand_in_a_move() -> None:
    acted = Acted()
    world = acted.world
    acted.act(Action.OBJECT, _intent("pointing", "object", Target("leg", 2)))
    assert world.head.kind == "robot hand"
    site = world.data.site(names.grasp_site(names.ACTIVE_SIDE)).xpos
    assert eye_angle_deg(world, site) < AIM_TOLERANCE_DEG


def test_an_unreachable_point_stops_at_the_limits() -> None:
    world = PhysicalWorld()
    log = HeadLog(world)
    world.head.attend(np.array([0.0, -1.0, 3.0]), "right, high up")  # past pan and tilt
    world.run(2.0)
    model = world.model
    ctrl = np.array(log.ctrl)
    for i, joint in enumerate(names.HEAD_JOINTS):
        low, high = model.jnt_range[model.joint(joint).id]
        assert low < ctrl[:, i].min() and ctrl[:, i].max() < high
    assert np.isclose(ctrl[-1, 0], world.head.low[0]) and np.isclose(ctrl[-1, 1], world.head.low[1])
    nefc, head_joints = world.data.nefc, [model.joint(j).id for j in names.HEAD_JOINTS]
    limits = world.data.efc_type[:nefc] == mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT
    limits &= np.isin(world.data.efc_id[:nefc], head_joints)
    assert not limits.any()  # the margin keeps the head's joint limits inactive


def test_unknown_attention_names_the_choices() -> None:
    world = PhysicalWorld()
    with pytest.raises(ValueError, match="'palm', 'person hand', 'robot hand'"):
        world.head.attend_to("ceiling")


def test_same_seed_gives_identical_qpos() -> None:
    runs = []
    for _ in range(2):
        acted = Acted(seed=4)
        acted.act(Action.OBJECT, _intent("pointing", "object", Target("leg", 3)))
        acted.body.perform(Gesture.GIVE_ME, None)
        runs.append(acted.world.data.qpos.copy())
    assert np.array_equal(runs[0], runs[1])


def test_the_vision_detectors_look_at_takes_the_head_over() -> None:
    from robin_sim.control.gaze import head_angles, head_qpos, look_at

    world = PhysicalWorld()
    world.head.attend(world.legs.position(3), "pointed")
    world.run(0.3)  # the head is turning to leg 3
    palm = world.human.palm_centre()
    look_at(world.sim, palm)
    world.run(0.5)
    aim = head_angles(world.model, world.data, palm)
    act = [world.model.actuator(a).id for a in names.HEAD_ACTUATORS]
    assert np.array_equal(world.data.ctrl[act], aim)  # look_at's targets stand: the gaze let go
    assert np.abs(head_qpos(world.model, world.data) - aim).max() < 0.02  # rad (gravity sag)
    world.head.attend_to("robot hand")  # the next attention takes the head back
    world.run(1.0)
    site = world.data.site(names.grasp_site(names.ACTIVE_SIDE)).xpos
    assert eye_angle_deg(world, site) < AIM_TOLERANCE_DEG
