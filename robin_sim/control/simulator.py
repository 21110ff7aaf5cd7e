"""The control loop (:class:`Simulator`) and the hand's grip controller.

The :class:`Simulator` owns the MuJoCo model and data, the active arm's IK
(:mod:`robin_sim.control.ik`) and the :class:`HandController`, and steps physics at its 2 ms
step while control runs at its own, slower rate (default 50 Hz). Hooks let other parts join
every control tick: controllers before physics (e.g. the person's hand) and observers after it
(e.g. a video recorder).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import mink
import mujoco
import numpy as np

from robin_sim.control.ik import ArmIK, JointPlan, arm_kinematic_model, home_arm_q
from robin_sim.control.trajectory import CartesianPath, min_jerk
from robin_sim.model import names
from robin_sim.model.names import Side


@dataclass(frozen=True)
class HandTargets:
    """Open and closed actuator targets of one hand (actuator order of names.hand_actuators)."""

    open: np.ndarray
    closed: np.ndarray


class HandController:
    """Opens and closes the fingers along minimum-jerk ramps of their position targets.

    The closed targets lie past the point where the fingers meet a leg (``robot_spec``), so a
    closing hand stops at the leg and squeezes it with the position error times the actuator
    gain, capped by each actuator's force range (the grip force limit). Closing is done when
    the fingers have stopped moving (:func:`robin_sim.robot.motion.fingers_settled`).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        targets: HandTargets,
        side: Side = names.ACTIVE_SIDE,
    ) -> None:
        self.model, self.data, self.targets = model, data, targets
        self.actuators = np.array([model.actuator(a).id for a in names.hand_actuators(side)])
        joints = model.actuator_trnid[self.actuators, 0]
        self.joint_qadr = model.jnt_qposadr[joints]
        self.joint_dofs = model.jnt_dofadr[joints]
        self._low, self._high = model.actuator_ctrlrange[self.actuators].T
        distal = {names.finger_joints(side, f)[1] for f in names.FINGERS if f != names.THUMB}
        self._distal = np.array([a in distal for a in names.hand_actuators(side)])
        self._from = self.command
        self._to = self._from.copy()
        self._start = 0.0
        self._duration = 1e-9
        self._active = False

    @property
    def command(self) -> np.ndarray:
        """The current finger actuator targets."""
        return self.data.ctrl[self.actuators].copy()

    def move_to(self, goal: np.ndarray, now: float, duration: float) -> None:
        """Ramp the finger targets to ``goal`` from time ``now`` over ``duration`` s."""
        self._from, self._to = self.command, np.clip(np.asarray(goal, float), self._low, self._high)
        self._start, self._duration, self._active = now, max(duration, 1e-9), True

    def close(self, now: float, duration: float = 0.8) -> None:
        """Start closing the fingers (they stop where they meet an object)."""
        self.move_to(self.targets.closed, now, duration)

    def open(self, now: float, duration: float = 0.6) -> None:
        """Start opening the fingers fully."""
        self.move_to(self.targets.open, now, duration)

    def blend(self, amount: float) -> np.ndarray:
        """Targets ``amount`` of the way from open (0) to closed (1)."""
        return self.targets.open + amount * (self.targets.closed - self.targets.open)

    def eased(self) -> np.ndarray:
        """Current targets with the two fingers' distal joints at their open targets: the
        fingertips visibly ease while the proximal joints and the thumb keep squeezing."""
        return np.where(self.distal, self.targets.open, self.command)

    @property
    def distal(self) -> np.ndarray:
        """Mask over the hand actuators: the two fingers' distal joints (not the thumb's)."""
        return self._distal.copy()

    def busy(self, now: float) -> bool:
        """True while the ramp is still running."""
        return now < self._start + self._duration

    def update(self, now: float) -> None:
        """Write this tick's finger targets into ``data.ctrl`` (nothing once a ramp is over)."""
        if not self._active:
            return
        s = min_jerk((now - self._start) / self._duration)
        self.data.ctrl[self.actuators] = self._from + s * (self._to - self._from)
        self._active = s < 1.0


TickCallback = Callable[["Simulator"], None]


