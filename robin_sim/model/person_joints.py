"""The person's joints, kept out of the physics: angles in ``data.userdata``, poses in body frames.

The person is driven, never pushed, so the integrator need not carry its DoFs. ``person.xml``
describes it with joints (readable, and the figure's code names them); :func:`strip_joints`
deletes them from the scene's spec and gives the model ``userdata`` for their positions instead
(one value per hinge or slide, four per ball), in the joints' order in the scene, so that a
joint's "qpos address" is its address in ``data.userdata`` (:func:`figure_joint`). Every person
body then hangs welded from its parent; :func:`pose` writes each body's frame relative to its
parent (``model.body_pos`` / ``body_quat``) from the angles, the way MuJoCo's kinematics applies
joints (in order, each about its axis in the body frame as turned so far, through its anchor),
and the next kinematics (any ``mj_step`` or ``mj_forward``) places the bodies. Measured
(``bench/bench_person_physics.py``): the person adds 6-8 % to ``mj_step`` this way, 33 % with
its 62 joint DoFs.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import mujoco
import numpy as np

from robin_sim.model import names

BALL, SLIDE = int(mujoco.mjtJoint.mjJNT_BALL), int(mujoco.mjtJoint.mjJNT_SLIDE)


@dataclass(frozen=True)
class FigureJoint:
    """One of the person's joints as ``person.xml`` has it, and where its value lives."""

    name: str
    kind: int  # mujoco.mjtJoint
    body: str
    axis: np.ndarray  # (3,) in the body frame
    anchor: np.ndarray  # (3,) in the body frame
    range: np.ndarray  # (2,) low, high
    adr: int  # first index in data.userdata
    size: int  # values: 4 for a ball (a quaternion), else 1


@dataclass(frozen=True)
class Figure:
    """Every person joint, and the un-posed frame of every body that has one."""

    joints: tuple[FigureJoint, ...]
    bodies: tuple[str, ...]  # bodies with joints, parents before children
    base_pos: np.ndarray  # (len(bodies), 3)
    base_quat: np.ndarray  # (len(bodies), 4)
    size: int  # userdata values in all

    def joint(self, name: str) -> FigureJoint:
        """The joint ``name``; ``KeyError`` naming the valid ones."""
        for joint in self.joints:
            if joint.name == name:
                return joint
        raise KeyError(f"no person joint {name!r}; valid: {[j.name for j in self.joints]}")

    def adr(self, joint_names: tuple[str, ...] | list[str]) -> np.ndarray:
        """userdata addresses of one-valued joints ``joint_names``."""
        return np.array([self.joint(n).adr for n in joint_names], dtype=int)

    def ranges(self, joint_names: tuple[str, ...] | list[str]) -> np.ndarray:
        """(n, 2) ranges of ``joint_names``."""
        return np.array([self.joint(n).range for n in joint_names])

    def base_quat_of(self, body: str) -> np.ndarray:
        """The un-posed rotation (w, x, y, z) of ``body`` in its parent."""
        return self.base_quat[self.bodies.index(body)].copy()


def is_person_joint(name: str) -> bool:
    """Whether a scene joint called ``name`` is one of the person's (not the palm's)."""
    return name.startswith("human_") and name != names.HUMAN_PALM_JOINT


@functools.cache
def jointed_scene() -> mujoco.MjModel:
    """``scene.xml`` compiled as written, the person with its joints: the bodies' frames."""
    return mujoco.MjModel.from_xml_path(str(names.SCENE_XML))


@functools.cache
def figure() -> Figure:
    """The person's posed joints and their bodies, read once from :func:`jointed_scene`; the
    idle hand's fingers are baked, not posed (:mod:`robin_sim.model.idle_hand`)."""
    model = jointed_scene()
    baked = set(names.person_hand_joints(names.IDLE_HAND_SIDE))
    joints, bodies, adr = [], [], 0
    for j in range(model.njnt):
        if not is_person_joint(model.joint(j).name) or model.joint(j).name in baked:
            continue
        kind = int(model.jnt_type[j])
        size = 4 if kind == BALL else 1
        body = model.body(int(model.jnt_bodyid[j])).name
        joints.append(
            FigureJoint(
                model.joint(j).name,
                kind,
                body,
                model.jnt_axis[j].copy(),
                model.jnt_pos[j].copy(),
                model.jnt_range[j].copy(),
                adr,
                size,
            )
        )
        if body not in bodies:
            bodies.append(body)
        adr += size
    ids = [model.body(b).id for b in bodies]
    return Figure(
        tuple(joints), tuple(bodies), model.body_pos[ids].copy(), model.body_quat[ids].copy(), adr
    )


