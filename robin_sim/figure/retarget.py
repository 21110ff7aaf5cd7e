"""Retarget a hand tracker's 21 landmarks onto the person's hand joints, in closed form.

The landmarks (MediaPipe Hands order: 0 wrist; 1-4 thumb CMC, MCP, IP, tip; 5-8 index MCP, PIP,
DIP, tip; 9-12 middle; 13-16 ring; 17-20 little) give bone vectors. A palm frame is built from
the wrist, the middle finger's knuckle (forward) and the index and little knuckles (across),
in the hand's own convention (x towards the wrist, y towards the thumb, z the palm normal: the
model's ``human_r_hand`` frame). Each joint angle is then an angle between bone vectors:

- a finger's MCP flexion: the elevation of its first bone above the palm plane; its spread:
  the bone's azimuth in that plane (the frame follows the middle finger: :func:`palm_frame`),
  faded out as the finger flexes (a curled finger's azimuth says little about its spread);
- PIP and DIP: the angle between consecutive bones;
- the thumb's CMC (two axes): the direction of its metacarpal in the thumb's base frame, read
  from the model (abduction, then flexion); its MCP and IP: angles between bones.

A closed-form fit rather than an IK solve (mink frame tasks on tips and knuckles) because the
tracker gives every joint's neighbours: each angle is determined by two bone vectors, needs no
segment lengths (the tracker's hand and the model's differ in size and proportions), no
iterations and no tuning, and one frame costs microseconds. What it ignores: twist about a
bone (the tracker gives none) and the tracker's depth noise, which enters every angle.
"""

from __future__ import annotations

import mujoco
import numpy as np

from robin_sim.model import names

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


def palm_frame(p: np.ndarray) -> np.ndarray:
    """Columns x (towards the wrist), y (towards the thumb), z (palm normal) of a right hand.

    From the wrist to the middle knuckle (forward) and the little to the index knuckle
    (across), then turned about the normal so that -x follows the middle finger's first bone
    in the palm plane: the tracker's wrist point is off the middle finger's line, and the
    model's straight fingers point along -x."""
    x = -_unit(p[9] - p[0])
    across = p[5] - p[17]
    y = _unit(across - np.dot(across, x) * x)
    frame = np.column_stack([x, y, np.cross(x, y)])
    middle = frame.T @ (p[10] - p[9])
    turn = float(np.arctan2(middle[1], -middle[0])) if np.hypot(*middle[:2]) > 1e-9 else 0.0
    c, s = np.cos(turn), np.sin(turn)
    return frame @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


class Retargeter:
    """Fits joint angles of the model's right hand (:func:`names.person_hand_joints`)."""

    def __init__(self, model: mujoco.MjModel) -> None:
        body = model.body(names.person_finger_bodies("r", "thumb")[0])
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, body.quat)
        self.thumb_frame = rotation.reshape(3, 3)  # thumb base axes in the hand frame
        self.joints = names.person_hand_joints("r")
        ids = [model.joint(j).id for j in self.joints]
        self.low, self.high = model.jnt_range[ids, 0], model.jnt_range[ids, 1]

    def fit(self, points: np.ndarray, aspect: float = 16 / 9, mirror: bool = False) -> np.ndarray:
        """Joint angles (rad, in the order of :attr:`joints`, clipped to the limits)."""
        p = metric(points, aspect, mirror)
        frame = palm_frame(p)
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
        return np.clip(np.array(out), self.low, self.high)

    def curled_toward_palm(self, points: np.ndarray, aspect: float, mirror: bool) -> float:
        """Mean elevation of the fingertips above the palm plane (palm side positive): for the
        right reading of a hand's side, curled fingers lie on the palm side."""
        p = metric(points, aspect, mirror)
        frame = palm_frame(p)
        tips = np.array([frame.T @ (p[i] - p[0]) for i in (8, 12, 16, 20)])
        return float(tips[:, 2].mean())
