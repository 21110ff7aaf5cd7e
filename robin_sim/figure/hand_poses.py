"""The shapes of the person's hand poses, and how each performance of one varies.

The scene gives every pose six visual geoms (a palm box and five finger capsules,
:data:`robin_sim.model.names.HUMAN_VIS_PARTS`). :class:`HandShaper` rewrites their position,
orientation and size in ``model`` from a :class:`PoseShape`: per finger a curl (0 straight,
1 folded into a fist) and a spread, a thumb direction, and the wrist's orientation, given by the
direction the straight fingers point and the palm's normal in the hand body's frame (x towards
the person, away from Robin; z up). The six poses differ in silhouette as a watcher sees them:

- pointing: a fist with the index straight, pointing down towards the pointed place;
- give me: the flat hand held out palm up, fingers together (it matches the collision palm);
- grasp: a "C", fingers half curled and thumb opposed, shown to Robin;
- release: the open hand raised, palm to Robin, fingers spread wide;
- thumb up / thumb down: a fist with knuckles to Robin, the thumb straight up / down.

:class:`Performance` draws one performance: curl, spread and thumb jitter, a wrist rotation, a
hand size and a skin tone (a person never makes a gesture the same way twice). Only visual-only
geoms change, so physics is untouched.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from pil.types import SIGN_OF, Feedback, Gesture
from robin_sim.model import names

HUMAN_FINGERS: tuple[str, ...] = (
    "index",
    "middle",
    "ring",
    "little",
)  # the person's (Robin's: names.FINGERS)
PALM_HALF = np.array([0.045, 0.045, 0.012])  # m, palm box half sizes
FINGER_RADIUS = 0.009  # m
THUMB_RADIUS = 0.010  # m
FINGER_LENGTH = {"index": 0.075, "middle": 0.082, "ring": 0.076, "little": 0.062}  # m
THUMB_LENGTH = 0.058  # m
FINGER_Y = {"index": 0.03, "middle": 0.01, "ring": -0.01, "little": -0.03}  # m, base offsets
THUMB_BASE = np.array([-0.005, 0.045, 0.0])  # m
# Skin tones (RGB) from light to dark; a performance picks a point on this line.
SKIN_TONES = np.array(
    [
        [0.96, 0.80, 0.69],
        [0.87, 0.68, 0.55],
        [0.72, 0.52, 0.38],
        [0.55, 0.37, 0.25],
        [0.36, 0.23, 0.15],
    ]
)
DEFAULT_SKIN = 1.0  # index on SKIN_TONES: the scene's skin colour
FINGER_DRAWS = 20  # the articulated hand's joints (names.person_hand_joints)


@dataclass(frozen=True, slots=True)
class PoseShape:
    """One hand pose in the hand body frame (see the module doc)."""

    curl: tuple[float, float, float, float]  # index, middle, ring, little: 0 straight .. 1 fist
    spread: float  # rad between neighbouring straight fingers
    thumb: tuple[float, float, float]  # thumb direction in the hand's own frame
    fingers_dir: tuple[float, float, float]  # where straight fingers point (body frame)
    palm_normal: tuple[float, float, float]  # palm normal (body frame)


_TO_ROBOT = (-1.0, 0.0, 0.0)
_POINT_DOWN = (-0.73, 0.0, -0.68)  # towards the place below and in front of the hand
_FACE_ROBOT = (-0.8, 0.0, 0.6)  # palm towards Robin's head
SHAPES: dict[str, PoseShape] = {
    "neutral": PoseShape(
        (0.35, 0.4, 0.45, 0.5), 0.05, (-0.6, 0.7, -0.3), (-1, 0, -0.5), (0, -1, 0)
    ),
    SIGN_OF[Gesture.POINTING]: PoseShape(
        (0.0, 1.0, 1.0, 1.0), 0.0, (-0.7, -0.2, 0.7), _POINT_DOWN, (0, -1, 0)
    ),
    SIGN_OF[Gesture.GIVE_ME]: PoseShape(
        (0.0, 0.0, 0.0, 0.0), 0.02, (-0.45, 0.9, 0.0), _TO_ROBOT, (0, 0, 1)
    ),
    SIGN_OF[Gesture.GRASP]: PoseShape(
        (0.55, 0.55, 0.55, 0.55), 0.05, (-0.8, 0.1, 0.6), (0, 0, 1), _FACE_ROBOT
    ),
    SIGN_OF[Gesture.RELEASE]: PoseShape(
        (0.0, 0.0, 0.0, 0.0), 0.3, (-0.1, 1.0, 0.0), (0, 0, 1), _FACE_ROBOT
    ),
    SIGN_OF[Feedback.OK]: PoseShape(
        (1.0, 1.0, 1.0, 1.0), 0.0, (0.05, 1.0, 0.0), _TO_ROBOT, (0, -1, 0)
    ),
    SIGN_OF[Feedback.NOT_OK]: PoseShape(
        (1.0, 1.0, 1.0, 1.0), 0.0, (0.05, 1.0, 0.0), _TO_ROBOT, (0, 1, 0)
    ),
}


@dataclass(frozen=True, slots=True)
class Performance:
    """How one performance of a pose differs from the pose's shape."""

    curl: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)  # added to each curl
    spread: float = 0.0  # rad added to the spread
    thumb: tuple[float, float, float] = (0.0, 0.0, 0.0)  # added to the thumb direction
    wrist: tuple[float, float, float] = (0.0, 0.0, 0.0)  # rotation vector (rad), body frame
    size: float = 1.0  # hand size scale
    skin: float = DEFAULT_SKIN  # index on SKIN_TONES (fractional: between two tones)
    # articulated hand: per joint, in units of the pose library's spread of real hands'
    # frames (robin_sim.figure.articulated); empty: none
    fingers: tuple[float, ...] = ()

    @classmethod
    def draw(
        cls,
        rng: np.random.Generator,
        *,
        jitter: float = 1.0,
        size_range: tuple[float, float] = (0.88, 1.12),
        skin_range: tuple[float, float] = (0.0, len(SKIN_TONES) - 1.0),
    ) -> Performance:
        """A random performance; ``jitter`` scales the pose jitter (0: none)."""
        return cls(
            curl=tuple(rng.normal(0.0, 0.08 * jitter, 4).tolist()),
            spread=float(rng.normal(0.0, 0.05 * jitter)),
            thumb=tuple(rng.normal(0.0, 0.12 * jitter, 3).tolist()),
            wrist=tuple(rng.normal(0.0, 0.12 * jitter, 3).tolist()),
            size=float(rng.uniform(*size_range)),
            skin=float(rng.uniform(*skin_range)),
            fingers=tuple(rng.normal(0.0, jitter, FINGER_DRAWS).tolist()),
        )


