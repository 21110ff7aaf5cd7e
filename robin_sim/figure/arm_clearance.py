"""How near the person's right arm comes to the handed-over legs and Robin, for the posture.

The person is kinematic: nothing in the physics keeps its arm out of a leg Robin holds over the
person's palm or out of Robin's hand delivering it. :class:`ArmClearance` lets the posture's
solve (:class:`~robin_sim.figure.posture.Posture`) score each candidate arm (elbow swings about
the shoulder-wrist line, torso poses) by how far it comes inside :data:`ARM_CLEARANCE` of them.

Both sides are capsules, measured analytically as segments less radii: the arm's sphere and
capsules (upper arm and forearm, read from the model as shares along the segments shoulder to
elbow and elbow to wrist) and every leg and robot geom (capsules and cylinders along their axis,
spheres as points, boxes along their longest axis with the rest of the box as radius: never
nearer than the geom is). Only obstacles whose bounding spheres lie within reach of the line
from shoulder to wrist (where any elbow swing can put the arm) are measured, all candidates
at once in a few array operations.
"""

from __future__ import annotations

import mujoco
import numpy as np

from robin_sim.model import names
from robin_sim.model.geom_groups import category_geoms

ARM_CLEARANCE = 0.006  # m kept between the arm's geoms and a leg's or Robin's
# m: obstacles whose bounding spheres come this near to where the arm can be are measured (and
# make the posture solve again at the next render: they may move while the hand holds still)
BROAD = 0.05
_CAPSULE, _CYLINDER = int(mujoco.mjtGeom.mjGEOM_CAPSULE), int(mujoco.mjtGeom.mjGEOM_CYLINDER)
_SPHERE, _BOX = int(mujoco.mjtGeom.mjGEOM_SPHERE), int(mujoco.mjtGeom.mjGEOM_BOX)


def _quat_mat(quat: np.ndarray) -> np.ndarray:
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, quat)
    return mat.reshape(3, 3)


