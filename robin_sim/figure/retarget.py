"""Retarget a hand tracker's 21 landmarks onto the person's hand joints: closed form, refined.

The landmarks (MediaPipe Hands order: 0 wrist; 1-4 thumb CMC, MCP, IP, tip; 5-8 index MCP, PIP,
DIP, tip; 9-12 middle; 13-16 ring; 17-20 little) give bone vectors. A palm frame is built from
the wrist, the middle finger's knuckle (forward) and the index and little knuckles (across),
in the hand's own convention (x towards the wrist, y towards the thumb, z the palm normal: the
model's ``human_r_hand`` frame), turned about the normal towards the middle finger's first
bone as far as that bone lies flat (:func:`steady_palm_frame`). A first guess of each joint
angle is an angle between bone vectors:

- a finger's MCP flexion: the elevation of its first bone above the palm plane; its spread:
  the bone's azimuth in that plane, faded out as the finger flexes;
- PIP and DIP: the angle between consecutive bones;
- the thumb's CMC (two axes): the direction of its metacarpal in the thumb's base frame, read
  from the model (abduction, then flexion); its MCP and IP: angles between bones.

The guess ignores the plane each finger curls in (the tracker's depth sets it) and the model's
joint axes, so a curled finger or the thumb could point 30-50 degrees off. It is then refined
by bounded least squares (``scipy.optimize.least_squares``, the joint limits as bounds) on the
15 bone directions: the model's bones, posed by MuJoCo's forward kinematics, against the
landmarks', in the palm frame, the tracker's depth axis weighted by :data:`DEPTH_WEIGHT` (it is
the noisiest). Directions rather than positions: the tracker's hand and the model's differ in
size and proportions. Each finger's residuals depend on its own four joints only, which the
solver is told (a block-sparse Jacobian), so a fit costs a few milliseconds. Rather than mink
frame tasks on tips and knuckles: the hand is a fixed tree of hinges with no contacts or
posture to trade against, where a small least-squares problem with bounds is exact and needs
no gains. Twist about a bone is not observed and is left at the model's.
"""

from __future__ import annotations

import copy
from collections.abc import Callable

import mujoco
import numpy as np
from scipy.optimize import least_squares

from robin_sim.model import names
from robin_sim.model.person_joints import figure, pose

DEPTH_WEIGHT = 0.5  # the tracker's depth residual against its image-plane ones
REFINE_EVALUATIONS = 30  # solver steps at most per fit (each five forward kinematics)
STEP = 1e-6  # rad, the Jacobian's finite difference
FINGER_POINTS: dict[str, tuple[int, int, int, int]] = {
    "thumb": (1, 2, 3, 4),
    "index": (5, 6, 7, 8),
    "middle": (9, 10, 11, 12),
    "ring": (13, 14, 15, 16),
    "little": (17, 18, 19, 20),
}


def _unit(v: np.ndarray) -> np.ndarray:
    return v / max(float(np.linalg.norm(v)), 1e-12)


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.arccos(np.clip(np.dot(_unit(a), _unit(b)), -1.0, 1.0)))


def metric(points: np.ndarray, aspect: float, mirror: bool) -> np.ndarray:
    """Landmarks (x, y normalised by the image's width and height, z by its width) in one
    unit along every axis; ``mirror`` flips x (a left hand read as a right one)."""
    p = np.asarray(points, float).copy()
    p[:, 1] /= aspect  # y in widths
    if mirror:
        p[:, 0] = -p[:, 0]
    return p