def skin_colour(skin: float) -> np.ndarray:
    """RGB of skin index ``skin`` on :data:`SKIN_TONES` (linear between tones)."""
    x = float(np.clip(skin, 0.0, len(SKIN_TONES) - 1.0))
    low = int(np.floor(x))
    high = min(low + 1, len(SKIN_TONES) - 1)
    return SKIN_TONES[low] + (x - low) * (SKIN_TONES[high] - SKIN_TONES[low])


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _rotvec(v: np.ndarray) -> np.ndarray:
    angle = float(np.linalg.norm(v))
    if angle < 1e-12:
        return np.eye(3)
    k = v / angle
    skew = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * skew + (1 - np.cos(angle)) * skew @ skew


def wrist_rotation(shape: PoseShape, performance: Performance) -> np.ndarray:
    """Rotation from the hand's own frame (fingers -x, palm normal +z) to the body frame."""
    f = _unit(np.asarray(shape.fingers_dir, float))
    n = np.asarray(shape.palm_normal, float)
    n = _unit(n - np.dot(n, f) * f)
    x = -f
    rotation = np.column_stack([x, np.cross(n, x), n])
    return _rotvec(np.asarray(performance.wrist, float)) @ rotation


def _finger_dir(curl: float, spread: float) -> np.ndarray:
    """Direction of a finger capsule in the hand frame: straight along -x, curling to +z."""
    phi = np.clip(curl, 0.0, 1.1) * np.radians(125)
    d = np.array([-np.cos(phi), 0.0, np.sin(phi)])
    c, s = np.cos(spread), np.sin(spread)
    return np.array([d[0] * c, d[0] * s, d[2]])


