"""The person's idle left hand, baked into one body: its fingers never move.

The left hand only hangs (:mod:`robin_sim.figure.idle_arm`); its fingers hold the pose
library's ``neutral`` pose for the whole of every episode. So the scene gives them no bodies
of their own: :func:`bake_idle_hand` turns each of the 15 finger bodies into a frame of
``human_l_hand`` posed at that pose (MuJoCo flattens frames when it compiles), and the hand's
20 finger joints get no ``userdata``. The geoms and the fingertip sites keep their names and
their places to the last bit of the pose, so a render cannot tell the baked hand from the
jointed one (``tests/test_idle_hand.py``); the physics carries 15 bodies fewer
(``bench/bench_person_physics.py``).
"""

from __future__ import annotations

import mujoco
import numpy as np

from robin_sim.model import names
from robin_sim.model.person_joints import axis_quats, jointed_scene, quat_products
from robin_sim.model.pose_library import load_library

IDLE_SIDE = names.IDLE_HAND_SIDE
IDLE_POSE = "neutral"  # the library's pose the idle hand holds


def idle_hand_joints() -> tuple[str, ...]:
    """The idle hand's 20 finger joints, baked (no ``userdata``)."""
    return names.person_hand_joints(IDLE_SIDE)


def idle_finger_bodies() -> tuple[str, ...]:
    """The idle hand's finger bodies, knuckle before tip, that become frames."""
    return tuple(
        body
        for finger in names.PERSON_HAND_FINGERS
        for body in names.person_finger_bodies(IDLE_SIDE, finger)
    )


def idle_hand_angles() -> dict[str, float]:
    """Each idle finger joint's angle: the library's pose, inside the joint's range."""
    model = jointed_scene()
    pose = load_library().pose(IDLE_POSE)
    out = {}
    for name, angle in zip(idle_hand_joints(), pose, strict=True):
        low, high = model.joint(name).range
        out[name] = float(np.clip(angle, low, high))
    return out


def baked_frames() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each idle finger body's frame in its parent (pos, quat) at the idle pose: its resolved
    frame turned by its joints in order, each about its axis through the body's origin."""
    model, angles = jointed_scene(), idle_hand_angles()
    frames = {}
    for body in idle_finger_bodies():
        b = model.body(body)
        quat = b.quat[None].copy()
        for j in range(int(b.jntadr[0]), int(b.jntadr[0] + b.jntnum[0])):
            joint = model.joint(j)
            if np.any(joint.pos):
                raise ValueError(f"{joint.name} turns about {joint.pos}, not its body's origin")
            quat = quat_products(quat, axis_quats(joint.axis[None], np.array([angles[joint.name]])))
        frames[body] = (b.pos.copy(), quat[0])
    return frames


def bake_idle_hand(spec: mujoco.MjSpec) -> None:
    """Turn the idle hand's finger bodies in ``spec`` into frames of the hand at the idle pose
    (module doc); their joints are deleted."""
    for body_name, (pos, quat) in baked_frames().items():
        body = spec.body(body_name)
        for joint in list(body.joints):
            spec.delete(joint)
        body.alt.type = mujoco.mjtOrientation.mjORIENTATION_QUAT
        body.pos, body.quat = pos, quat
        body.to_frame()
