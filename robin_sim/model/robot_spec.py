"""Numbers about Robin and its workspace that the MJCF cannot carry (or that code needs without
compiling a model): joint velocity limits, hand open/closed commands, the measured reach.

Angles are radians unless a name ends in ``_DEG``. Figures for the arm follow the public KUKA
LWR 4+ datasheet values; the reach region was measured on ``models/robin/robin.xml`` with mink
(see ``models/robin/README.md``). ``tests/test_model.py`` checks these against the model.
"""

from __future__ import annotations

import math

# --- arm (KUKA LWR 4+ style), joints 1..7 --------------------------------------------------------
ARM_JOINT_LIMITS_DEG: tuple[float, ...] = (170, 120, 170, 120, 170, 120, 170)
ARM_VELOCITY_LIMITS_DEG: tuple[float, ...] = (110, 110, 128, 128, 204, 184, 184)
ARM_TORQUE_LIMITS: tuple[float, ...] = (176, 176, 100, 100, 100, 38, 38)  # N·m
ARM_JOINT_LIMITS: tuple[float, ...] = tuple(math.radians(v) for v in ARM_JOINT_LIMITS_DEG)
ARM_VELOCITY_LIMITS: tuple[float, ...] = tuple(math.radians(v) for v in ARM_VELOCITY_LIMITS_DEG)
ARM_LINK_LENGTHS: tuple[float, ...] = (0.31, 0.40, 0.39, 0.078)  # base-shoulder-elbow-wrist-flange
SHOULDER_HEIGHT = 1.20  # m, height of joint 2 of both arms

# --- hand (Schunk SDH style) -------------------------------------------------------------------
# Position targets in the order of ``names.hand_actuators(side)``:
# knuckle1, f1_prox, f1_dist, f2_prox, f2_dist, thumb_prox, thumb_dist.
# Positive finger angles curl a finger toward the palm axis (closing).
HAND_OPEN_CTRL: tuple[float, ...] = (0.0, -0.5, 0.35, -0.5, 0.35, -0.5, 0.35)
# Commanded past contact on purpose: on a 4 cm leg the fingers stop at the leg and the actuators
# saturate at their force limits, which sets the grip force.
HAND_CLOSED_CTRL: tuple[float, ...] = (0.0, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6)
HAND_CLOSE_TIME = 0.6  # s, time to wait after switching to HAND_CLOSED_CTRL before lifting
HAND_OPEN_TIME = 0.4  # s, time for the fingers to clear a released leg
# Where the open fingers come down around a leg grasped at its centre: this far either side of
# its axis and along it (m). Another leg there keeps the close from holding it (measured: two
# parallel legs with axes 6 or 8 cm apart: "closed on nothing"; 10 cm apart: held).
FINGER_SPREAD, FINGER_ALONG = 0.08, 0.055

# Grasp site frame (``names.grasp_site``): origin where the axis of a grasped leg lies; z along
# the approach direction, pointing out of the palm (top-down grasp: z points down); y along the
# grasped leg's axis (the line through fingers 1 and 2); x from the thumb toward fingers 1 and 2.
GRASP_SITE_FROM_FLANGE = 0.200  # m along the flange z axis

# --- workspace (mirrors models/scene.xml) ------------------------------------------------------
TABLE_TOP_Z = 0.75
TABLE_X_RANGE: tuple[float, float] = (0.25, 1.05)
TABLE_Y_RANGE: tuple[float, float] = (-0.60, 0.60)
LEG_RADIUS = 0.02
LEG_LENGTH = 0.30  # tip to tip (capsule)
LEG_MASS = 0.25
GRASP_HEIGHT = TABLE_TOP_Z + LEG_RADIUS  # grasp site z for a top-down grasp of a lying leg
HANDOVER_HEIGHT = 0.88  # z of the human palm surface for a handover

# Bin for delivered legs, on the floor beside the person (models/scene.xml, body ``bin``):
# inner size x, y, depth above its floor; walls and floor 1 cm thick.
BIN_INNER_SIZE: tuple[float, float, float] = (0.36, 0.36, 0.25)
BIN_WALL = 0.01
BIN_FLOOR_TOP_Z = BIN_WALL  # z of the bin's inner floor

# Region (x, y) where the left arm's grasp site reaches top-down at GRASP_HEIGHT with any leg
# yaw (measured on a 5 cm grid, see the README); a convex polygon, counter-clockwise.
LEFT_REACH_POLYGON: tuple[tuple[float, float], ...] = (
    (0.40, -0.10),
    (0.55, -0.10),
    (0.70, 0.10),
    (0.70, 0.55),
    (0.40, 0.55),
)


def in_left_reach(x: float, y: float) -> bool:
    """True if (x, y) lies inside (or on) :data:`LEFT_REACH_POLYGON`."""
    pts = LEFT_REACH_POLYGON
    for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1], strict=True):
        if (x1 - x0) * (y - y0) - (y1 - y0) * (x - x0) < -1e-12:
            return False
    return True


# --- the person (facts the vision data set needs without a model) ---------------------------
# The pointing hand: toward the person and above the pointed place, low enough that its
# fingertips stay a few centimetres below the robot's open fingers at home.
POINT_OFFSET: tuple[float, float, float] = (0.14, 0.0, 0.13)  # m
PERSON_CLEAR_X = 0.95  # m: the pointing hand draws back this far, out of the robot's way
# m the drawn-back pointing hand is then raised: held up into Robin's view, above its own left
# upper arm, which hides a hand held lower above the left spots and legs from both eyes
POINT_RAISE = 0.20
# m along y the drawn-back thumb moves aside, away from Robin's active (left, +y) arm reaching
# to the palm, which still hid part of a thumb held straight back (boxes 7-10 px, 5 of 60
# thumbs down discarded); aside, both eyes see it whole (boxes 35 px and more)
THUMB_ASIDE = -0.15
