"""Friction-only grasps on the hand test bench: the leg stays in the hand while lifted and shaken.

The hand hangs palm down on three position-controlled slides (``bench_x/y/z``); nothing but
contact forces holds the leg (no welds, no writes to the leg's qpos).
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from hand_bench import HandBench

from pil.types import Hand
from robin_sim.control.hand_state import HandSensor
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import SceneLayout, build_model

LIFT = 0.20  # m
LIFT_SPEED = 0.25  # m/s, peak of the min-jerk profile
SHAKE_SPEED = 0.5  # m/s, peak
HOLD_TOL = 0.005  # m: leg centre in the palm frame while lifting and holding
SHAKE_TOL = 0.010  # m: leg centre in the palm frame while shaken


class Bench(HandBench):
    """The hand test bench, plus which fingers touch the leg."""

    def fingers_touching_leg(self) -> set[str]:
        """Fingers (names.FINGERS) with a contact on the leg, read from data.contact."""
        touching = set()
        for contact in self.data.contact[: self.data.ncon]:
            geoms = {contact.geom1, contact.geom2}
            if self.leg_geom not in geoms:
                continue
            other = (geoms - {self.leg_geom}).pop()
            body = self.model.body(self.model.geom_bodyid[other])
            for finger in names.FINGERS:
                if body.name in names.finger_bodies("l", finger):
                    touching.add(finger)
        return touching


@pytest.fixture
def held() -> tuple[Bench, np.ndarray]:
    """A bench with the leg grasped on the table; the leg's position in the palm after closing."""
    bench = Bench()
    bench.grasp()
    return bench, bench.leg_in_palm()


def test_open_hand_does_not_disturb_leg_on_descent() -> None:
    bench = Bench()
    start = bench.data.xpos[bench.leg].copy()
    bench.descend_to_leg()
    assert np.linalg.norm(bench.data.xpos[bench.leg] - start) < 1e-3
    assert bench.fingers_touching_leg() == set()


def test_closing_touches_the_leg_with_thumb_and_fingers(held: tuple[Bench, np.ndarray]) -> None:
    bench, in_palm = held
    assert {"thumb", "f1", "f2"} <= bench.fingers_touching_leg()
    # the leg sits centred between the fingers, on the grasp site within 5 mm
    site = np.array([0.0, 0.0, spec.GRASP_SITE_FROM_FLANGE])
    assert np.linalg.norm(in_palm - site) < 0.005


def test_lift_and_hold_keeps_leg_in_hand(held: tuple[Bench, np.ndarray]) -> None:
    """Lift 20 cm then hold 1 s: the leg stays within 5 mm of where it sat after closing."""
    bench, in_palm = held
    start_z = bench.data.xpos[bench.leg][2]
    palm_z = bench.data.xpos[bench.palm][2]
    drift: list[float] = []
    bench.on_step.append(lambda: drift.append(float(np.linalg.norm(bench.leg_in_palm() - in_palm))))
    bench.move(2, LIFT, LIFT_SPEED)
    bench.run(1.0)
    assert max(drift) < HOLD_TOL, f"max drift {max(drift) * 1000:.2f} mm"
    palm_rise = bench.data.xpos[bench.palm][2] - palm_z
    assert palm_rise > LIFT - 0.01  # the bench really lifted
    assert bench.data.xpos[bench.leg][2] - start_z == pytest.approx(palm_rise, abs=HOLD_TOL)
    assert len(bench.fingers_touching_leg()) >= 2
    assert all(w.number == 0 for w in bench.data.warning)


def test_lifted_leg_survives_shaking(held: tuple[Bench, np.ndarray]) -> None:
    """Shaken back and forth along x and y at 0.5 m/s peak: drift under 1 cm, still held."""
    bench, in_palm = held
    bench.move(2, LIFT, LIFT_SPEED)
    drift: list[float] = []
    bench.on_step.append(lambda: drift.append(float(np.linalg.norm(bench.leg_in_palm() - in_palm))))
    for axis in (0, 1):
        for delta in (0.1, -0.2, 0.1):
            bench.move(axis, delta, SHAKE_SPEED)
    bench.run(0.5)
    assert max(drift) < SHAKE_TOL, f"max drift {max(drift) * 1000:.2f} mm"
    assert {"thumb"} < bench.fingers_touching_leg()
    assert bench.data.xpos[bench.leg][2] > spec.TABLE_TOP_Z + LIFT - SHAKE_TOL


def test_opening_releases_leg_onto_table(held: tuple[Bench, np.ndarray]) -> None:
    bench, _ = held
    bench.move(2, 0.05, LIFT_SPEED)
    bench.command_hand(spec.HAND_OPEN_CTRL)
    bench.run(1.0)
    assert bench.fingers_touching_leg() == set()
    assert bench.data.xpos[bench.leg][2] == pytest.approx(spec.GRASP_HEIGHT, abs=2e-3)


