"""The person's right hand fitted around what is near it: a received leg, Robin's fingers.

The figure's hand is kinematic (its geoms never collide), so a pose written as the library has
it can pass through a leg lying on the collision palm or through Robin's fingers delivering
it. :class:`HandFit` changes a wanted hand (20 joint angles and the turn in the mocap frame)
just enough to keep clear of them:

* **the turn**: while a table leg lies on or comes down to the collision palm
  (``human_palm``, welded to the mocap frame), the hand turns palm up in the mocap frame, the
  visual palm under the leg where the physics palm carries it, turned :data:`HOLD_YAW` about
  the palm's normal: the leg lies along the mocap frame's x (the handover direction), and a
  hand along it put the forearm, which continues the hand, under the leg's end (23-45 mm
  into it); across the palm at this angle the forearm comes from the side, the leg diagonal
  over palm and fingers as a rod is held. The turn blends there between :data:`TURN_FAR` and
  :data:`TURN_NEAR` of the leg's distance to the collision palm;
* **the fingers**: each finger (and the thumb) takes the furthest of :data:`STEPS` along the
  way from the wanted angles to an open hand (flexion 0; the thumb as held out for "give me")
  and on to a finger bent back (:data:`EXTENDED`; the thumb swung out, :data:`THUMB_AWAY`),
  or last, curled (:data:`CURLS`), at which its geoms keep :data:`FINGER_CLEARANCE` from every
  leg and every geom of Robin's near it: the fingers close onto a leg's surface, not through it, and
  give way to Robin's.

Candidates are measured with ``mujoco.mj_geomDistance`` in a scratch ``MjData`` (the scene's
own kinematics stay untouched; the figure's finger frames live in ``model.body_quat``,
:mod:`robin_sim.model.person_joints`), all five fingers at once per step.
"""

from __future__ import annotations

import mujoco
import numpy as np

from pil.types import SIGN_OF, Gesture
from robin_sim.model import names
from robin_sim.model.geom_groups import body_geoms, category_geoms
from robin_sim.model.person_joints import axis_quats, figure, quat_products
from robin_sim.model.pose_library import load_library

FINGER_CLEARANCE = 0.002  # m kept between a finger and a leg or Robin's geoms
# m from a leg to the collision palm: at TURN_NEAR and closer the hand holds it (HOLD_TURN);
# from TURN_FAR on it keeps its own turn (a band of 1-4 cm turned it too late: fingers and
# palm 15-18 mm into a leg Robin lowered onto the palm)
TURN_NEAR, TURN_FAR = 0.04, 0.10
ABOVE = 0.7  # share of that distance upwards for a leg above the palm
NEAR = 0.03  # m: obstacles within this of the hand's bounding sphere are measured
# the way from the wanted finger (1) to the open finger (0) and on to a finger bent back (-1)
STEPS = (1.0, 0.8, 0.6, 0.4, 0.2, 0.0, -0.5, -1.0)
EXTENDED = (-0.35, 0.0, 0.0)  # rad: MCP, PIP, DIP of a finger bent back
# last resort, from the wanted finger towards a curled one: a pointing index reaching down to
# Robin's hand at the pointed leg (5 mm into its palm) curls away from it
CURLS = (0.5, 1.0)
CURLED = (1.4, 1.6, 1.0)  # rad: MCP, PIP, DIP
THUMB_AWAY = (-0.8, -0.3, 0.0, 0.0)  # rad: the thumb swung out, away from the palm
HOLD_YAW = np.radians(40.0)  # about the palm normal, the wrist towards the person's right
HOLD_TURN = np.array([np.cos(HOLD_YAW / 2), 0.0, 0.0, np.sin(HOLD_YAW / 2)])


