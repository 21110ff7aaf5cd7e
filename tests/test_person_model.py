"""The articulated person (models/person/person.xml): joints, limits, rest pose, reach, looks;
its joints kept out of the physics and posed from userdata exactly as MuJoCo's joints would."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from robin_sim.figure.articulated import ArticulatedHand
from robin_sim.figure.posture import Posture
from robin_sim.model import names, person_joints
from robin_sim.model import robot_spec as spec
from robin_sim.model.idle_hand import idle_hand_angles
from robin_sim.model.person_joints import figure, is_person_joint
from robin_sim.model.scene import LEG_COLORS, SceneLayout, build_model

HINGE = mujoco.mjtJoint.mjJNT_HINGE


@pytest.fixture(scope="module")
def scene() -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = build_model()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    return model, data


def _subtree(model: mujoco.MjModel, root: str) -> list[int]:
    top = model.body(root).id
    out = []
    for g in range(model.ngeom):
        b = int(model.geom_bodyid[g])
        while b not in (0, top):
            b = int(model.body_parentid[b])
        if b == top:
            out.append(g)
    return out


def test_each_hand_has_the_21_landmark_skeleton_with_limited_joints(scene) -> None:
    """Both hands as person.xml writes them (the jointed scene); in the episode's scene the
    right hand keeps them posed from userdata, the idle left hand's fingers are baked (its
    landmark sites stay: tests/test_idle_hand.py)."""
    model, jointed = scene[0], person_joints.jointed_scene()
    for side in ("r", "l"):
        joints = names.person_hand_joints(side)
        assert len(joints) == 20  # >= 15: three per finger (and a spread), the thumb 4
        for name in joints:
            j = jointed.joint(name)
            assert j.type[0] == HINGE
            low, high = j.range
            assert low < 0.0 <= high and high - low > 0.5, name  # the straight hand is inside
            if side != names.IDLE_HAND_SIDE:
                assert figure().joint(name).kind == HINGE
        # the thumb's base: two joints in one body, about different axes
        base = jointed.body(names.person_finger_bodies(side, "thumb")[0])
        adr = int(base.jntadr[0])
        axes = jointed.jnt_axis[adr : adr + int(base.jntnum[0])]
        assert len(axes) == 2 and abs(float(np.dot(*axes))) < 0.1
        # 21 landmarks: the wrist point, and per finger three bodies (knuckles) and a tip
        for m in (model, jointed):
            assert m.site(names.person_wrist_point(side)).id >= 0
        for finger in names.PERSON_HAND_FINGERS:
            assert all(jointed.body(b).id >= 0 for b in names.person_finger_bodies(side, finger))
            assert model.site(names.person_fingertip_site(side, finger)).id >= 0


def test_arms_head_and_torso_joints_are_limited() -> None:
    for name in (
        *names.person_arm_joints("r"),
        *names.person_arm_joints("l"),
        *names.NECK_JOINTS,
        *names.TORSO_JOINTS,
    ):
        j = figure().joint(name)
        assert j.range[0] < j.range[1], name
        assert j.range[0] <= 0.0 <= j.range[1], name  # zero: standing upright, arms hanging


def test_no_segment_touches_the_table_or_bin_at_rest(scene) -> None:
    model, data = scene
    posture = Posture(model, data)
    ArticulatedHand(model, data).show("neutral")
    posture.update()
    mujoco.mj_kinematics(model, data)
    mujoco.mj_collision(model, data)
    assert posture.gap < 1e-3 and all(
        abs(data.userdata[figure().joint(j).adr]) < 1e-5 for j in names.TORSO_JOINTS
    )  # at rest the person stands upright where the file puts them
    person = _subtree(model, names.PERSON_BODY) + _subtree(model, names.HUMAN_MOCAP_BODY)
    fixed = _subtree(model, names.TABLE_BODY) + _subtree(model, names.BIN_BODY)
    fromto = np.zeros(6)
    closest = min(
        mujoco.mj_geomDistance(model, data, p, t, 1.0, fromto) for p in person for t in fixed
    )
    assert closest > 0.01, f"a person segment comes within {closest:.3f} m of the table or bin"


def test_the_arm_meets_the_hand_where_the_person_gestures(scene) -> None:
    """The forearm's end lies on the hand's wrist (2 mm) at the handover point and above every
    default leg and spot, and the hand faces within 25 degrees of what the wrist can do."""
    model, data = scene
    layout = SceneLayout()
    hand, posture = ArticulatedHand(model, data), Posture(model, data)
    mocap = model.body(names.HUMAN_MOCAP_BODY).mocapid[0]
    places = [("give_me", np.array(layout.handover) - model.site(names.HUMAN_PALM_SITE).pos)]
    offset = np.array(spec.POINT_OFFSET)
    z_leg, z_spot = spec.TABLE_TOP_Z + spec.LEG_RADIUS, spec.TABLE_TOP_Z
    places += [("pointing", np.array([x, y, z_leg]) + offset) for x, y, _ in layout.legs]
    places += [("pointing", np.array([x, y, z_spot]) + offset) for x, y in layout.spots]
    for pose, at in places:
        data.mocap_pos[mocap] = at
        hand.show(pose)
        posture.update()
        mujoco.mj_kinematics(model, data)
        arm = data.site(names.person_wrist_site("r")).xpos
        wrist = data.site(names.person_wrist_point("r")).xpos
        assert np.linalg.norm(arm - wrist) < 2e-3, (pose, at)
        assert posture.wrist_error < np.radians(25), (pose, at, posture.wrist_error)


def test_clothes_look_like_no_leg(scene) -> None:
    """Every garment (and hair, eyes, shoes) is at least 0.2 (RGB distance) from every leg
    colour; the skin geoms take the vision code's tones (``skin`` 0-4) at run time."""
    model, _ = scene
    legs = np.array(LEG_COLORS)[:, :3]
    worn = [g for g in _subtree(model, names.PERSON_BODY) if model.geom_matid[g] >= 0]
    assert len(worn) >= 10
    for g in worn:
        rgb = model.mat_rgba[model.geom_matid[g], :3]
        assert np.min(np.linalg.norm(legs - rgb, axis=1)) > 0.2, (g, rgb)
    skin = ArticulatedHand(model, mujoco.MjData(model)).skin_geoms
    # two hands of 17 geoms, the neck, the face, two wrists
    assert len(skin) == 38 and not set(skin.tolist()) & set(worn)