def _turned(frame: np.ndarray, angle: float) -> np.ndarray:
    """``frame`` turned by ``angle`` (rad) about its own z axis."""
    c, s = np.cos(angle), np.sin(angle)
    return frame @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _knuckle_frame(p: np.ndarray) -> tuple[np.ndarray, float, float]:
    """The frame from the wrist to the middle knuckle (-x) and the little to the index knuckle
    (y), the middle finger's first bone's turn from -x about its normal, and how flat that bone
    lies in the palm plane (1: in it, 0: along the normal)."""
    x = -_unit(p[9] - p[0])
    across = p[5] - p[17]
    y = _unit(across - np.dot(across, x) * x)
    frame = np.column_stack([x, y, np.cross(x, y)])
    middle = frame.T @ (p[10] - p[9])
    planar = float(np.hypot(middle[0], middle[1]))
    turn = float(np.arctan2(-middle[1], -middle[0])) if planar > 1e-9 else 0.0
    return frame, turn, planar / max(float(np.linalg.norm(middle)), 1e-12)


def palm_frame(p: np.ndarray) -> np.ndarray:
    """Columns x (towards the wrist), y (towards the thumb), z (palm normal) of a right hand.

    From the wrist to the middle knuckle (forward) and the little to the index knuckle
    (across), then turned about the normal so that -x follows the middle finger's first bone
    in the palm plane: the tracker's wrist point is off the middle finger's line, and the
    model's straight fingers point along -x."""
    frame, turn, _ = _knuckle_frame(p)
    return _turned(frame, turn)


def steady_palm_frame(p: np.ndarray) -> np.ndarray:
    """:func:`palm_frame` with its turn about the palm normal faded as the middle finger curls:
    that turn follows the middle finger's first bone in the palm plane, whose direction a curled
    finger no longer gives (it turned a thumb-up fist's frame half round). Open fingers keep it
    whole. The hand frame both the fit and the live mirror use."""
    frame, turn, flat = _knuckle_frame(p)
    return _turned(frame, turn * flat**2)


def landmark_bones(p: np.ndarray, frame: np.ndarray) -> np.ndarray:
    """(15, 3): the unit bone directions of the five fingers (three each, knuckle to knuckle and
    the last to the tip) of metric landmarks ``p`` in the hand frame ``frame``."""
    out = []
    for a, b, c, d in FINGER_POINTS.values():
        out += [_unit(frame.T @ (p[j] - p[i])) for i, j in ((a, b), (b, c), (c, d))]
    return np.array(out)


