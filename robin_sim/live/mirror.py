"""The participant's hand in Robin's world (``live --webcam``): landmarks drive the person's hand.

:class:`HandMirror` takes each tracker reading (:meth:`HandMirror.take`, any thread: the newest
is kept behind a lock, as the participant's inbox keeps messages) and, on the physics thread
at the next control tick (:meth:`HandMirror.tick`, a controller of the simulator), retargets it
onto the articulated person's right hand: the 20 joint angles from
:meth:`~robin_sim.figure.retarget.Retargeter.fit`, the hand's turn (the ball joint in the mocap
frame) from the landmarks' palm frame (:func:`~robin_sim.figure.retarget.steady_palm_frame`)
seen as Robin sees the person: the webcam looks at the participant as Robin faces the person
(image right is the
world's -y, image down -z, depth +x: :data:`CAMERA_TO_WORLD`). The arm and body follow the
turned hand when a render looks (:class:`~robin_sim.figure.posture.Posture`). The fit is written at
every tick until the next reading (the scripted body's own pose blends are overridden while the
participant's hand is mirrored); a reading with no hand keeps the last pose. Only the person's
hand joints and turn are written: no robot joint, no leg, no mocap position, no collision geom.

A left hand is mirrored into a right one. The tracker names hands as a self-view (a mirror)
shows them, and the page sends it the camera's own frames: a real right hand is read "Left", a
real left hand "Right" (:data:`LEFT_HAND`; the footage's right hands are all read "Left"). A
left hand's x is flipped: the person shows its mirror image, as a self-view does.

After each applied reading the fingertips physics shows (sites, hand frame, from the wrist
point) are compared with the landmarks' fingertips scaled to the model's hand
(:meth:`HandMirror.scaled_tips`: the landmarks' bone directions laid from the model's finger
roots with the model's bone lengths): :attr:`HandMirror.errors_mm` (mean over the five tips),
and with those of the hand posed with the fit alone (:attr:`HandMirror.follow_mm`: the scene
follows the retargeting);
:attr:`HandMirror.turn_deg` is how far the hand's rotation lies from the landmarks' palm frame.
"""

from __future__ import annotations

import copy
import threading
from itertools import pairwise

import mujoco
import numpy as np

from robin_sim.control.simulator import Simulator
from robin_sim.figure.articulated import JOINT_LIMIT_MARGIN
from robin_sim.figure.retarget import FINGER_POINTS, Retargeter
from robin_sim.live.hands.landmarks import HandInput
from robin_sim.model import names
from robin_sim.model.person_joints import figure, pose

# camera axes (image right, image down, depth away) in the world, as Robin faces the person
CAMERA_TO_WORLD = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
LEFT_HAND = "Right"  # the tracker's handedness of a real left hand in the camera's frames
KEPT_ERRORS = 1000  # fingertip errors kept (the newest)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / max(float(np.linalg.norm(v)), 1e-12)


def _mat(quat: np.ndarray) -> np.ndarray:
    out = np.zeros(9)
    mujoco.mju_quat2Mat(out, quat)
    return out.reshape(3, 3)