class HandFit:
    """Fits the right hand's wanted angles and turn around legs and Robin (module doc)."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self.model, self.data = model, data
        self.scratch = mujoco.MjData(model)
        fig = figure()
        joints = names.person_hand_joints("r")
        self.low, self.high = fig.ranges(joints).T
        # per hand joint: its body (model id), base frame and axis; bodies in chain order
        self.joint_body = np.array([model.body(fig.joint(j).body).id for j in joints])
        self.axes = np.array([fig.joint(j).axis for j in joints])
        self.bodies = list(dict.fromkeys(self.joint_body.tolist()))
        self.base = np.array([fig.base_quat_of(model.body(b).name) for b in self.bodies])
        self.finger_of_joint = np.arange(20) // 4  # thumb 0, index 1 .. little 4
        self.finger_geoms = [
            body_geoms(model, (names.person_finger_bodies("r", f)[0],))
            for f in names.PERSON_HAND_FINGERS
        ]
        self.hand_body = model.body(names.person_hand_body("r")).id
        self.hand_base = fig.base_quat_of(names.person_hand_body("r"))  # the turn's base frame
        groups = category_geoms(model)
        self.legs = groups["legs"]
        self.obstacles = np.concatenate([groups["legs"], groups["robot"]])
        self.palm = model.geom(names.HUMAN_PALM_GEOM).id
        self.open_thumb = load_library().pose(SIGN_OF[Gesture.GIVE_ME])[:4]
        self._fromto = np.zeros(6)

    # --- the turn --------------------------------------------------------------------------
    def leg_distance(self) -> float:
        """Distance (m, up to :data:`TURN_FAR`) from the collision palm to the nearest table
        leg above it (the way between them mostly along the palm's normal: a leg coming down
        onto the palm or lying on it, also while the palm tips it off, not one beside it)."""
        best = TURN_FAR
        normal = self.scratch.geom_xmat[self.palm].reshape(3, 3)[:, 2]
        for leg in self.legs:
            gap = mujoco.mj_geomDistance(
                self.model, self.scratch, self.palm, int(leg), TURN_FAR, self._fromto
            )
            rise = float((self._fromto[3:] - self._fromto[:3]) @ normal)
            if gap < best and (gap <= 0.0 or rise >= ABOVE * gap):
                best = gap
        return float(best)

    def holding(self) -> float:
        """How far (0 .. 1, smooth) the hand has turned to hold a leg coming down onto it."""
        share = (TURN_FAR - self.leg_distance()) / (TURN_FAR - TURN_NEAR)
        share = min(max(share, 0.0), 1.0)
        return share * share * (3 - 2 * share)

    def turn(self, wanted: np.ndarray, share: float) -> np.ndarray:
        """``wanted`` (w, x, y, z), turned ``share`` of the way to :data:`HOLD_TURN`."""
        if share <= 0.0:
            return wanted
        q = np.asarray(wanted, float) / np.linalg.norm(wanted)
        if q[0] < 0:
            q = -q
        out = (1 - share) * q + share * HOLD_TURN
        return out / np.linalg.norm(out)

    def _load(self) -> None:
        """The scene now in the scratch data, kinematics computed (``data``'s may be stale or
        not computed yet)."""
        scratch, data = self.scratch, self.data
        scratch.qpos[:] = data.qpos
        scratch.mocap_pos[:] = data.mocap_pos
        scratch.mocap_quat[:] = data.mocap_quat
        mujoco.mj_kinematics(self.model, scratch)

    # --- the fingers -----------------------------------------------------------------------
    def near(self) -> np.ndarray:
        """Leg and robot geoms within reach of the hand (in the scratch data)."""
        data, model = self.scratch, self.model
        centre = data.xpos[self.hand_body]
        gap = np.linalg.norm(data.geom_xpos[self.obstacles] - centre, axis=1)
        gap -= model.geom_rbound[self.obstacles] + 0.2  # the hand with its fingers out
        return self.obstacles[gap < NEAR]

    def _ladder(self, wanted: np.ndarray) -> np.ndarray:
        """Hands from ``wanted`` to open and bent back (:data:`STEPS`), then towards curled
        (:data:`CURLS`), one row each."""
        open_hand = wanted.copy()
        extended = wanted.copy()
        curled = wanted.copy()
        for finger in range(1, 5):
            flex = slice(4 * finger + 1, 4 * finger + 4)
            open_hand[flex] = 0.0
            extended[flex] = EXTENDED
            curled[flex] = CURLED
        open_hand[:4] = self.open_thumb
        extended[:4] = THUMB_AWAY
        rows = [
            open_hand + s * (wanted - open_hand)
            if s >= 0
            else open_hand - s * (extended - open_hand)
            for s in STEPS
        ]
        rows += [wanted + s * (curled - wanted) for s in CURLS]
        return np.clip(np.array(rows), self.low, self.high)

    def _depths(self, angles: np.ndarray, near: np.ndarray, fingers: list[int]) -> np.ndarray:
        """Per finger of ``fingers``: how far (m) its geoms come inside :data:`FINGER_CLEARANCE` of
        the ``near`` geoms with the hand at ``angles`` (0 or less: clear)."""
        model, scratch = self.model, self.scratch
        saved = model.body_quat[self.bodies].copy()
        turns = axis_quats(self.axes, angles)
        quats = dict(zip(self.bodies, self.base, strict=True))
        for body, turn in zip(self.joint_body, turns, strict=True):
            quats[body] = quat_products(quats[body][None], turn[None])[0]
        model.body_quat[self.bodies] = np.array([quats[b] for b in self.bodies])
        try:
            mujoco.mj_kinematics(model, scratch)
        finally:
            model.body_quat[self.bodies] = saved
        out = np.full(5, -np.inf)
        for finger in fingers:
            geoms = self.finger_geoms[finger]
            gap = np.linalg.norm(
                scratch.geom_xpos[geoms][:, None] - scratch.geom_xpos[near][None], axis=2
            )
            gap -= model.geom_rbound[geoms][:, None] + model.geom_rbound[near][None]
            for i, j in zip(*np.nonzero(gap < FINGER_CLEARANCE), strict=True):
                a, b = int(geoms[i]), int(near[j])
                reach = FINGER_CLEARANCE
                distance = mujoco.mj_geomDistance(model, scratch, a, b, reach, self._fromto)
                out[finger] = max(out[finger], FINGER_CLEARANCE - distance)
        return out

    def fingers(self, wanted: np.ndarray) -> np.ndarray:
        """``wanted`` angles with each finger at the furthest step that keeps it clear of
        the legs and Robin as :meth:`_load` put them."""
        near = self.near()
        if len(near) == 0:
            return wanted
        ladder = self._ladder(wanted)
        pick = np.full(5, -1)
        least = np.full(5, np.inf)
        best = np.zeros(5, dtype=int)
        for step, row in enumerate(ladder):
            open_fingers = [f for f in range(5) if pick[f] < 0]
            if not open_fingers:
                break
            depth = self._depths(row, near, open_fingers)
            for finger in open_fingers:
                if depth[finger] <= 0.0:
                    pick[finger] = step
                elif depth[finger] < least[finger]:
                    least[finger], best[finger] = depth[finger], step
        pick = np.where(pick >= 0, pick, best)
        return ladder[pick[self.finger_of_joint], np.arange(20)]

    def fit(self, angles: np.ndarray, turn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The hand to write for the wanted ``angles`` and ``turn`` (module doc), as the scene
        is now. The turn is applied first (the fingers are measured where the hand is
        turned)."""
        self._load()
        share = self.holding()
        turned = self.turn(turn, share)
        body = self.hand_body
        saved = self.model.body_quat[body].copy()
        # the hand body turned (as person_joints.pose would) while the fingers are measured,
        # then put back: the scene's hand stays as written until the caller writes this fit
        # (a mirrored hand in a live session is written by another writer, robin_sim.live.mirror)
        turn_quat = quat_products(self.hand_base[None], np.asarray(turned)[None])[0]
        self.model.body_quat[body] = turn_quat
        try:
            return self.fingers(angles), turned
        finally:
            self.model.body_quat[body] = saved