def segment_distances(p1: np.ndarray, q1: np.ndarray, p2: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Distances between segments p1-q1 and p2-q2 (arrays of shape (..., 3), broadcast; a
    segment may be a point)."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a = np.sum(d1 * d1, -1)
    e = np.sum(d2 * d2, -1)
    b = np.sum(d1 * d2, -1)
    c = np.sum(d1 * r, -1)
    f = np.sum(d2 * r, -1)
    tiny = 1e-12
    a_safe, e_safe = np.maximum(a, tiny), np.maximum(e, tiny)
    denom = a * e - b * b
    s = np.where(denom > tiny, np.clip((b * f - c * e) / np.maximum(denom, tiny), 0, 1), 0.0)
    s = np.where(a > tiny, s, 0.0)
    t = np.where(e > tiny, (b * s + f) / e_safe, 0.0)
    low, high = t < 0.0, t > 1.0
    s = np.where(low & (a > tiny), np.clip(-c / a_safe, 0, 1), s)
    s = np.where(high & (a > tiny), np.clip((b - c) / a_safe, 0, 1), s)
    t = np.clip(t, 0.0, 1.0)
    gap = (p1 + s[..., None] * d1) - (p2 + t[..., None] * d2)
    return np.sqrt(np.sum(gap * gap, -1))


class ArmClearance:
    """The right arm's capsules and the obstacles' (module doc), measured per candidate arm."""

    def __init__(self, model: mujoco.MjModel) -> None:
        upper, fore, wrist = names.person_arm_bodies("r")
        pieces: list[tuple[int, float, float, float]] = []  # segment, from, to (shares), radius
        for segment, (body, child) in enumerate(((upper, fore), (fore, wrist))):
            length = float(np.linalg.norm(model.body(child).pos))
            along = model.body(child).pos / length
            for g in np.flatnonzero(model.geom_bodyid == model.body(body).id):
                kind, size = int(model.geom_type[g]), model.geom_size[g]
                half = size[1] if kind == _CAPSULE else 0.0
                if kind not in (_CAPSULE, _SPHERE):
                    raise ValueError(f"person arm geom {g} is of type {kind}: capsules, spheres")
                axis = _quat_mat(model.geom_quat[g])[:, 2]
                ends = [model.geom_pos[g] + sign * half * axis for sign in (-1.0, 1.0)]
                shares = sorted(float(end @ along) / length for end in ends)
                off = max(float(np.linalg.norm(end - (end @ along) * along)) for end in ends)
                if off > 1e-6:
                    raise ValueError(f"person arm geom {g} lies off its segment by {off:.4f} m")
                pieces.append((segment, shares[0], shares[1], float(size[0])))
        self.segment = np.array([p[0] for p in pieces])
        self.shares = np.array([p[1:3] for p in pieces])
        self.radius = np.array([p[3] for p in pieces])
        groups = category_geoms(model)
        self.obstacles = np.concatenate([groups["legs"], groups["robot"]])
        kept, halves, radii, axes = [], [], [], []
        for g in self.obstacles:
            kind, size = int(model.geom_type[g]), model.geom_size[g]
            if kind in (_CAPSULE, _CYLINDER):
                along, half, radius = 2, float(size[1]), float(size[0])
            elif kind == _SPHERE:
                along, half, radius = 2, 0.0, float(size[0])
            elif kind == _BOX:
                along = int(np.argmax(size))
                half = float(size[along])
                radius = float(np.linalg.norm(np.delete(size, along)))
            else:
                continue
            kept.append(int(g))
            halves.append(half)
            radii.append(radius)
            axes.append(along)
        self.obstacles = np.array(kept, dtype=int)
        self.half = np.array(halves)
        self.obstacle_radius = np.array(radii)
        self.axis = np.array(axes)
        self.bound = model.geom_rbound[self.obstacles].copy()
        self.reach = float(self.radius.max())

    def near(
        self, data: mujoco.MjData, shoulder: np.ndarray, wrist: np.ndarray, swing: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The obstacles within :data:`BROAD` of an arm from ``shoulder`` to ``wrist`` whose
        elbow lies at most ``swing`` from the line between them: their segments' ends (two
        (m, 3) arrays) and radii, in ``data``'s computed kinematics."""
        centres = data.geom_xpos[self.obstacles]
        line = wrist - shoulder
        share = np.clip((centres - shoulder) @ line / max(float(line @ line), 1e-12), 0.0, 1.0)
        apart = np.linalg.norm(centres - (shoulder + share[:, None] * line), axis=1)
        k = np.flatnonzero(apart - self.bound < swing + self.reach + BROAD)
        mats = data.geom_xmat[self.obstacles[k]].reshape(-1, 3, 3)
        axes = mats[np.arange(len(k)), :, self.axis[k]]
        half = (self.half[k])[:, None] * axes
        return centres[k] - half, centres[k] + half, self.obstacle_radius[k]

    def depths(
        self,
        near: tuple[np.ndarray, np.ndarray, np.ndarray],
        shoulder: np.ndarray,
        elbows: np.ndarray,
        wrist: np.ndarray,
    ) -> np.ndarray:
        """Per candidate elbow of ``elbows`` (n, 3): how far (m) the arm from ``shoulder`` over
        it to ``wrist`` comes inside :data:`ARM_CLEARANCE` of the ``near`` obstacles (0 when
        clear)."""
        starts, ends, radii = near
        if len(radii) == 0:
            return np.zeros(len(elbows))
        n = len(elbows)
        a = np.where(self.segment[None, :, None] == 0, shoulder, elbows[:, None, :])
        b = np.where(self.segment[None, :, None] == 0, elbows[:, None, :], wrist)
        p = a + self.shares[None, :, :1] * (b - a)  # (n, k, 3)
        q = a + self.shares[None, :, 1:] * (b - a)
        gap = segment_distances(
            p[:, :, None, :], q[:, :, None, :], starts[None, None], ends[None, None]
        )
        gap -= self.radius[None, :, None] + radii[None, None, :]
        return np.maximum(ARM_CLEARANCE - gap.reshape(n, -1).min(axis=1), 0.0)
