"""The articulated person's right hand forms the poses: joint angles written kinematically.

:class:`ArticulatedHand` turns a pose of the library (:mod:`robin_sim.model.pose_library`,
from real hands) and one :class:`~robin_sim.figure.hand_poses.Performance` into the hand's 20
joint angles and its turn in the mocap frame (the ball joint ``human_r_hand_turn``: where the
pose's silhouette faces, :func:`~robin_sim.figure.hand_poses.wrist_rotation`), and writes them
into ``data.userdata`` (the person's joints live there, not in the physics:
:mod:`robin_sim.model.person_joints`), posing the hand's bodies. A change of pose is either
immediate (a still picture, Robin's reading) or a seeded minimum-jerk blend from the current
hand over ``blend`` seconds, played out by :meth:`ArticulatedHand.update` at every control
tick: the hand moves into a gesture, it does not switch shapes. Before a render looks,
:meth:`ArticulatedHand.prepare_view` fits the hand around a leg coming down onto the palm or
lying on it and around Robin's fingers (:mod:`robin_sim.figure.hand_fit`). Only the person's
joints are written (their geoms never collide); the collision palm under the mocap frame is
untouched. The performance's hand size is not used (the hand's segment lengths are the
model's); its skin tone colours every skin geom.
"""

from __future__ import annotations

from dataclasses import replace

import mujoco
import numpy as np

from robin_sim.figure.hand_fit import HandFit
from robin_sim.figure.hand_poses import SHAPES, Performance, skin_colour, wrist_rotation
from robin_sim.model import names
from robin_sim.model.geom_groups import body_geoms
from robin_sim.model.person_joints import figure, has_figure, pose
from robin_sim.model.pose_library import load_library

# How a performance's offsets enter the joints (rad per unit): a finger's curl spreads over its
# MCP, PIP and DIP; the spread fans the fingers about the middle; the thumb's direction moves
# its CMC's two axes and its MCP.
CURL_GAINS = (0.9, 1.1, 0.7)
FAN = (1.5, 0.5, -0.5, -1.5)  # index .. little
THUMB_GAINS = (1.5, 1.5, 1.0)
# rad kept inside every joint limit: a joint at its limit would add a constraint to the solver
JOINT_LIMIT_MARGIN = 1e-6
SKIN_CLASS_RGBA = (0.87, 0.68, 0.55)  # the scene's skin tone (hand_poses.DEFAULT_SKIN)
# Where the hand faces (fingers' direction, palm normal; hand body frame) where an arm cannot
# hold the capsule hand's turn (hand_poses.SHAPES: fingers straight up, the palm to Robin's
# head, which needs the forearm to come from below the hand): the hand raised at the wrist
# from a forearm held level, the palm (or the fist's fingers) towards Robin.
TURNS: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "grasp": ((-0.7, 0.0, 0.7), (-0.7, 0.0, -0.7)),
    "release": ((-0.7, 0.0, 0.7), (-0.7, 0.0, -0.7)),
}


def has_articulated_hand(model: mujoco.MjModel) -> bool:
    """Whether ``model`` holds the articulated person (posed from its userdata)."""
    return has_figure(model)


def _smooth(s: float) -> float:
    s = min(max(s, 0.0), 1.0)
    return s * s * s * (10 - 15 * s + 6 * s * s)


def subtree_geoms(model: mujoco.MjModel, root: str) -> np.ndarray:
    """Geom ids of body ``root`` and every body below it."""
    return body_geoms(model, (root,))


