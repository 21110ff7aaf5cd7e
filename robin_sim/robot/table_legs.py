"""``TableLegs``: the table legs as physics has them, read from MuJoCo's state.

Where each leg lies and along which axis, how fast it moves, whether the robot can pick it up
where it lies, and the leg the hand is nearest. Laying a leg at its layout pose
(:meth:`TableLegs.lay`) is a scene change (a new table, or the person putting a leg back),
never part of an action: the robot's actions move legs only through contacts.
"""

from __future__ import annotations

import mujoco
import numpy as np

from robin_sim.control.simulator import Simulator
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import SceneLayout
from robin_sim.robot.targets import fingers_blocked

ON_TABLE_TOLERANCE = 0.01  # m: a leg's centre this close to the grasp height lies on the table
FLAT_AXIS_Z = 0.1  # an axis with |z| below this lies flat (about 6 degrees from horizontal)
AT_REST_SPEED = 0.01  # m/s: a leg slower than this is at rest


class TableLegs:
    """The layout's legs in ``sim`` (one free body each, named by :mod:`robin_sim.model.names`)."""

    def __init__(self, sim: Simulator, layout: SceneLayout) -> None:
        self.sim, self.layout = sim, layout
        model = sim.model
        self.count = len(layout.legs)
        self._bodies = [model.body(names.leg_body(k)).id for k in range(self.count)]
        joints = [model.joint(names.leg_joint(k)).id for k in range(self.count)]
        self._qadr = [int(model.jnt_qposadr[j]) for j in joints]
        self._dofadr = [int(model.jnt_dofadr[j]) for j in joints]

    def position(self, leg: int) -> np.ndarray:
        """Centre of leg ``leg``, m (world frame)."""
        return self.sim.data.xpos[self._bodies[leg]].copy()

    def positions(self) -> np.ndarray:
        """Centres of all legs, shape (legs, 3)."""
        return np.array([self.position(k) for k in range(self.count)])

    def axis(self, leg: int) -> np.ndarray:
        """Unit vector along leg ``leg``'s axis (world frame, measured)."""
        return self.sim.data.xmat[self._bodies[leg]].reshape(3, 3)[:, 0].copy()

    def speed(self, leg: int) -> float:
        """Linear speed of leg ``leg``'s centre, m/s."""
        adr = self._dofadr[leg]
        return float(np.linalg.norm(self.sim.data.qvel[adr : adr + 3]))

    def on_table(self, leg: int) -> bool:
        """Leg ``leg``'s centre is at the height of a leg lying on the table top."""
        return abs(self.position(leg)[2] - spec.GRASP_HEIGHT) < ON_TABLE_TOLERANCE

    def out_of_reach(self, leg: int) -> bool:
        """Leg ``leg`` lies on the table top where the arm cannot reach it (an action on it
        would fail: e.g. pushed there by a wrong move a person let stand)."""
        return self.on_table(leg) and not spec.in_left_reach(*self.position(leg)[:2])

    def graspable(self, leg: int) -> bool:
        """Leg ``leg`` lies flat on the table top inside the arm's reach, at rest, and no other
        leg lies where the open fingers come down around it (:func:`fingers_blocked`)."""
        centre, axis = self.position(leg), self.axis(leg)
        flat = abs(float(axis[2])) < FLAT_AXIS_Z
        resting = self.speed(leg) < AT_REST_SPEED
        others = [(self.position(k), self.axis(k)) for k in range(self.count) if k != leg]
        free = not fingers_blocked(centre, axis, others)
        return self.on_table(leg) and flat and resting and spec.in_left_reach(*centre[:2]) and free

    def grasp_place(self, leg: int) -> tuple[np.ndarray, np.ndarray]:
        """Centre and axis of ``leg`` where it lies; off the table: its layout place."""
        if self.on_table(leg):
            return self.position(leg), self.axis(leg)
        x, y, yaw = self.layout.legs[leg]
        return np.array([x, y, spec.GRASP_HEIGHT]), np.array([np.cos(yaw), np.sin(yaw), 0.0])

    def nearest(self) -> int:
        """The leg on the table nearest the robot's hand (any leg's layout place if none is
        left on the table)."""
        pool = [k for k in range(self.count) if self.on_table(k)] or range(self.count)
        site = self.sim.site_pose().translation()
        return min(pool, key=lambda k: float(np.linalg.norm(self.grasp_place(k)[0] - site)))

    def lay(self, leg: int) -> None:
        """Put leg ``leg`` at rest at its layout pose (a scene change, never in an action)."""
        x, y, yaw = self.layout.legs[leg]
        z = spec.TABLE_TOP_Z + spec.LEG_RADIUS
        q, v = self._qadr[leg], self._dofadr[leg]
        data = self.sim.data
        data.qpos[q : q + 7] = [x, y, z, np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)]
        data.qvel[v : v + 6] = 0.0
        mujoco.mj_forward(self.sim.model, data)


__all__ = ["TableLegs"]
