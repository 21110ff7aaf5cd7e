"""Every name the code uses to address the MJCF model: files, joints, actuators, sites, bodies.

The model files (``models/``) and the code agree through this module only; no joint, site or
file name is written as a string literal anywhere else in ``robin_sim``.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from typing import Literal

from pil.types import SIGN_NAMES

Side = Literal["l", "r"]
SIDES: tuple[Side, ...] = ("l", "r")
ACTIVE_SIDE: Side = "l"  # the paper's Robin hands over with its left arm

# --- files -------------------------------------------------------------------------------------
# The MJCF files are package data: ``robin_sim/model/mjcf`` (in a source checkout a link to the
# repository's ``models/``), so an installed wheel finds them without the repository.
MODELS_DIR = Path(str(resources.files("robin_sim.model") / "mjcf"))
ROBOT_XML = MODELS_DIR / "robin" / "robin.xml"
SCENE_XML = MODELS_DIR / "scene.xml"

# --- robot -------------------------------------------------------------------------------------
TORSO_BODY = "torso"
HOME_KEY = "home"
HEAD_JOINTS: tuple[str, ...] = ("head_pan", "head_tilt")
HEAD_CAMERAS: tuple[str, ...] = ("head_left_eye", "head_right_eye")
EYE_CAMERA = HEAD_CAMERAS[0]  # the left eye: the gaze aims it, the video's inset shows it
ARM_DOF = 7


def arm_joints(side: Side) -> tuple[str, ...]:
    """The seven arm joints of one side, shoulder to wrist: ``l_joint1`` .. ``l_joint7``."""
    return tuple(f"{side}_joint{i}" for i in range(1, ARM_DOF + 1))


def arm_bodies(side: Side) -> tuple[str, ...]:
    """The arm's base and its seven links, shoulder to wrist: ``l_base``, ``l_link1`` ..."""
    return (f"{side}_base", *(f"{side}_link{i}" for i in range(1, ARM_DOF + 1)))


def arm_actuators(side: Side) -> tuple[str, ...]:
    """Position actuators of the arm joints (same names as the joints)."""
    return arm_joints(side)


# Schunk SDH style hand: finger 1 and finger 2 rotate about the palm normal (``knuckle``, the two
# coupled by a joint equality), each finger has a proximal and a distal joint; finger 3 is the
# thumb, fixed in rotation.
THUMB = "thumb"
FINGERS: tuple[str, ...] = ("f1", "f2", THUMB)


def finger_joints(side: Side, finger: str) -> tuple[str, str]:
    """The proximal and distal joint of ``finger`` (one of FINGERS); actuators share the names."""
    return f"{side}_{finger}_prox", f"{side}_{finger}_dist"


def hand_joints(side: Side) -> tuple[str, ...]:
    """Every hand joint: the two knuckles, then proximal and distal joints of each finger."""
    fingers = (joint for finger in FINGERS for joint in finger_joints(side, finger))
    return (f"{side}_knuckle1", f"{side}_knuckle2", *fingers)


def hand_actuators(side: Side) -> tuple[str, ...]:
    """Hand position actuators: one knuckle (the other follows by equality) and six finger ones."""
    fingers = (joint for finger in FINGERS for joint in finger_joints(side, finger))
    return (f"{side}_knuckle1", *fingers)


def grasp_site(side: Side) -> str:
    """Site between the fingertips where a grasped leg's axis lies; the IK frame target."""
    return f"{side}_grasp_site"


def palm_site(side: Side) -> str:
    """Site at the palm centre."""
    return f"{side}_palm_site"


def hand_body(side: Side) -> str:
    """The hand's root body (palm); every finger body descends from it."""
    return f"{side}_palm"


# --- scene -------------------------------------------------------------------------------------
TABLE_BODY = "table"
TABLE_TOP_GEOM = "table_top"
FLOOR_GEOM = "floor"
SCENE_CAMERAS: tuple[str, ...] = ("front", "side", "head")  # that film the scene (eyes: above)
DEFAULT_CAMERA = "front"

