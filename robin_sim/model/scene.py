"""Compose the MuJoCo scene: Robin, the table, N table legs placed from a layout, the person.

``SceneLayout`` says where the legs lie, which table spots "location" can mean and where the
person holds out a palm for a handover; ``build_model`` turns it into an ``mujoco.MjModel`` by
editing ``models/scene.xml`` with ``mujoco.MjSpec`` (the four legs of the file are replaced).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import mujoco
import numpy as np

from pil.task.layout import LayoutError, LayoutSection, LegPose, Spot
from pil.task.params import MAX_LEGS  # a table's legs: the task's bound, for the scene too
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.idle_hand import bake_idle_hand
from robin_sim.model.person_joints import strip_joints

# Default table: the four legs lie along x in a row near the robot (x 0.44, 0.12 m apart) and
# the four spots for "location" in a second row further out (x 0.68), each spot's row half-way
# between two legs' rows. A leg placed on a spot lies along x like the resting ones (the wrist
# keeps the grasp's yaw), so placed and resting legs overlap in x only over 6 cm, 2 cm apart;
# the open fingers (spec.FINGER_SPREAD either side of a grasped leg's axis, FINGER_ALONG along
# it) clear every other leg by >= 3 cm, and every spot lies >= 7 cm (y) outside the palm at the
# handover point, so the hand never reaches under the held-out palm. See models/robin/README.md.
DEFAULT_LEGS: tuple[LegPose, ...] = (
    (0.44, 0.19, 0.0),
    (0.44, 0.31, 0.0),
    (0.44, 0.43, 0.0),
    (0.44, 0.55, 0.0),
)
DEFAULT_SPOTS: tuple[Spot, ...] = ((0.68, 0.13), (0.68, 0.25), (0.68, 0.37), (0.68, 0.49))
DEFAULT_HANDOVER: tuple[float, float, float] = (0.60, 0.0, spec.HANDOVER_HEIGHT)
# Bin centre (x, y) on the floor: beyond the table's far edge, left of the person (seen from
# Robin), below the path along x by which the person carries a delivered leg off the palm.
DEFAULT_BIN: tuple[float, float] = (1.22, -0.20)
BIN_X_RANGE: tuple[float, float] = (1.15, 1.30)  # bin centre: clear of the table and the person
BIN_Y_RANGE: tuple[float, float] = (-0.45, 0.45)
LEG_CLEARANCE = 0.01  # m between two legs' surfaces at least
SPOT_CLEARANCE = 0.06  # m from a spot to any leg's axis at least
LEG_COLORS: tuple[tuple[float, float, float, float], ...] = (
    (0.85, 0.25, 0.2, 1),
    (0.2, 0.65, 0.3, 1),
    (0.2, 0.4, 0.85, 1),
    (0.9, 0.75, 0.15, 1),
    (0.6, 0.3, 0.75, 1),
    (0.1, 0.7, 0.75, 1),
    (0.95, 0.5, 0.65, 1),
    (0.45, 0.3, 0.15, 1),
)
# What a participant calls each of LEG_COLORS (same order).
LEG_COLOUR_NAMES = ("red", "green", "blue", "yellow", "purple", "teal", "pink", "brown")
_REACH_TEXT = (
    "the left arm's reach: x 0.40-0.55 m for y -0.10..0.55 m, narrowing to y 0.10..0.55 m at "
    "x 0.70 m (robot_spec.LEFT_REACH_POLYGON)"
)


def leg_ends(pose: LegPose) -> tuple[np.ndarray, np.ndarray]:
    """End points (x, y) of a leg's axis (the capsule's segment, without the round caps)."""
    x, y, yaw = pose
    half = spec.LEG_LENGTH / 2 - spec.LEG_RADIUS
    d = half * np.array([math.cos(yaw), math.sin(yaw)])
    return np.array([x, y]) - d, np.array([x, y]) + d


def _point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab = b - a
    t = float(np.clip(np.dot(p - a, ab) / float(np.dot(ab, ab)), 0.0, 1.0))
    return float(np.linalg.norm(p - (a + t * ab)))


def _segments_distance(s1: tuple[np.ndarray, ...], s2: tuple[np.ndarray, ...]) -> float:
    (a, b), (c, d) = s1, s2

    def cross(o: np.ndarray, p: np.ndarray, q: np.ndarray) -> float:
        return float((p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]))

    if cross(a, b, c) * cross(a, b, d) < 0 and cross(c, d, a) * cross(c, d, b) < 0:
        return 0.0
    return min(
        _point_segment(a, c, d),
        _point_segment(b, c, d),
        _point_segment(c, a, b),
        _point_segment(d, a, b),
    )


def leg_gap(a: LegPose, b: LegPose) -> float:
    """Gap (m) between the surfaces of two legs lying on the table; <= 0 when they touch."""
    return _segments_distance(leg_ends(a), leg_ends(b)) - 2 * spec.LEG_RADIUS


def _on_table(x: float, y: float) -> bool:
    (x0, x1), (y0, y1) = spec.TABLE_X_RANGE, spec.TABLE_Y_RANGE
    return x0 <= x <= x1 and y0 <= y <= y1


def _table_text() -> str:
    (x0, x1), (y0, y1) = spec.TABLE_X_RANGE, spec.TABLE_Y_RANGE
    return f"the table top: x {x0:.2f}..{x1:.2f} m, y {y0:.2f}..{y1:.2f} m"


@dataclass(frozen=True)
class SceneLayout:
    """Where the legs lie, which spots exist, and where the person's palm waits for a handover.

    ``legs``: (x, y, yaw) per leg, metres and radians, the leg lying on the table top.
    ``spots``: (x, y) table spots that a "location" target can name.
    ``handover``: (x, y, z) of the person's palm surface centre (``human_palm_site``).
    ``bin``: (x, y) of the centre of the bin on the floor where the person drops delivered legs.
    """

    legs: tuple[LegPose, ...] = DEFAULT_LEGS
    spots: tuple[Spot, ...] = DEFAULT_SPOTS
    handover: tuple[float, float, float] = DEFAULT_HANDOVER
    bin: tuple[float, float] = DEFAULT_BIN

    def __post_init__(self) -> None:
        legs = tuple(tuple(float(v) for v in leg) for leg in self.legs)
        spots = tuple(tuple(float(v) for v in s) for s in self.spots)
        object.__setattr__(self, "legs", legs)
        object.__setattr__(self, "spots", spots)
        object.__setattr__(self, "handover", tuple(float(v) for v in self.handover))
        object.__setattr__(self, "bin", tuple(float(v) for v in self.bin))
        self._validate()

    def _validate(self) -> None:
        if not 1 <= len(self.legs) <= MAX_LEGS:
            raise LayoutError(f"a layout needs 1 to {MAX_LEGS} legs, got {len(self.legs)}")
        for i, leg in enumerate(self.legs):
            if len(leg) != 3:
                raise LayoutError(f"leg {i}: expected (x, y, yaw), got {leg!r}")
            for end in leg_ends(leg):
                if not _on_table(*end):
                    raise LayoutError(
                        f"leg {i} at (x={leg[0]:.3f}, y={leg[1]:.3f}, yaw={leg[2]:.3f} rad) "
                        f"sticks out over the edge (end at x={end[0]:.3f}, y={end[1]:.3f}); "
                        f"its axis must lie on {_table_text()}"
                    )
            if not spec.in_left_reach(leg[0], leg[1]):
                raise LayoutError(
                    f"leg {i} at (x={leg[0]:.3f}, y={leg[1]:.3f}) is out of reach; valid "
                    f"centres lie within {_REACH_TEXT}"
                )
        segments = [leg_ends(leg) for leg in self.legs]
        min_gap = 2 * spec.LEG_RADIUS + LEG_CLEARANCE
        for i in range(len(segments)):
            for j in range(i + 1, len(segments)):
                gap = _segments_distance(segments[i], segments[j])
                if gap < min_gap:
                    raise LayoutError(
                        f"legs {i} and {j} overlap or touch (axes {gap:.3f} m apart); "
                        f"their axes must be at least {min_gap:.3f} m apart"
                    )
        for k, spot in enumerate(self.spots):
            if len(spot) != 2:
                raise LayoutError(f"spot {k}: expected (x, y), got {spot!r}")
            if not _on_table(*spot) or not spec.in_left_reach(*spot):
                raise LayoutError(
                    f"spot {k} at (x={spot[0]:.3f}, y={spot[1]:.3f}) is off the table or out "
                    f"of reach; valid spots lie on {_table_text()} and within {_REACH_TEXT}"
                )
            for i, seg in enumerate(segments):
                if _point_segment(np.array(spot), *seg) < SPOT_CLEARANCE:
                    raise LayoutError(
                        f"spot {k} at (x={spot[0]:.3f}, y={spot[1]:.3f}) lies on leg {i}; a spot "
                        f"must be at least {SPOT_CLEARANCE:.2f} m from every leg's axis"
                    )
        if len(self.handover) != 3:
            raise LayoutError(f"handover: expected (x, y, z), got {self.handover!r}")
        hx, hy, hz = self.handover
        if not spec.in_left_reach(hx, hy) or not 0.80 <= hz <= 1.00:
            raise LayoutError(
                f"handover palm at (x={hx:.3f}, y={hy:.3f}, z={hz:.3f}) is out of reach; "
                f"valid: (x, y) within {_REACH_TEXT}, z 0.80..1.00 m"
            )
        (bx0, bx1), (by0, by1) = BIN_X_RANGE, BIN_Y_RANGE
        if len(self.bin) != 2 or not (bx0 <= self.bin[0] <= bx1 and by0 <= self.bin[1] <= by1):
            raise LayoutError(
                f"bin at {self.bin!r} is not a valid (x, y) centre; valid: x {bx0:.2f}..{bx1:.2f}"
                f" m (beyond the table, before the person), y {by0:.2f}..{by1:.2f} m"
            )

    @classmethod
    def of(cls, section: LayoutSection) -> SceneLayout:
        """The layout of a scenario's parsed ``layout`` section (:mod:`pil.task.layout`): the
        scene's defaults where it is silent, then checked where the robot can work."""
        given = {f.name: getattr(section, f.name) for f in fields(section)}
        return cls(**{key: value for key, value in given.items() if value is not None})


