"""The idle hand baked into one body sits exactly where the jointed hand at its pose sits."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from robin_sim.figure.articulated import subtree_geoms
from robin_sim.model import names
from robin_sim.model.idle_hand import (
    idle_finger_bodies,
    idle_hand_angles,
    idle_hand_joints,
)
from robin_sim.model.person_joints import figure, jointed_scene, pose
from robin_sim.model.scene import build_spec

TOL = 1e-9  # m, and in rotation-matrix entries: the same frames up to rounding


def _hand_geoms(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """Rows (pos, rotation, size, type) of every geom on the idle hand and its fingers,
    sorted, so two models' lists compare whatever the geoms' order."""
    rows = [
        np.concatenate(
            [data.geom_xpos[g], data.geom_xmat[g], model.geom_size[g], [model.geom_type[g]]]
        )
        for g in subtree_geoms(model, names.person_hand_body(names.IDLE_HAND_SIDE))
    ]
    return np.array(sorted(rows, key=lambda r: tuple(np.round(r, 6))))


@pytest.fixture(scope="module")
def jointed() -> tuple[mujoco.MjModel, mujoco.MjData]:
    """``scene.xml`` with its joints, the idle hand's at the idle pose, the rest at zero."""
    model = jointed_scene()
    data = mujoco.MjData(model)
    for name, angle in idle_hand_angles().items():
        data.qpos[model.joint(name).qposadr[0]] = angle
    mujoco.mj_kinematics(model, data)
    return model, data


@pytest.fixture(scope="module")
def baked() -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The scene as episodes build it, posed from zero userdata (no turn anywhere)."""
    model = build_spec().compile()
    data = mujoco.MjData(model)
    pose(model, data)
    mujoco.mj_kinematics(model, data)
    return model, data


def test_baked_hand_geoms_sit_where_the_jointed_hand_puts_them(jointed, baked) -> None:
    want, got = _hand_geoms(*jointed), _hand_geoms(*baked)
    assert got.shape == want.shape and len(got) >= 16  # palm, heel, 15 phalanges
    np.testing.assert_allclose(got, want, atol=TOL)


def test_fingertip_sites_keep_their_names_and_places(jointed, baked) -> None:
    for finger in names.PERSON_HAND_FINGERS:
        site = names.person_fingertip_site(names.IDLE_HAND_SIDE, finger)
        np.testing.assert_allclose(baked[1].site(site).xpos, jointed[1].site(site).xpos, atol=TOL)


def test_idle_fingers_have_no_bodies_joints_or_userdata(baked) -> None:
    model = baked[0]
    for body in idle_finger_bodies():
        assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body) == -1
    for joint in idle_hand_joints():
        assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint) == -1
        with pytest.raises(KeyError):
            figure().joint(joint)
    assert model.nbody == jointed_scene().nbody - len(idle_finger_bodies())
    assert model.nuserdata == figure().size


def test_idle_angles_are_the_library_pose_inside_the_ranges() -> None:
    model = jointed_scene()
    angles = idle_hand_angles()
    assert tuple(angles) == idle_hand_joints()
    moved = 0
    for name, angle in angles.items():
        low, high = model.joint(name).range
        assert low <= angle <= high
        moved += abs(angle) > 1e-3
    assert moved >= 10  # half relaxed: most joints bent, not the zero pose