def part_segments(
    pose: str, performance: Performance | None = None
) -> dict[str, tuple[np.ndarray, np.ndarray, float]]:
    """Finger capsules of ``pose`` as (start, end, radius) in the body frame (palm excluded)."""
    performance = performance or Performance()
    shape = SHAPES[pose]
    rotation = wrist_rotation(shape, performance)
    k = performance.size
    out: dict[str, tuple[np.ndarray, np.ndarray, float]] = {}
    spread = shape.spread + performance.spread
    for i, finger in enumerate(HUMAN_FINGERS):
        curl = shape.curl[i] + performance.curl[i]
        base = np.array([-PALM_HALF[0], FINGER_Y[finger], 0.0]) * k
        offset = (1.5 - i) * spread  # index spreads towards the thumb (+y)
        length = FINGER_LENGTH[finger] * (1.0 - 0.5 * np.clip(curl, 0, 1)) * k
        tip = base + length * _finger_dir(curl, -offset)
        out[finger] = (rotation @ base, rotation @ tip, FINGER_RADIUS * k * (1 + 0.2 * curl))
    thumb = _unit(np.asarray(shape.thumb, float) + np.asarray(performance.thumb, float))
    base = THUMB_BASE * k
    out["thumb"] = (rotation @ base, rotation @ (base + THUMB_LENGTH * k * thumb), THUMB_RADIUS * k)
    return out


def _capsule(start: np.ndarray, end: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """Centre, quaternion (z along the segment) and half length of a capsule."""
    axis = end - start
    half = float(np.linalg.norm(axis)) / 2
    quat = np.zeros(4)
    z = axis / max(2 * half, 1e-12)
    mujoco.mju_quatZ2Vec(quat, z)
    return (start + end) / 2, quat, half


class HandShaper:
    """Writes pose shapes into the scene's ``human_vis_<pose>_<part>`` geoms of ``model``."""

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.geoms = {
            pose: {
                part: model.geom(names.human_vis_geom(pose, part)).id
                for part in names.HUMAN_VIS_PARTS
            }
            for pose in SHAPES
        }

    @staticmethod
    def fits(model: mujoco.MjModel) -> bool:
        """Whether ``model`` has every pose's six part geoms (the project's scene does)."""
        return all(
            mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, names.human_vis_geom(p, part)) >= 0
            for p in SHAPES
            for part in names.HUMAN_VIS_PARTS
        )

    def shape(self, pose: str, performance: Performance | None = None) -> None:
        """Give ``pose``'s geoms their shape for ``performance`` (default: the plain pose)."""
        performance = performance or Performance()
        model, ids = self.model, self.geoms[pose]
        rotation = wrist_rotation(SHAPES[pose], performance)
        palm = ids["palm"]
        model.geom_pos[palm] = 0.0
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, rotation.flatten())
        model.geom_quat[palm] = quat
        model.geom_size[palm] = PALM_HALF * performance.size
        for part, (start, end, radius) in part_segments(pose, performance).items():
            centre, quat, half = _capsule(start, end)
            g = ids[part]
            model.geom_pos[g], model.geom_quat[g] = centre, quat
            model.geom_size[g] = (radius, half, 0.0)
        colour = skin_colour(performance.skin)
        for g in ids.values():
            model.geom_rgba[g, :3] = colour

    def shape_all(self) -> None:
        """Every pose in its plain shape."""
        for pose in SHAPES:
            self.shape(pose)