def test_the_person_has_no_dofs_and_poses_as_its_joints_would(scene) -> None:
    """The scene keeps none of the person's joints (the integrator pays for none of them);
    :func:`person_joints.pose` places every person geom and site where MuJoCo's own kinematics
    puts them in ``scene.xml`` compiled with the joints, for random angles within the limits."""
    model, _ = scene
    assert not any(is_person_joint(model.joint(j).name) for j in range(model.njnt))
    # 43 posed DoFs, one a ball (a quaternion); the idle hand's 20 are baked (model.idle_hand)
    assert model.nuserdata == figure().size == 44
    jointed = mujoco.MjModel.from_xml_path(str(names.SCENE_XML))
    assert jointed.nv - model.nv == 63
    rng = np.random.default_rng(0)
    for _ in range(3):
        a, b = mujoco.MjData(jointed), mujoco.MjData(model)
        for name, angle in idle_hand_angles().items():
            a.qpos[jointed.joint(name).qposadr[0]] = angle
        for j in figure().joints:
            adr = jointed.joint(j.name).qposadr[0]
            if j.size == 4:
                value = rng.normal(size=4)
                value /= np.linalg.norm(value)
            else:
                value = np.array([rng.uniform(*j.range)])
            a.qpos[adr : adr + j.size] = value
            b.userdata[j.adr : j.adr + j.size] = value
        mujoco.mj_kinematics(jointed, a)
        person_joints.pose(model, b)
        mujoco.mj_kinematics(model, b)
        for kind, count in (
            (mujoco.mjtObj.mjOBJ_GEOM, jointed.ngeom),
            (mujoco.mjtObj.mjOBJ_SITE, jointed.nsite),
        ):
            for k in range(count):
                name = mujoco.mj_id2name(jointed, kind, k)
                if not name or not name.startswith("human_"):
                    continue
                if kind == mujoco.mjtObj.mjOBJ_GEOM:
                    np.testing.assert_allclose(b.geom(name).xpos, a.geom_xpos[k], atol=1e-9)
                    np.testing.assert_allclose(b.geom(name).xmat, a.geom_xmat[k], atol=1e-9)
                else:
                    np.testing.assert_allclose(b.site(name).xpos, a.site_xpos[k], atol=1e-9)