class ArmRig:
    """The full scene driven by a plain mink IK on the left grasp site (50 Hz, min-jerk paths).

    A measuring rig for the model (can the real arm and hand do the task?), not the project's
    controller: it integrates IK on its own configuration and sends it as position targets.
    """

    def __init__(self) -> None:
        import mink

        self.mink = mink
        self.layout = SceneLayout()
        self.model = build_model(self.layout)
        self.data = mujoco.MjData(self.model)
        mujoco.mj_resetDataKeyframe(self.model, self.data, self.model.key(names.HOME_KEY).id)
        mujoco.mj_forward(self.model, self.data)
        self.config = mink.Configuration(self.model, self.data.qpos.copy())
        self.task = mink.FrameTask(names.grasp_site("l"), "site", 1.0, 0.5)
        self.posture = mink.PostureTask(self.model, cost=1e-3)
        self.posture.set_target(self.data.qpos.copy())
        self.limits = [mink.ConfigurationLimit(self.model)]
        self.arm_q = [self.model.joint(j).qposadr[0] for j in names.arm_joints("l")]
        self.arm_a = [self.model.actuator(a).id for a in names.arm_actuators("l")]
        self.hand_a = [self.model.actuator(a).id for a in names.hand_actuators("l")]
        self.on_tick: list = []

    @staticmethod
    def top_down(yaw: float) -> np.ndarray:
        y = np.array([np.cos(yaw), np.sin(yaw), 0.0])
        z = np.array([0.0, 0.0, -1.0])
        return np.column_stack([np.cross(y, z), y, z])

    def goto(self, position: list[float], yaw: float, speed: float = 0.3) -> None:
        mink = self.mink
        start = self.config.get_transform_frame_to_world(names.grasp_site("l"), "site")
        p0, r0 = start.translation().copy(), start.rotation()
        r1 = mink.SO3.from_matrix(self.top_down(yaw))
        ticks = max(round(1.875 * np.linalg.norm(np.subtract(position, p0)) / speed / 0.02), 15)
        for k in range(1, ticks + 11):
            s = min(k / ticks, 1.0)
            s = 10 * s**3 - 15 * s**4 + 6 * s**5
            pose = mink.SE3.from_rotation_and_translation(
                r0.interpolate(r1, s), p0 + s * (np.asarray(position) - p0)
            )
            self.task.set_target(pose)
            for _ in range(2):
                vel = mink.solve_ik(
                    self.config, [self.task, self.posture], 0.02, "daqp", 1e-3, limits=self.limits
                )
                self.config.integrate_inplace(vel, 0.02)
            self.data.ctrl[self.arm_a] = self.config.q[self.arm_q]
            for _ in range(10):
                mujoco.mj_step(self.model, self.data)
            for callback in self.on_tick:
                callback()

    def move_person_hand(self, goal: np.ndarray, duration: float) -> None:
        """Minimum-jerk motion of the person's mocap hand to ``goal`` (the arm holds still)."""
        mocap = int(self.model.body_mocapid[self.model.body(names.HUMAN_MOCAP_BODY).id])
        start = self.data.mocap_pos[mocap].copy()
        steps = round(duration / self.model.opt.timestep)
        for i in range(1, steps + 1):
            s = i / steps
            self.data.mocap_pos[mocap] = start + (10 * s**3 - 15 * s**4 + 6 * s**5) * (goal - start)
            mujoco.mj_step(self.model, self.data)

    def hand_command(self, ctrl: tuple[float, ...], wait: float) -> None:
        self.data.ctrl[self.hand_a] = ctrl
        for _ in range(round(wait / self.model.opt.timestep)):
            mujoco.mj_step(self.model, self.data)


@pytest.mark.slow
@pytest.mark.parametrize("leg", [0, 3])
def test_arm_grasps_leg_and_hands_it_to_the_palm(leg: int) -> None:
    """Grasp a default leg top-down, carry it at 0.3 m/s, release it above the human palm:
    held in the hand all the way (drift < 5 mm), then resting on the palm."""
    rig = ArmRig()
    model, data = rig.model, rig.data
    sensor = HandSensor(model, "l")
    x, y, yaw = rig.layout.legs[leg]
    leg_body = model.body(names.leg_body(leg)).id
    palm = model.body(names.hand_body("l")).id

    def in_palm() -> np.ndarray:
        rot = data.xmat[palm].reshape(3, 3)
        return rot.T @ (data.xpos[leg_body] - data.xpos[palm])

    rig.goto([x, y, spec.GRASP_HEIGHT + 0.08], yaw)
    rig.goto([x, y, spec.GRASP_HEIGHT], yaw, speed=0.1)
    assert np.linalg.norm(data.xpos[leg_body][:2] - [x, y]) < 2e-3  # the descent did not push it
    rig.hand_command(spec.HAND_CLOSED_CTRL, spec.HAND_CLOSE_TIME)
    assert sensor.grasped_leg(data) == leg
    start = in_palm()
    record: list[tuple[int | None, float]] = []
    rig.on_tick.append(
        lambda: record.append((sensor.grasped_leg(data), np.linalg.norm(in_palm() - start)))
    )
    hx, hy, hz = rig.layout.handover
    rig.goto([x, y, spec.GRASP_HEIGHT + 0.15], yaw)
    # the person holds out the palm once the leg is up: the mocap hand moves in (palm up)
    rig.move_person_hand(np.array([hx, hy, hz]) - model.site(names.HUMAN_PALM_SITE).pos, 2.0)
    # the leg goes down along x: between the palm's two rims (along the person's fingers)
    rig.goto([hx, hy, spec.GRASP_HEIGHT + 0.15], 0.0)
    rig.goto([hx, hy, hz + 0.012 + 0.045], 0.0, speed=0.15)
    assert all(held == leg for held, _ in record)
    assert max(d for _, d in record) < 0.005
    rig.on_tick.clear()
    rig.hand_command(spec.HAND_OPEN_CTRL, spec.HAND_OPEN_TIME)
    rig.goto([hx, hy, hz + 0.15], 0.0)
    rig.hand_command(spec.HAND_OPEN_CTRL, 1.0)
    palm_site = data.site(names.HUMAN_PALM_SITE).xpos
    # the leg lies on the palm: its axis one radius above the palm surface, centred on it
    assert data.xpos[leg_body][2] - palm_site[2] == pytest.approx(spec.LEG_RADIUS, abs=2e-3)
    assert np.linalg.norm(data.xpos[leg_body][:2] - palm_site[:2]) < 0.03
    assert sensor.hand(data) is Hand.FREE
    assert all(w.number == 0 for w in data.warning)