class ArticulatedHand:
    """Writes hand poses into the person's right hand in ``model`` / ``data`` (module doc)."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self.model, self.data = model, data
        self.library = load_library()
        fig = figure()
        joints = names.person_hand_joints("r")
        self.qadr = fig.adr(joints)  # in data.userdata
        self.low, self.high = fig.ranges(joints).T
        self.turn_q = fig.joint(names.HUMAN_HAND_TURN).adr
        self.hand_geoms = subtree_geoms(model, names.person_hand_body("r"))
        person = np.concatenate(
            [subtree_geoms(model, names.PERSON_BODY), subtree_geoms(model, names.HUMAN_MOCAP_BODY)]
        )
        skin = np.all(np.abs(model.geom_rgba[person, :3] - SKIN_CLASS_RGBA) < 1e-6, axis=1)
        self.skin_geoms = person[skin]
        self.fit = HandFit(model, data)  # keeps the fingers and palm clear of legs and Robin
        self._from: tuple[np.ndarray, np.ndarray] | None = None
        self._to: tuple[np.ndarray, np.ndarray] = (self.angles(), self.turn())
        self._wanted = self._to  # the hand as the pose wants it, before the fit
        self._fitted = False  # the written hand differs from the wanted one
        self._start, self._duration = 0.0, 0.0

    # --- reading the hand -----------------------------------------------------------------
    def angles(self) -> np.ndarray:
        """The hand's joint angles now (rad)."""
        return self.data.userdata[self.qadr].copy()

    def turn(self) -> np.ndarray:
        """The hand's turn in the mocap frame now (quaternion w, x, y, z)."""
        turn = self.data.userdata[self.turn_q : self.turn_q + 4].copy()
        return turn if np.any(turn) else np.array([1.0, 0.0, 0.0, 0.0])  # fresh data: none

    def target(
        self, pose: str, performance: Performance | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Joint angles and turn quaternion of ``pose`` as ``performance`` makes it."""
        performance = performance or Performance()
        angles = self.library.pose(pose)
        for i, curl in enumerate(performance.curl):
            base = 4 + 4 * i  # index .. little: spread, mcp, pip, dip
            angles[base] += FAN[i] * performance.spread
            angles[base + 1 : base + 4] += curl * np.array(CURL_GAINS)
        angles[:3] += np.asarray(performance.thumb) * np.array(THUMB_GAINS)
        if performance.fingers:
            angles += np.asarray(performance.fingers) * self.library.sd[pose]
        quat = np.zeros(4)
        shape = SHAPES[pose]
        if pose in TURNS:
            shape = replace(shape, fingers_dir=TURNS[pose][0], palm_normal=TURNS[pose][1])
        mujoco.mju_mat2Quat(quat, wrist_rotation(shape, performance).flatten())
        return np.clip(angles, self.low + JOINT_LIMIT_MARGIN, self.high - JOINT_LIMIT_MARGIN), quat

    # --- writing it -----------------------------------------------------------------------
    def show(self, pose: str, performance: Performance | None = None, blend: float = 0.0) -> None:
        """Form ``pose``: at once (``blend`` 0) or moving there over ``blend`` seconds."""
        performance = performance or Performance()
        self.model.geom_rgba[self.skin_geoms, :3] = skin_colour(performance.skin)
        self._to = self.target(pose, performance)
        if blend > 0.0:
            self._from = self._wanted
            self._start, self._duration = float(self.data.time), blend
        else:
            self._from = None
            self._write(*self._to)

    def busy(self, now: float) -> bool:
        """True while a blend is under way."""
        return self._from is not None and now < self._start + self._duration

    def update(self, now: float) -> None:
        """Write the blend's hand, as the pose wants it, at simulated time ``now`` (nothing when
        none runs); :meth:`prepare_view` fits it around what is near when a render looks."""
        if self._from is None:
            return
        s = _smooth((now - self._start) / self._duration)
        (a0, q0), (a1, q1) = self._from, self._to
        quat = np.zeros(4)
        mujoco.mju_normalize4(q0)
        if np.dot(q0, q1) < 0:
            q1 = -q1
        quat = (1 - s) * q0 + s * q1  # nlerp: the turns are under 180 degrees apart
        self._write(a0 + s * (a1 - a0), quat / np.linalg.norm(quat), fit=False)
        if s >= 1.0:
            self._from = None

    def prepare_view(self) -> None:
        """Fit the hand around a leg or Robin's hand near it
        (:class:`~robin_sim.figure.hand_fit.HandFit`) before a render looks, ahead of the
        body's posture (which follows the hand's turn); nothing is written while nothing is near
        and nothing was fitted (no physics needs it, so runs without renders pay nothing)."""
        angles, quat = self._wanted
        fitted, turned = self.fit.fit(angles, quat)
        changed = not (np.array_equal(fitted, angles) and np.array_equal(turned, quat))
        if changed or self._fitted:
            self._put(fitted, turned, changed)

    def _write(self, angles: np.ndarray, quat: np.ndarray, fit: bool = True) -> None:
        """Write the hand wanted at ``angles`` and turn ``quat``, fitted (``fit``) or as is."""
        self._wanted = (angles, quat)
        fitted, turned = self.fit.fit(angles, quat) if fit else (angles, quat)
        changed = not (np.array_equal(fitted, angles) and np.array_equal(turned, quat))
        self._put(fitted, turned, changed)

    def _put(self, angles: np.ndarray, quat: np.ndarray, fitted: bool) -> None:
        self._fitted = fitted
        self.data.userdata[self.qadr] = angles
        self.data.userdata[self.turn_q : self.turn_q + 4] = quat
        pose(self.model, self.data)
