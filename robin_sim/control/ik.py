"""Arm inverse kinematics with mink and the joint-space plans it produces.

The arm is driven by differential IK (mink): a :class:`mink.FrameTask` on the grasp site, a
:class:`mink.PostureTask` towards the home keyframe, :class:`mink.ConfigurationLimit` and
:class:`mink.VelocityLimit`, solver ``daqp``. The IK integrates on its own configuration at the
control rate (not on the measured joints); its joint values become position-actuator targets.
A whole Cartesian path is rolled out ahead of execution into a :class:`JointPlan`, so a target
out of reach is refused before anything moves, the motion is exactly reproducible, and a
rejected motion can be undone by replaying its commands backwards.

Only the active arm's seven joints move: the IK runs on a kinematic copy of the model that keeps
those joints only (:func:`arm_kinematic_model`, seven DoF, ≈ 40 % faster per solve); on a full
model the other DoFs are held by mink's :class:`mink.DofFreezingTask` as equality constraints.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import mink
import mujoco
import numpy as np

from robin_sim.control.trajectory import CartesianPath
from robin_sim.model import names
from robin_sim.model.names import Side

IK_SOLVER = "daqp"
POSITION_TOLERANCE = 0.01  # m; a path end the IK misses by more is out of reach
ORIENTATION_TOLERANCE = 0.15  # rad; a path end the IK turns short of by more is out of reach
DEFAULT_VELOCITY_LIMIT = 1.5  # rad/s, used for joints without a given limit


def arm_kinematic_model(spec: mujoco.MjSpec, side: Side) -> mujoco.MjModel:
    """A copy of ``spec`` compiled with the arm joints of ``side`` only (the rest welded).

    Actuators, equalities, tendons, sensors, contact pairs/excludes and keyframes are removed
    (they may refer to deleted joints); geometry and kinematics are unchanged.
    """
    kept = set(names.arm_joints(side))
    copy = spec.copy()
    for group in (copy.actuators, copy.equalities, copy.tendons, copy.sensors, copy.keys):
        for element in list(group):
            copy.delete(element)
    for group in (copy.pairs, copy.excludes):
        for element in list(group):
            copy.delete(element)
    for joint in list(copy.joints):
        if joint.name not in kept:
            copy.delete(joint)
    for body in copy.bodies:  # a sleep policy needs a free body; kinematics needs no sleep
        body.sleep = mujoco.mjtSleepPolicy.mjSLEEP_AUTO
    copy.option.enableflags &= ~int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    return copy.compile()


def home_arm_q(model: mujoco.MjModel, side: Side) -> np.ndarray:
    """The arm joint values of the ``home`` keyframe (zeros if the model has none)."""
    key_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, names.HOME_KEY)
    adr = [model.jnt_qposadr[model.joint(j).id] for j in names.arm_joints(side)]
    if key_id < 0:
        return np.zeros(len(adr))
    return model.key_qpos[key_id, adr].copy()


@dataclass(frozen=True)
class JointPlan:
    """Arm joint targets, one row per control tick, and how well the path end was reached."""

    q: np.ndarray  # (ticks, 7)
    dt: float
    position_error: float  # m, grasp site vs path end after the last tick
    orientation_error: float  # rad

    @property
    def duration(self) -> float:
        """Seconds the plan takes to play."""
        return len(self.q) * self.dt

    @property
    def reaches_goal(self) -> bool:
        """True when the path end is met within both tolerances (position and orientation)."""
        return (
            self.position_error <= POSITION_TOLERANCE
            and self.orientation_error <= ORIENTATION_TOLERANCE
        )

    def prefix(self, fraction: float) -> JointPlan:
        """The first ``fraction`` of the plan (at least one tick)."""
        ticks = max(1, round(len(self.q) * min(max(fraction, 0.0), 1.0)))
        return JointPlan(self.q[:ticks], self.dt, self.position_error, self.orientation_error)

    def reversed_from(self, start_q: np.ndarray) -> JointPlan:
        """Commands retracing this plan backwards, ending at ``start_q`` (the undo motion)."""
        back = np.vstack([self.q[::-1][1:], start_q[None, :]])
        return JointPlan(back, self.dt, 0.0, 0.0)


class ArmIK:
    """Differential IK for one arm's grasp site on its own configuration."""

    def __init__(
        self,
        model: mujoco.MjModel,
        side: Side = names.ACTIVE_SIDE,
        velocity_limits: Mapping[str, float] | None = None,
        posture_q: np.ndarray | None = None,
        position_cost: float = 1.0,
        orientation_cost: float = 0.5,
        posture_cost: float = 1e-2,
    ) -> None:
        self.model = model
        self.side = side
        self.joints = names.arm_joints(side)
        self.site = names.grasp_site(side)
        self._qadr = np.array([model.jnt_qposadr[model.joint(j).id] for j in self.joints])
        self.configuration = mink.Configuration(model)
        self.frame_task = mink.FrameTask(
            self.site,
            "site",
            position_cost=position_cost,
            orientation_cost=orientation_cost,
            lm_damping=1.0,
        )
        self.posture_task = mink.PostureTask(model, cost=posture_cost)
        limits = dict.fromkeys(self.joints, DEFAULT_VELOCITY_LIMIT) | dict(velocity_limits or {})
        self.limits = [mink.ConfigurationLimit(model), mink.VelocityLimit(model, limits)]
        arm_dofs = {int(model.jnt_dofadr[model.joint(j).id]) for j in self.joints}
        frozen = [i for i in range(model.nv) if i not in arm_dofs]
        self.constraints = [mink.DofFreezingTask(model, frozen)] if frozen else []
        q0 = self._full_q(home_arm_q(model, side) if posture_q is None else posture_q)
        self.configuration.update(q0)
        self.posture_task.set_target(q0)
        self.solves = 0

    def _full_q(self, arm_q: np.ndarray) -> np.ndarray:
        q = self.model.qpos0.copy()
        q[self._qadr] = arm_q
        return q

    @property
    def q(self) -> np.ndarray:
        """The IK's current arm joint values (seven)."""
        return self.configuration.q[self._qadr].copy()

    def reset(self, arm_q: np.ndarray) -> None:
        """Put the IK configuration at ``arm_q`` (e.g. the measured joints at start)."""
        q = self.configuration.q.copy()
        q[self._qadr] = arm_q
        self.configuration.update(q)

    def site_pose(self) -> mink.SE3:
        """The grasp site's pose in the IK configuration."""
        return self.configuration.get_transform_frame_to_world(self.site, "site")

    def step(self, target: mink.SE3, dt: float) -> np.ndarray:
        """One IK solve towards ``target`` and an integration over ``dt``; the new arm q."""
        self.frame_task.set_target(target)
        velocity = mink.solve_ik(
            self.configuration,
            [self.frame_task, self.posture_task],
            dt,
            IK_SOLVER,
            limits=self.limits,
            constraints=self.constraints,
        )
        self.configuration.integrate_inplace(velocity, dt)
        self.solves += 1
        return self.q

    def errors(self, target: mink.SE3) -> tuple[float, float]:
        """Position (m) and orientation (rad) error of the current configuration."""
        pose = self.site_pose()
        position = float(np.linalg.norm(pose.translation() - target.translation()))
        angle = float(np.linalg.norm((pose.rotation().inverse() @ target.rotation()).log()))
        return position, angle

    def plan(self, path: CartesianPath, dt: float, settle: float = 0.4) -> JointPlan:
        """Roll the IK along ``path`` (plus ``settle`` s at its end) from the current q.

        The IK configuration ends at the plan's last q; call :meth:`reset` to discard a plan.
        """
        ticks = int(np.ceil((path.duration + settle) / dt))
        rows = np.empty((ticks, len(self.joints)))
        for i in range(ticks):
            rows[i] = self.step(path.sample((i + 1) * dt), dt)
        position, angle = self.errors(path.end)
        return JointPlan(rows, dt, position, angle)
