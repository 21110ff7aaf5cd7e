"""The person's hand: a mocap body moved along minimum-jerk paths at every control tick.

:class:`HumanHand` plugs into :class:`robin_sim.control.simulator.Simulator` as a controller. It
moves the
mocap body ``human_hand`` between poses: resting at the person's side, pointing at a leg or a
table spot, holding the palm out (palm up) for "give me", and taking a delivered leg away: the
palm carries the leg off, tips it into the bin beside the table and comes back. The leg is moved
by contact only (the palm supports it; nothing is attached or written into the leg's state).
"""

from __future__ import annotations

from collections.abc import Sequence

import mink
import mujoco
import numpy as np

from robin_sim.control.simulator import Simulator
from robin_sim.control.trajectory import CartesianPath, pose, through
from robin_sim.model import names, robot_spec

HAND_SPEED = 0.35  # m/s peak, free hand
CARRY_SPEED = 0.25  # m/s peak while a leg lies on the palm
TIP_ANGLE = 2.0  # rad the palm rolls to tip a leg off
# A palm held out under the robot's hand first draws back and down, so it never sweeps into a
# held leg on its way to point somewhere.
POINT_RETREAT = np.array([0.15, 0.0, -0.06])  # m
SLIDE_IN = 0.2  # m: the palm slides in under a held leg from this far on the person's side
# m/s peak of a palm carrying a leg upwards: the physics palm, welded to the mocap frame, trails
# it by about 29 ms of its speed (7 mm rising at CARRY_SPEED), so the leg on it sank that far
# into the figure's palm, which hangs from the mocap frame; at this speed 2-3 mm
CARRY_RISE_SPEED = 0.08