PERSON_BODY = "human"  # the person standing across the table
HUMAN_MOCAP_BODY = "human_hand"  # mocap: the person's right hand (palm up for "give me")
HUMAN_PALM_GEOM = "human_palm"
HUMAN_PALM_SITE = "human_palm_site"


def leg_body(index: int) -> str:
    """Body of table leg ``index`` (0-based); each has a free joint ``leg{i}_free``."""
    return f"leg{index}"


def leg_joint(index: int) -> str:
    """Free joint of table leg ``index``."""
    return f"leg{index}_free"


def leg_geom(index: int) -> str:
    """Collision geom of table leg ``index``."""
    return f"leg{index}_geom"


# --- added by the model helper (H3): test bench, gesture visuals, fingertips ------------------
HAND_TEST_SCENE_XML = MODELS_DIR / "hand_test_scene.xml"
HAND_TEST_SLIDES: tuple[str, ...] = ("bench_x", "bench_y", "bench_z")  # joints = actuators
HEAD_CAMERA = "head"  # the robot's view, between the two eye cameras
HEAD_ACTUATORS: tuple[str, ...] = HEAD_JOINTS  # position actuators named like the joints

# Visual-only geoms on the human hand showing each gesture: ``human_vis_<pose>_<part>``; only
# the ``neutral`` pose is opaque in the file, the others have alpha 0 until shown.
HUMAN_VIS_POSES: tuple[str, ...] = ("neutral", *SIGN_NAMES)  # pil.types: the six signs
HUMAN_VIS_PARTS: tuple[str, ...] = ("palm", "thumb", "index", "middle", "ring", "little")


HUMAN_VIS_PREFIX = "human_vis_"  # what every gesture geom's name starts with


def human_vis_geom(pose: str, part: str) -> str:
    """Visual geom of gesture ``pose`` (one of HUMAN_VIS_POSES) and hand ``part``."""
    return f"{HUMAN_VIS_PREFIX}{pose}_{part}"


def fingertip_site(side: Side, finger: str) -> str:
    """Site at the tip of ``finger`` (one of FINGERS)."""
    return f"{side}_{finger}_tip"


def finger_bodies(side: Side, finger: str) -> tuple[str, ...]:
    """Bodies of one finger, base to tip: ``{side}_{finger}_base``, ``_proximal``, ``_distal``."""
    return tuple(f"{side}_{finger}_{link}" for link in ("base", "proximal", "distal"))


# --- added by the model helper (H3b): the person's physical palm, the bin ---------------------
# The collision palm ``HUMAN_PALM_GEOM`` sits on this dynamic body, welded to the mocap hand
# ``HUMAN_MOCAP_BODY`` (same frame); ``HUMAN_PALM_SITE`` stays on the mocap hand (the commanded
# palm centre), ``HUMAN_PALM_BODY_SITE`` is the same point on the physical palm.
HUMAN_PALM_BODY = "human_palm_body"
HUMAN_PALM_JOINT = "human_palm_free"
HUMAN_PALM_WELD = "human_palm_weld"
HUMAN_PALM_BODY_SITE = "human_palm_body_site"
PERSON_BODIES: tuple[str, ...] = (PERSON_BODY, HUMAN_MOCAP_BODY, HUMAN_PALM_BODY)  # with children
HUMAN_PALM_RIM_GEOMS: tuple[str, ...] = ("human_palm_rim_thumb", "human_palm_rim_little")
BIN_BODY = "bin"
# The bin for delivered legs (static body on the floor): its floor and four walls; "near" faces
# Robin (-x), "left" is +y (Robin's left).
BIN_GEOMS: tuple[str, ...] = (
    "bin_floor",
    "bin_wall_near",
    "bin_wall_far",
    "bin_wall_left",
    "bin_wall_right",
)