def enable_sleep(model_spec: mujoco.MjSpec) -> None:
    """Let legs at rest sleep (MuJoCo's island sleeping): their physics is skipped until a
    moving body touches them.

    Robin's actuated arms never sleep (MuJoCo's automatic policy for actuated trees) and
    neither does the person's palm, which a weld ties to the moving mocap hand; so a leg held
    by the hand or lying on the palm stays awake, and the hand sensor reads its contacts. A
    sleeping leg's contacts are not in ``data.contact``: nothing may rely on them.
    """
    model_spec.option.enableflags |= int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    model_spec.body(names.HUMAN_PALM_BODY).sleep = mujoco.mjtSleepPolicy.mjSLEEP_NEVER


def build_spec(layout: SceneLayout | None = None, *, sleep: bool = False) -> mujoco.MjSpec:
    """The scene as an editable ``MjSpec`` with the legs and bin of ``layout`` (default: the
    file's); the legs' bodies come last, so their free joints follow the person's palm joint.
    ``sleep``: resting legs sleep (:func:`enable_sleep`). Off by default: in a closed-loop
    episode (60 %, seed 1) a held leg's contacts went missing with it and the hand read free
    while it held the leg, and the hand state must come from contacts."""
    layout = layout or SceneLayout()
    model_spec = mujoco.MjSpec.from_file(str(names.SCENE_XML))
    bake_idle_hand(model_spec)  # the idle hand's fingers hold one pose (model.idle_hand)
    strip_joints(model_spec)  # the person is posed from userdata (model.person_joints)
    if sleep:
        enable_sleep(model_spec)
    template = model_spec.geom(names.leg_geom(0))
    size, fromto = np.array(template.size), np.array(template.fromto)
    leg_class = model_spec.find_default(template.classname.name)
    i = 0
    while (body := model_spec.body(names.leg_body(i))) is not None:
        model_spec.delete(body)
        i += 1
    model_spec.body(names.BIN_BODY).pos = [*layout.bin, 0.0]
    z = spec.TABLE_TOP_Z + spec.LEG_RADIUS
    for k, (x, y, yaw) in enumerate(layout.legs):
        body = model_spec.worldbody.add_body(
            name=names.leg_body(k),
            pos=[x, y, z],
            quat=[math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)],
        )
        body.add_freejoint(name=names.leg_joint(k))
        body.add_geom(
            leg_class,
            name=names.leg_geom(k),
            type=mujoco.mjtGeom.mjGEOM_CAPSULE,
            size=size,
            fromto=fromto,
            rgba=LEG_COLORS[k % len(LEG_COLORS)],
        )
    return model_spec


def build_model(layout: SceneLayout | None = None, *, sleep: bool = False) -> mujoco.MjModel:
    """Compile the scene with the legs of ``layout`` (default: the four of ``scene.xml``)."""
    return build_spec(layout, sleep=sleep).compile()


def leg_count(model: mujoco.MjModel) -> int:
    """Number of table legs (bodies ``leg0``, ``leg1``, ...) in a compiled scene."""
    count = 0
    while mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, names.leg_body(count)) >= 0:
        count += 1
    return count