class HumanHand:
    """Moves the person's mocap hand; call :meth:`attach` to drive it from a simulator."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self.model, self.data = model, data
        body_id = model.body(names.HUMAN_MOCAP_BODY).id
        self.mocap_id = int(model.body_mocapid[body_id])
        if self.mocap_id < 0:
            raise ValueError(f"body {names.HUMAN_MOCAP_BODY!r} is not a mocap body")
        self.rest_pose = self.pose()
        site = model.site(names.HUMAN_PALM_SITE)
        self.palm_offset = model.site_pos[site.id].copy()  # palm centre in the hand frame
        self._path: CartesianPath | None = None
        self._start = 0.0

    def attach(self, sim: Simulator) -> None:
        """Drive the hand at every control tick of ``sim``."""
        sim.add_controller(lambda s: self.update(s.time + s.control_dt))

    def pose(self) -> mink.SE3:
        """The hand's current (mocap) pose."""
        return pose(self.data.mocap_pos[self.mocap_id], self.data.mocap_quat[self.mocap_id])

    def palm_centre(self) -> np.ndarray:
        """World position of the palm centre (``human_palm_site``)."""
        return self.data.site(names.HUMAN_PALM_SITE).xpos.copy()

    def busy(self, now: float) -> bool:
        """True while a motion is under way."""
        return self._path is not None and now < self._start + self._path.duration

    def follow(self, waypoints: Sequence[mink.SE3], now: float, speed: float = HAND_SPEED) -> float:
        """Move through ``waypoints`` starting at the current pose; returns the duration."""
        self._path = through([self.pose(), *waypoints], speed)
        self._start = now
        return self._path.duration

    def update(self, now: float) -> None:
        """Place the mocap body where the current motion is at ``now``."""
        if self._path is None:
            return
        target = self._path.sample(now - self._start)
        self.data.mocap_pos[self.mocap_id] = target.translation()
        self.data.mocap_quat[self.mocap_id] = target.rotation().wxyz
        if now >= self._start + self._path.duration:  # arrived: idle until the next motion
            self._path = None

    # --- gestures and moves ------------------------------------------------------------------
    def hand_pose_for_palm(self, palm_centre: np.ndarray) -> mink.SE3:
        """The palm-up hand pose whose palm centre lies at ``palm_centre``."""
        return pose(np.asarray(palm_centre, float) - self.palm_offset)

    def rest(self, now: float, speed: float = HAND_SPEED) -> float:
        """Back to the rest pose at the person's side."""
        return self.follow([self.rest_pose], now, speed)

    def point_at(
        self,
        position: np.ndarray,
        now: float,
        draw_back_first: bool = False,
        speed: float = HAND_SPEED,
    ) -> float:
        """Hold the hand above ``position`` (the pointing gesture's place); returns the time.

        ``draw_back_first``: start by drawing back and down (:data:`POINT_RETREAT`).
        """
        waypoints = [pose(np.asarray(position, float) + robot_spec.POINT_OFFSET)]
        if draw_back_first:
            waypoints.insert(0, pose(self.pose().translation() + POINT_RETREAT))
        return self.follow(waypoints, now, speed)

    def hold_out_palm(
        self, palm_centre: np.ndarray, now: float, speed: float = HAND_SPEED
    ) -> float:
        """Hold the palm out, palm up, with its centre at ``palm_centre`` ("give me")."""
        goal = self.hand_pose_for_palm(palm_centre)
        high = goal.translation() + np.array([0.0, 0.0, 0.05])
        return self.follow([pose(high), goal], now, speed)

    def slide_under(self, palm_centre: np.ndarray, now: float, speed: float = HAND_SPEED) -> float:
        """Bring the palm back under something held above ``palm_centre``: in from the
        person's side 4 cm below, then up into place (never from above). A hand raised on
        the person's side (a thumb shown drawn back) comes down there first, so its fingers
        never sweep down past the held leg's end."""
        goal = self.hand_pose_for_palm(palm_centre)
        low = goal.translation() + np.array([0.0, 0.0, -0.04])
        entry = low + np.array([SLIDE_IN, 0.0, 0.0])
        waypoints = [pose(entry), pose(low), goal]
        here = self.pose().translation()
        if here[0] >= entry[0] and here[2] > entry[2]:
            waypoints.insert(0, pose(np.array([here[0], here[1], entry[2]])))
        return self.follow(waypoints, now, speed)

    def withdraw(
        self,
        clear_x: float,
        now: float,
        raise_by: float = 0.0,
        speed: float = HAND_SPEED,
        aside: float = 0.0,
    ) -> float:
        """Draw the hand straight back (+x, towards the person) to ``clear_x``, out of the
        robot's way, then raise it ``raise_by`` m and move it ``aside`` m along y, at
        ``speed`` (:data:`CARRY_SPEED` with a leg on the palm, which also rises at
        :data:`CARRY_RISE_SPEED`); returns the duration (0 if it is there already)."""
        here = self.pose()
        if here.translation()[0] >= clear_x - 1e-6:
            return 0.0
        back = here.translation().copy()
        back[0] = clear_x
        waypoints = [mink.SE3.from_rotation_and_translation(here.rotation(), back)]
        if raise_by <= 0.0 and aside == 0.0:
            return self.follow(waypoints, now, speed)
        up = back + np.array([0.0, aside, raise_by])
        raised = mink.SE3.from_rotation_and_translation(here.rotation(), up)
        draw = through([here, *waypoints], speed)
        rise_speed = CARRY_RISE_SPEED if speed <= CARRY_SPEED and raise_by > 0.0 else speed
        rise = through([draw.end, raised], rise_speed)
        self._path = CartesianPath(draw.segments + rise.segments)
        self._start = now
        return self._path.duration

    def take_away(self, bin_position: np.ndarray, now: float) -> float:
        """Carry what lies on the palm to the bin, tip it in, and go back to rest.

        The palm lowers 3 cm (clear of the robot's fingers), moves straight along +x (along a
        leg lying in the handover direction, so the leg slides nowhere and does not roll) to
        the bin's x, then rolls about x so the leg rolls off towards -y into the bin.
        """
        start = self.pose().translation()
        lowered = start + np.array([0.0, 0.0, -0.03])
        over_bin = np.array([bin_position[0], lowered[1], lowered[2]])
        tipped = mink.SE3.from_rotation_and_translation(
            mink.SO3.from_x_radians(TIP_ANGLE), over_bin
        )
        carry = through([self.pose(), pose(lowered), pose(over_bin)], CARRY_SPEED)
        tip = through([carry.end, tipped], HAND_SPEED, 1.5)
        back = through([tip.end, self.rest_pose], HAND_SPEED)
        self._path = CartesianPath(carry.segments + tip.segments + back.segments)
        self._start = now
        return self._path.duration