class Simulator:
    """Model, data, the active arm's IK and hand controllers, and the control loop.

    One control tick (``control_dt``, default 20 ms = 50 Hz) runs the registered controllers
    (e.g. the person's hand), writes the arm's next planned joint targets and the finger
    targets, steps physics ``control_dt / timestep`` times, then calls the observers (e.g. a
    video recorder grabbing a frame when one is due). Nothing here draws random numbers: the
    same model, data and calls give bit-identical trajectories.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        hand_targets: HandTargets,
        data: mujoco.MjData | None = None,
        *,
        spec: mujoco.MjSpec | None = None,
        side: Side = names.ACTIVE_SIDE,
        control_dt: float = 0.02,
        velocity_limits: Mapping[str, float] | None = None,
    ) -> None:
        self.model, self.side = model, side
        if data is None:
            data = mujoco.MjData(model)
            key_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, names.HOME_KEY)
            if key_id >= 0:
                mujoco.mj_resetDataKeyframe(model, data, key_id)
            mujoco.mj_forward(model, data)
        self.data = data
        self.substeps = max(1, round(control_dt / model.opt.timestep))
        self.control_dt = self.substeps * model.opt.timestep
        for arm_side in names.SIDES:  # both arms hold where they are
            for joint in names.arm_joints(arm_side):
                if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, joint) >= 0:
                    data.actuator(joint).ctrl[0] = data.joint(joint).qpos[0]
        self.arm_actuators = np.array([model.actuator(a).id for a in names.arm_actuators(side)])
        self._arm_qadr = np.array(
            [model.jnt_qposadr[model.joint(j).id] for j in names.arm_joints(side)]
        )
        ik_model = model if spec is None else arm_kinematic_model(spec, side)
        self.ik = ArmIK(ik_model, side, velocity_limits, posture_q=home_arm_q(model, side))
        self.ik.reset(self.arm_q)
        self.hand = HandController(model, data, hand_targets, side)
        self._plan: JointPlan | None = None
        self._plan_tick = 0
        self._controllers: list[TickCallback] = []
        self._observers: list[TickCallback] = []
        self._view_hooks: list[Callable[[], None]] = []  # before a render reads the state
        self.ticks = 0
        self.physics_seconds = 0.0  # wall time spent in mj_step (for benchmarks; not simulated)

    # --- state --------------------------------------------------------------------------------
    @property
    def time(self) -> float:
        """Simulated time in seconds."""
        return float(self.data.time)

    @property
    def arm_q(self) -> np.ndarray:
        """Measured arm joint values."""
        return self.data.qpos[self._arm_qadr].copy()

    @property
    def arm_command(self) -> np.ndarray:
        """The arm's current position targets."""
        return self.data.ctrl[self.arm_actuators].copy()

    def site_pose(self) -> mink.SE3:
        """Measured pose of the grasp site."""
        site = self.data.site(names.grasp_site(self.side))
        return mink.SE3.from_rotation_and_translation(
            mink.SO3.from_matrix(site.xmat.reshape(3, 3)), site.xpos.copy()
        )

    def commanded_site_pose(self) -> mink.SE3:
        """Pose of the grasp site at the arm's current targets (where the plans start)."""
        self.ik.reset(self.arm_command)
        return self.ik.site_pose()

    # --- hooks --------------------------------------------------------------------------------
    def add_controller(self, callback: TickCallback) -> Callable[[], None]:
        """Call ``callback(sim)`` at every tick before physics; returns a function removing it."""
        self._controllers.append(callback)
        return lambda: self._controllers.remove(callback)

    def add_observer(self, callback: TickCallback) -> Callable[[], None]:
        """Call ``callback(sim)`` at every tick after physics; returns a function removing it."""
        self._observers.append(callback)
        return lambda: self._observers.remove(callback)

    def add_view_hook(self, callback: Callable[[], None]) -> Callable[[], None]:
        """Call ``callback()`` whenever a render is about to read the state
        (:meth:`prepare_view`): for what only pictures show (the articulated person's body,
        which no physics touches); returns a function removing it."""
        self._view_hooks.append(callback)
        return lambda: self._view_hooks.remove(callback)

    def prepare_view(self) -> None:
        """Bring what only renders show up to date (every :meth:`add_view_hook` callback); a
        caller that captures or renders the state calls it first."""
        for callback in self._view_hooks:
            callback()

    # --- arm motion ---------------------------------------------------------------------------
    def plan(self, path: CartesianPath, settle: float = 0.4) -> JointPlan:
        """IK rollout of ``path`` from the current arm targets; nothing moves."""
        start = self.arm_command
        self.ik.reset(start)
        try:
            return self.ik.plan(path, self.control_dt, settle)
        finally:
            self.ik.reset(start)

    def play(self, plan: JointPlan) -> None:
        """Start sending ``plan``'s joint targets, one row per tick."""
        self._plan, self._plan_tick = plan, 0

    def halt(self) -> None:
        """Stop playing the current plan: the arm's targets become where it is now, so it
        brakes to a stop there (its damping sets the stopping distance)."""
        if self._plan is not None:
            self.data.ctrl[self.arm_actuators] = self.arm_q
            self.ik.reset(self.arm_q)
            self._plan = None

    @property
    def moving(self) -> bool:
        """True while a joint plan is being played."""
        return self._plan is not None

    # --- loop ---------------------------------------------------------------------------------
    def tick(self) -> None:
        """One control period: controllers, arm and finger targets, physics, observers."""
        for callback in tuple(self._controllers):
            callback(self)
        if self._plan is not None:
            self.data.ctrl[self.arm_actuators] = self._plan.q[self._plan_tick]
            self._plan_tick += 1
            if self._plan_tick >= len(self._plan.q):
                self.ik.reset(self._plan.q[-1])
                self._plan = None
        self.hand.update(self.time)
        began = time.perf_counter()
        for _ in range(self.substeps):
            mujoco.mj_step(self.model, self.data)
        self.physics_seconds += time.perf_counter() - began
        self.ticks += 1
        for callback in tuple(self._observers):
            callback(self)

    def run(self, seconds: float) -> None:
        """Run the control loop for ``seconds`` of simulated time."""
        for _ in range(max(0, round(seconds / self.control_dt))):
            self.tick()

    def step_until(self, done: Callable[[Simulator], bool], timeout: float) -> bool:
        """Tick until ``done(sim)`` holds (True) or ``timeout`` s have passed (False)."""
        end = self.time + timeout
        while self.time < end - 1e-9:
            self.tick()
            if done(self):
                return True
        return False

    def execute(self, plan: JointPlan) -> None:
        """Play ``plan`` to its end."""
        self.play(plan)
        while self.moving:
            self.tick()