class Retargeter:
    """Fits joint angles of the model's right hand (:func:`names.person_hand_joints`)."""

    def __init__(self, model: mujoco.MjModel) -> None:
        fig = figure()
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, fig.base_quat_of(names.person_finger_bodies("r", "thumb")[0]))
        self.thumb_frame = rotation.reshape(3, 3)  # thumb base axes in the hand frame
        self.joints = names.person_hand_joints("r")
        self.low, self.high = fig.ranges(self.joints).T
        # a copy: posing writes the person's body frames into the model (model.person_joints)
        self.model = copy.copy(model)
        self._data = mujoco.MjData(self.model)  # the hand posed for the refinement
        self._qadr = fig.adr(self.joints)  # in data.userdata
        self._hand = model.body(names.person_hand_body("r")).id
        fingers = names.PERSON_HAND_FINGERS  # per finger: its three bodies' origins, its tip
        self._bodies = np.array(
            [[model.body(b).id for b in names.person_finger_bodies("r", f)] for f in fingers]
        )
        self._tips = np.array([model.site(names.person_fingertip_site("r", f)).id for f in fingers])
        self._per_finger = len(self.joints) // len(fingers)  # four joints each, finger by finger

    def model_bones(self, angles: np.ndarray) -> np.ndarray:
        """(15, 3): the model's unit bone directions in the hand frame, posed with ``angles``."""
        data = self._data
        data.userdata[self._qadr] = angles
        pose(self.model, data)
        mujoco.mj_kinematics(self.model, data)
        rotation = data.xmat[self._hand].reshape(3, 3)
        chain = np.concatenate([data.xpos[self._bodies], data.site_xpos[self._tips][:, None]], 1)
        bones = np.diff(chain, axis=1).reshape(-1, 3) @ rotation  # hand frame
        return bones / np.linalg.norm(bones, axis=1, keepdims=True)

    def _jacobian(
        self, residuals: Callable[[np.ndarray], np.ndarray], angles: np.ndarray
    ) -> np.ndarray:
        """Forward differences, a joint of every finger at once (a finger's nine residuals
        depend on its own joints only): four evaluations per Jacobian, not twenty."""
        base = residuals(angles)
        n, per = len(angles), self._per_finger
        jacobian = np.zeros((len(base), n))
        rows = len(base) // (n // per)
        for k in range(per):
            step = np.zeros(n)
            columns = np.arange(k, n, per)
            step[columns] = np.where(angles[columns] + STEP <= self.high[columns], STEP, -STEP)
            change = residuals(angles + step) - base
            for finger, column in enumerate(columns):
                block = slice(finger * rows, (finger + 1) * rows)
                jacobian[block, column] = change[block] / step[column]
        return jacobian

    def fit(
        self, points: np.ndarray, aspect: float = 16 / 9, mirror: bool = False, refine: bool = True
    ) -> np.ndarray:
        """Joint angles (rad, in the order of :attr:`joints`, within the limits): the closed-form
        guess, refined by least squares on the bone directions unless ``refine`` is off."""
        return self.fit_in_frame(points, aspect, mirror, refine)[0]

    def fit_in_frame(
        self, points: np.ndarray, aspect: float = 16 / 9, mirror: bool = False, refine: bool = True
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`fit`'s angles with the metric landmarks and the hand frame they were fitted
        in (:func:`metric`, :func:`steady_palm_frame`), for a caller that poses the hand."""
        p = metric(points, aspect, mirror)
        frame = steady_palm_frame(p)
        guess = np.clip(self.guess(p, frame), self.low, self.high)
        if not refine:
            return guess, p, frame
        want = landmark_bones(p, frame)
        weight = np.array([1.0, 1.0, DEPTH_WEIGHT])  # camera axes: image x, y, depth

        def residuals(angles: np.ndarray) -> np.ndarray:
            return ((self.model_bones(angles) - want) @ frame.T * weight).ravel()

        solved = least_squares(
            residuals,
            guess,
            bounds=(self.low, self.high),
            jac=lambda angles: self._jacobian(residuals, angles),
            max_nfev=REFINE_EVALUATIONS,
            x_scale=1.0,
        )
        return np.clip(solved.x, self.low, self.high), p, frame

    def guess(self, p: np.ndarray, frame: np.ndarray) -> np.ndarray:
        """The closed-form joint angles of metric landmarks ``p`` in the hand frame ``frame``
        (the module doc), before the limits."""
        out: list[float] = []
        for finger, (a, b, c, d) in FINGER_POINTS.items():
            bones = [frame.T @ (p[j] - p[i]) for i, j in ((a, b), (b, c), (c, d))]
            if finger == "thumb":
                local = _unit(self.thumb_frame.T @ bones[0])
                flex = float(np.arcsin(np.clip(local[2], -1, 1)))
                abduct = float(np.arctan2(-local[1], -local[0]))
                out += [abduct, flex, _angle(bones[0], bones[1]), _angle(bones[1], bones[2])]
                continue
            first = _unit(bones[0])
            mcp = float(np.arcsin(np.clip(first[2], -1, 1)))
            azimuth = float(np.arctan2(first[1], -first[0]))
            spread = azimuth * max(float(np.cos(mcp)), 0.0) ** 2
            out += [spread, mcp, _angle(bones[0], bones[1]), _angle(bones[1], bones[2])]
        return np.array(out)

    def curled_toward_palm(self, points: np.ndarray, aspect: float, mirror: bool) -> float:
        """Mean elevation of the fingertips above the palm plane (palm side positive): for the
        right reading of a hand's side, curled fingers lie on the palm side."""
        p = metric(points, aspect, mirror)
        frame = steady_palm_frame(p)
        tips = np.array([frame.T @ (p[i] - p[0]) for i in (8, 12, 16, 20)])
        return float(tips[:, 2].mean())