def strip_joints(spec: mujoco.MjSpec) -> None:
    """Delete the person's joints from the scene's ``spec`` (the idle hand's baked before:
    :func:`robin_sim.model.idle_hand.bake_idle_hand`) and give it the posed ones' userdata;
    the person's bodies keep no gravity compensation (nothing moves them)."""
    for joint in list(spec.joints):
        if is_person_joint(joint.name):
            spec.delete(joint)
    spec.nuserdata = figure().size
    kept = (names.HUMAN_MOCAP_BODY, names.HUMAN_PALM_BODY)
    for body in spec.bodies:
        if body.name.startswith(names.PERSON_BODY) and body.name not in kept:
            body.gravcomp = 0.0


def has_figure(model: mujoco.MjModel) -> bool:
    """Whether ``model`` holds the articulated person posed from userdata."""
    return model.nuserdata >= figure().size and all(
        mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, b) >= 0 for b in figure().bodies
    )


@dataclass(frozen=True)
class _Plan:
    """:func:`pose` as array operations: the slides' offsets, then the joints' turns level by
    level (a body's first joints, then its second ones, ...)."""

    slide_body: np.ndarray  # index into Figure.bodies
    slide_adr: np.ndarray
    slide_dir: np.ndarray  # (n, 3) the slide's axis in the parent's frame
    levels: tuple[
        tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray], ...
    ]  # body, adr, axis, ball


@functools.cache
def _plan() -> _Plan:
    """The plan of :func:`figure`'s joints; refuses joints :func:`pose` does not place (a slide
    after a turn in its body, an anchor off the body's origin)."""
    fig = figure()
    slides: list[tuple[int, int, np.ndarray]] = []
    levels: list[list[tuple[int, int, np.ndarray, bool]]] = []
    turned: dict[int, int] = {}
    for joint in fig.joints:
        body = fig.bodies.index(joint.body)
        if joint.kind == SLIDE:
            if body in turned:
                raise ValueError(f"slide {joint.name} follows a turn in its body")
            rotation = np.zeros(9)
            mujoco.mju_quat2Mat(rotation, fig.base_quat[body])
            slides.append((body, joint.adr, rotation.reshape(3, 3) @ joint.axis))
            continue
        if np.any(joint.anchor):
            raise ValueError(f"joint {joint.name} turns about {joint.anchor}, not its body origin")
        level = turned.get(body, 0)
        turned[body] = level + 1
        while len(levels) <= level:
            levels.append([])
        levels[level].append((body, joint.adr, joint.axis, joint.kind == BALL))
    return _Plan(
        np.array([b for b, _, _ in slides], dtype=int),
        np.array([a for _, a, _ in slides], dtype=int),
        np.array([d for _, _, d in slides]).reshape(-1, 3),
        tuple(
            (
                np.array([b for b, *_ in level], dtype=int),
                np.array([a for _, a, *_ in level], dtype=int),
                np.array([x for _, _, x, _ in level]),
                np.array([ball for *_, ball in level], dtype=bool),
            )
            for level in levels
        ),
    )


def axis_quats(axes: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """(n, 4) quaternions (w, x, y, z) of turns ``angles`` about unit ``axes`` (n, 3)."""
    half = 0.5 * np.asarray(angles)
    return np.column_stack([np.cos(half), np.sin(half)[:, None] * axes])


def quat_products(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise quaternion products a b, (n, 4) each (w, x, y, z)."""
    w1, x1, y1, z1 = a.T
    w2, x2, y2, z2 = b.T
    return np.stack(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ],
        axis=1,
    )


def pose(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """Write every person body's frame from the angles in ``data.userdata`` (module doc); a
    ball's zero quaternion (fresh data) reads as no turn."""
    fig, plan = figure(), _plan()
    values = data.userdata
    pos, quat = fig.base_pos.copy(), fig.base_quat.copy()
    pos[plan.slide_body] += plan.slide_dir * values[plan.slide_adr][:, None]
    for body, adr, axis, ball in plan.levels:
        turn = axis_quats(axis, values[adr])
        for k in np.flatnonzero(ball):
            q = values[adr[k] : adr[k] + 4]
            norm = float(np.linalg.norm(q))
            turn[k] = q / norm if norm > 1e-12 else (1.0, 0.0, 0.0, 0.0)
        quat[body] = quat_products(quat[body], turn)
    ids = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, b) for b in fig.bodies]
    model.body_pos[ids] = pos
    model.body_quat[ids] = quat
