"""Aim Robin's head (pan/tilt position actuators) at a point, e.g. the person's hand.

:func:`head_angles` gives the pan and tilt that point the head's optical axis at a world point,
within the joints' limits from the model. :func:`look_at` commands the head actuators and lets
the simulator run until the head is there (a real look, physics included);
:func:`pose_head` writes the angles into ``qpos`` for kinematic-only rendering of data sets
(never used in an episode).
"""

from __future__ import annotations

import mujoco
import numpy as np

from robin_sim.control.simulator import Simulator
from robin_sim.model import names

PAN, TILT = names.HEAD_JOINTS
SETTLE_TOLERANCE = 0.01  # rad: the head has arrived when both joints are this close
LOOK_TIMEOUT = 0.8  # s of simulated time a look may take at most


def head_angles(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    target: np.ndarray,
    origin: np.ndarray | None = None,
) -> np.ndarray:
    """(pan, tilt) in rad aiming the head's forward axis at ``target``, clipped to the limits.

    Positive tilt looks down (the tilt joint turns about +y). The aim is taken from
    ``origin`` (default: the tilt joint's anchor; an eye camera's position makes that eye's
    optical axis, parallel to the forward axis, pass through ``target``). ``data`` must hold
    a forward pass (the anchor is read from it).
    """
    anchor = data.xpos[int(model.joint(TILT).bodyid[0])] if origin is None else origin
    v = np.asarray(target, float) - anchor
    pan_id, tilt_id = model.joint(PAN).id, model.joint(TILT).id
    pan = np.clip(np.arctan2(v[1], v[0]), *model.jnt_range[pan_id])
    tilt = np.clip(np.arctan2(-v[2], np.hypot(v[0], v[1])), *model.jnt_range[tilt_id])
    return np.array([pan, tilt])


def head_qpos(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """Current (pan, tilt) of the head joints."""
    return np.array([data.qpos[model.jnt_qposadr[model.joint(j).id]] for j in names.HEAD_JOINTS])


def pose_head(model: mujoco.MjModel, data: mujoco.MjData, target: np.ndarray) -> np.ndarray:
    """Write the aiming angles into ``qpos`` and ``ctrl`` and update kinematics (renders only)."""
    mujoco.mj_kinematics(model, data)
    angles = head_angles(model, data, target)
    for joint, angle in zip(names.HEAD_JOINTS, angles, strict=True):
        data.qpos[model.jnt_qposadr[model.joint(joint).id]] = angle
        data.actuator(joint).ctrl[0] = angle
    mujoco.mj_kinematics(model, data)
    mujoco.mj_camlight(model, data)
    return angles


def look_at(sim: Simulator, target: np.ndarray, timeout: float = LOOK_TIMEOUT) -> bool:
    """Command the head at ``target`` and run ``sim`` until it is there; True if it arrived."""
    model, data = sim.model, sim.data
    angles = head_angles(model, data, target)
    for joint, angle in zip(names.HEAD_ACTUATORS, angles, strict=True):
        data.actuator(joint).ctrl[0] = angle

    def arrived(_: Simulator) -> bool:
        return bool(np.all(np.abs(head_qpos(model, data) - angles) < SETTLE_TOLERANCE))

    return arrived(sim) or sim.step_until(arrived, timeout)
