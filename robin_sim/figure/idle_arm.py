"""The person's idle left arm hangs along the body and keeps clear of the table and the bin.

The arm hangs plumb from the shoulder whatever the torso does (the shoulder's flexion takes
back the spine's lean), a little out from the body (:data:`ABDUCT`) with the elbow a little
bent (:data:`ELBOW`); where the hanging arm would come within :data:`TABLE_CLEARANCE` of the table
(its top grown by a lying leg's height, so legs on it are kept clear too), its frame or the bin,
the arm swings back at the shoulder by steps of :data:`SWING_STEP` until it is clear (the
least swing that is; where none is, the one that comes least near). The arm's segments are
sampled as balls (:data:`RADII`: each segment's thickness with some to spare)
and measured against the obstacles' boxes, read once from the model.
"""

from __future__ import annotations

import mujoco
import numpy as np

from robin_sim.figure.torso import axis_rotation
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.person_joints import Figure, jointed_scene

ABDUCT = 0.12  # rad the idle arm hangs out from the body
ELBOW = 0.15  # rad its elbow is bent
TABLE_CLEARANCE = 0.03  # m kept between the arm and the table, its frame and the bin
# m about each sampled point of the upper arm, the forearm and the hand (its thumb out to the
# side): the segment's radius with margin to spare
RADII = (0.05, 0.045, 0.08)
SWING_STEP = 0.1  # rad
SAMPLES = 8  # points per segment, its far end included: 5 cm apart at most


def _rots(axis: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """(n, 3, 3) turns about the unit ``axis`` by each of ``angles`` (Rodrigues)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    sin, cos = np.sin(angles)[:, None, None], np.cos(angles)[:, None, None]
    return np.eye(3) + sin * k + (1.0 - cos) * (k @ k)


def obstacle_boxes(model: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centres, rotations and half sizes of the table's and the bin's box geoms in the world
    (static bodies); the table top grown upwards by a lying leg's height."""
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    centres, rotations, sizes = [], [], []
    for body in (names.TABLE_BODY, names.BIN_BODY):
        top = model.body(body).id
        for g in np.flatnonzero(model.geom_bodyid == top):
            if model.geom_type[g] != mujoco.mjtGeom.mjGEOM_BOX:
                continue
            centre, size = data.geom_xpos[g].copy(), model.geom_size[g].copy()
            if model.geom(g).name == names.TABLE_TOP_GEOM:
                size[2] += spec.LEG_RADIUS
                centre[2] += spec.LEG_RADIUS
            centres.append(centre)
            rotations.append(data.geom_xmat[g].reshape(3, 3).copy())
            sizes.append(size)
    return np.array(centres), np.array(rotations), np.array(sizes)


class IdleArm:
    """The left arm's seven angles for a chest frame (module doc)."""

    def __init__(self, model: mujoco.MjModel, fig: Figure) -> None:
        self.joints = names.person_arm_joints("l")
        self.ranges = fig.ranges(self.joints)
        flex, abduct, _, elbow, *_ = (fig.joint(j).axis for j in self.joints)
        self.flex_axis = flex
        self.abduct, self.bend = axis_rotation(abduct, ABDUCT), axis_rotation(elbow, ELBOW)
        upper, fore, wrist = names.person_arm_bodies("l")
        body = model.body
        self.shoulder = body(upper).pos.copy()  # in the chest
        self.upper = body(fore).pos.copy()
        self.fore = body(wrist).pos.copy()
        # the hand straight, wrist to the middle finger's tip (its fingers are baked in the
        # scene: their lengths from the jointed one)
        jointed = jointed_scene()
        chain = [names.person_hand_body("l"), *names.person_finger_bodies("l", "middle")]
        tip = jointed.site(names.person_fingertip_site("l", "middle")).pos
        lengths = [np.linalg.norm(jointed.body(b).pos) for b in chain]
        self.hand = float(sum(lengths) + np.linalg.norm(tip))
        self.centres, self.rotations, self.sizes = obstacle_boxes(model)
        self.radii = np.repeat(RADII, SAMPLES)
        self.clearance = 0.0  # m: the last solve's nearest approach (less the radii)

    def _points(self, chest: np.ndarray, origin: np.ndarray, flex: np.ndarray) -> np.ndarray:
        """(len(flex), 3 * SAMPLES, 3) world points along the arm for each shoulder flexion."""
        shoulder = origin + chest @ self.shoulder
        upper = chest @ _rots(self.flex_axis, flex) @ self.abduct  # (n, 3, 3)
        fore = upper @ self.bend
        elbow = shoulder + upper @ self.upper
        wrist = elbow + fore @ self.fore
        tip = wrist + fore @ (self.hand * self.fore / np.linalg.norm(self.fore))
        s = np.linspace(1.0 / SAMPLES, 1.0, SAMPLES)[None, :, None]
        starts = (shoulder[None, None, :], elbow[:, None, :], wrist[:, None, :])
        ends = (elbow[:, None, :], wrist[:, None, :], tip[:, None, :])
        return np.concatenate([a + s * (b - a) for a, b in zip(starts, ends, strict=True)], 1)

    def _clearance(self, points: np.ndarray) -> np.ndarray:
        """Per candidate, the nearest approach (m, less the radii) of its points to any box."""
        rel = points[:, :, None, :] - self.centres[None, None]  # (c, p, b, 3)
        local = np.abs(np.einsum("cpbi,bij->cpbj", rel, self.rotations)) - self.sizes
        outside = np.linalg.norm(np.maximum(local, 0.0), axis=-1)
        distance = outside + np.minimum(local.max(axis=-1), 0.0)
        return (distance.min(axis=2) - self.radii).min(axis=1)

    def solve(self, origin: np.ndarray, chest: np.ndarray, lean: float) -> dict[str, float]:
        """The arm's joint values for the chest at ``origin`` turned by ``chest`` (its tilt from
        vertical ``lean``); sets :attr:`clearance`."""
        low, high = self.ranges[0]
        plumb = float(np.clip(lean, low, high))
        flex = np.array([plumb])
        clear = self._clearance(self._points(chest, origin, flex))
        k = 0
        if clear[0] < TABLE_CLEARANCE:  # swing back: the least swing that clears, else the clearest
            flex = np.arange(plumb, low, -SWING_STEP)
            clear = self._clearance(self._points(chest, origin, flex))
            ok = np.flatnonzero(clear >= TABLE_CLEARANCE)
            k = int(ok[0]) if len(ok) else int(np.argmax(clear))
        self.clearance = float(clear[k])
        values = np.zeros(len(self.joints))
        values[[0, 1, 3]] = flex[k], ABDUCT, ELBOW
        return dict(zip(self.joints, values.tolist(), strict=True))