# --- the articulated person (models/person/person.xml) -------------------------------------
# The person's own sides: "r" is their right (+y, the hand that gestures and takes the legs),
# "l" their left. Every person name starts with ``human_``; Robin's own start with ``l_``/``r_``.
PERSON_XML = MODELS_DIR / "person" / "person.xml"
PERSON_HAND_FINGERS: tuple[str, ...] = ("thumb", "index", "middle", "ring", "little")
FINGER_JOINT_KINDS: tuple[str, ...] = ("spread", "mcp", "pip", "dip")  # index .. little
THUMB_JOINT_KINDS: tuple[str, ...] = ("cmc_abduct", "cmc_flex", "mcp", "ip")
TORSO_JOINTS: tuple[str, ...] = (
    "human_step",
    "human_waist_turn",
    "human_waist_lean",
    "human_chest_lean",
)
# the spine's lean, shared between the abdomen and the chest: their sum is the chest's tilt
PERSON_LEAN_JOINTS: tuple[str, ...] = ("human_waist_lean", "human_chest_lean")
NECK_JOINTS: tuple[str, ...] = ("human_neck_yaw", "human_neck_pitch")
PERSON_ARM_KINDS: tuple[str, ...] = (
    "shoulder_flex",
    "shoulder_abduct",
    "shoulder_rot",
    "elbow",
    "forearm_roll",
    "wrist_flex",
    "wrist_dev",
)
PERSON_TORSO_BODY = "human_torso"  # the abdomen: the waist's turn and lean move it (the legs stay)
PERSON_CHEST_BODY = "human_chest"  # its own lean on the abdomen's; the head and arms hang from it
PERSON_HEAD_BODY = "human_head"
# the person's idle hand: its fingers hold one pose, baked into its body (model.idle_hand)
IDLE_HAND_SIDE: Side = "l"
HUMAN_HAND_TURN = "human_r_hand_turn"  # ball joint: the right hand's turn in the mocap frame
PERSON_EYES_SITE = "human_eyes"


def person_hand_joints(side: Side) -> tuple[str, ...]:
    """The 20 joints of one of the person's hands: thumb (CMC two axes, MCP, IP), then per
    finger index .. little (spread, MCP, PIP, DIP); the order of a hand pose's values."""
    out = [f"human_{side}_thumb_{kind}" for kind in THUMB_JOINT_KINDS]
    for finger in PERSON_HAND_FINGERS[1:]:
        out += [f"human_{side}_{finger}_{kind}" for kind in FINGER_JOINT_KINDS]
    return tuple(out)


def person_arm_joints(side: Side) -> tuple[str, ...]:
    """The seven joints of one of the person's arms, shoulder to wrist."""
    return tuple(f"human_{side}_{kind}" for kind in PERSON_ARM_KINDS)


def person_hand_body(side: Side) -> str:
    """Root body (palm) of one of the person's hands."""
    return f"human_{side}_hand"


def person_fingertip_site(side: Side, finger: str) -> str:
    """Site at the tip of one of the person's fingers (:data:`PERSON_HAND_FINGERS`)."""
    return f"human_{side}_{finger}_tip"


def person_wrist_site(side: Side) -> str:
    """Site at the end of the person's forearm (the arm's wrist)."""
    return f"human_{side}_wrist_site"


def person_wrist_point(side: Side) -> str:
    """Site on the person's hand where the forearm meets it (landmark 0 of a hand)."""
    return f"human_{side}_wrist_point"


def person_finger_bodies(side: Side, finger: str) -> tuple[str, str, str]:
    """Bodies of one of the person's fingers, knuckle to tip: ``human_r_index_1`` .. ``_3``."""
    return (f"human_{side}_{finger}_1", f"human_{side}_{finger}_2", f"human_{side}_{finger}_3")


def person_arm_bodies(side: Side) -> tuple[str, str, str]:
    """One of the person's arms: upper arm, forearm and wrist bodies."""
    return (f"human_{side}_upper_arm", f"human_{side}_forearm", f"human_{side}_wrist")