class HandMirror:
    """Drives the articulated person's right hand from landmark readings (module doc)."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData) -> None:
        self.model, self.data = model, data
        self.retargeter = Retargeter(model)
        fig = figure()  # the person's joints live in data.userdata (model.person_joints)
        self.qadr = fig.adr(self.retargeter.joints)
        self.low = self.retargeter.low + JOINT_LIMIT_MARGIN
        self.high = self.retargeter.high - JOINT_LIMIT_MARGIN
        self.turn_q = fig.joint(names.HUMAN_HAND_TURN).adr
        self._own = copy.copy(model)  # posing writes body frames into a model: its own copy
        self.mocap = int(model.body(names.HUMAN_MOCAP_BODY).mocapid[0])
        self.hand_body = model.body(names.person_hand_body("r")).id
        self.wrist_site = model.site(names.person_wrist_point("r")).id
        self.tip_sites = [
            model.site(names.person_fingertip_site("r", f)).id for f in names.PERSON_HAND_FINGERS
        ]
        # the model's hand as built (hand frame, from the wrist point)
        spec = mujoco.MjData(self._own)
        pose(self._own, spec)  # every joint at zero
        mujoco.mj_kinematics(self._own, spec)
        rotation = spec.xmat[self.hand_body].reshape(3, 3)
        wrist = spec.site_xpos[self.wrist_site]
        # per finger: its first knuckle (knuckle frame, from the wrist point) and bone lengths
        self.roots, self.bones = [], []
        for finger in names.PERSON_HAND_FINGERS:
            joints = [spec.xpos[model.body(b).id] for b in names.person_finger_bodies("r", finger)]
            joints.append(spec.site_xpos[model.site(names.person_fingertip_site("r", finger)).id])
            self.roots.append(rotation.T @ (joints[0] - wrist))
            self.bones.append([float(np.linalg.norm(b - a)) for a, b in pairwise(joints)])
        self._posed = mujoco.MjData(self._own)  # the hand posed with a fit alone (the record)
        self._lock = threading.Lock()
        self._pending: HandInput | None = None
        self._target: tuple[np.ndarray, np.ndarray] | None = None
        # what the next tick measures: the landmarks' tips scaled to the model (hand frame, m),
        # the tips of the hand posed with the fit alone, and the hand's wanted rotation
        self._wanted: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self.readings = 0  # readings with a hand applied
        # per applied reading, as the scene then shows the hand (means over the five tips):
        self.errors_mm: list[float] = []  # fingertips from the landmarks scaled to the model
        self.follow_mm: list[float] = []  # fingertips from those of the fit's pose
        self.turn_deg: list[float] = []  # the hand's rotation from the landmarks' palm frame

    # --- any thread ---------------------------------------------------------------------------
    def take(self, hand: HandInput) -> None:
        """Keep ``hand`` for the next tick (a newer reading replaces one not yet applied)."""
        if hand.points is None:
            return  # no hand: the last pose stays
        with self._lock:
            self._pending = hand

    @property
    def active(self) -> bool:
        """Whether a participant's reading drives the hand."""
        return self._target is not None

    # --- the physics thread -------------------------------------------------------------------
    def tick(self, _: Simulator | None = None) -> None:
        """Measure the last applied reading, apply a new one, write the hand (a controller)."""
        if self._wanted is not None:
            self._measure()
        with self._lock:
            hand, self._pending = self._pending, None
        if hand is not None:
            self._apply(hand)
        if self._target is not None:
            angles, quat = self._target
            self.data.userdata[self.qadr] = angles
            self.data.userdata[self.turn_q : self.turn_q + 4] = quat
            pose(self.model, self.data)

    def fit(self, hand: HandInput) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Joint angles, turn quaternion, the landmarks' fingertips scaled to the model (m, hand
        frame) and the hand's wanted rotation in the world, of ``hand``."""
        assert hand.points is not None
        mirror = hand.handedness == LEFT_HAND
        # the hand is turned so that it lies in the world as the fit's palm frame does (the
        # frame the angles were read in; a left hand: its mirror image, as a self-view shows it)
        fitted, p, frame = self.retargeter.fit_in_frame(hand.points, hand.aspect, mirror)
        angles = np.clip(fitted, self.low, self.high)
        world = CAMERA_TO_WORLD @ frame
        turn = _mat(self.data.mocap_quat[self.mocap]).T @ world
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, turn.flatten())
        return angles, quat, self.scaled_tips(p, frame), world

    def scaled_tips(self, p: np.ndarray, frame: np.ndarray) -> np.ndarray:
        """(5, 3) m: the landmarks' fingertips scaled to the model's hand, in the hand frame:
        from each of the model's finger roots along the landmarks' bone directions, each bone
        as long as the model's (the tracker's hand and the model's differ in proportions), in the
        landmarks' palm frame ``frame``, which the fit takes for the hand frame."""
        out = []
        for root, lengths, marks in zip(
            self.roots, self.bones, FINGER_POINTS.values(), strict=True
        ):
            tip = root.copy()
            for length, (a, b) in zip(lengths, pairwise(marks), strict=True):
                tip = tip + length * _unit(frame.T @ (p[b] - p[a]))
            out.append(tip)
        return np.array(out)

    def _apply(self, hand: HandInput) -> None:
        angles, quat, tips, world = self.fit(hand)
        self._target = (angles, quat)
        posed = self._posed
        posed.userdata[self.qadr] = angles
        pose(self._own, posed)
        mujoco.mj_kinematics(self._own, posed)
        self._wanted = (tips, self.tips_now(posed), world)
        self.readings += 1

    def tips_now(self, data: mujoco.MjData | None = None) -> np.ndarray:
        """(5, 3) m: the fingertip sites in the hand frame, from the wrist point, as physics
        last computed them (in ``data``: the session's unless given)."""
        data = self.data if data is None else data
        rotation = data.xmat[self.hand_body].reshape(3, 3)
        wrist = data.site_xpos[self.wrist_site]
        return np.array([rotation.T @ (data.site_xpos[s] - wrist) for s in self.tip_sites])

    def _measure(self) -> None:
        assert self._wanted is not None
        scaled, posed, world = self._wanted
        tips = self.tips_now()
        rotation = self.data.xmat[self.hand_body].reshape(3, 3)
        cos = (np.trace(world.T @ rotation) - 1.0) / 2.0
        for record, value in (
            (self.errors_mm, np.linalg.norm(tips - scaled, axis=1).mean() * 1000.0),
            (self.follow_mm, np.linalg.norm(tips - posed, axis=1).mean() * 1000.0),
            (self.turn_deg, np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))),
        ):
            record.append(float(value))
            del record[:-KEPT_ERRORS]
        self._wanted = None
