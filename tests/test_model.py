"""Robin's MJCF model and scenes: loading, stepping without warnings, names, limits, masses."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import SceneLayout, build_model, build_spec

EIGHT_LEGS = SceneLayout(
    legs=tuple((x, y, math.pi / 2) for x in (0.42, 0.50, 0.60, 0.68) for y in (0.14, 0.46)),
    spots=((0.45, -0.07),),
)


def _load(which: str) -> mujoco.MjModel:
    if which == "robot":
        return mujoco.MjModel.from_xml_path(str(names.ROBOT_XML))
    if which == "scene":
        return mujoco.MjModel.from_xml_path(str(names.SCENE_XML))
    if which == "bench":
        return mujoco.MjModel.from_xml_path(str(names.HAND_TEST_SCENE_XML))
    if which == "legs1":
        return build_model(SceneLayout(legs=((0.5, 0.3, 0.0),)))
    if which == "legs4":
        return build_model()
    if which == "legs8":
        return build_model(EIGHT_LEGS)
    raise AssertionError(which)


def _noisy_run(model: mujoco.MjModel, seed: int, steps: int = 500) -> mujoco.MjData:
    """Step from the home key with control noise (std 10 % of each range, clipped) each step."""
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    rng = np.random.default_rng(seed)
    lo, hi = model.actuator_ctrlrange.T
    home = data.ctrl.copy()
    for _ in range(steps):
        data.ctrl[:] = np.clip(home + rng.normal(0.0, 0.1 * (hi - lo)), lo, hi)
        mujoco.mj_step(model, data)
    return data


@pytest.mark.parametrize("which", ["robot", "scene", "bench", "legs1", "legs4", "legs8"])
def test_steps_one_second_under_noise_without_warnings(which: str) -> None:
    model = _load(which)
    data = _noisy_run(model, seed=7)
    counts = {mujoco.mjtWarning(i).name: data.warning[i].number for i in range(len(data.warning))}
    assert all(n == 0 for n in counts.values()), counts
    assert np.all(np.isfinite(data.qpos))
    assert data.time == pytest.approx(1.0)


def test_same_seed_same_trajectory() -> None:
    model = _load("scene")
    a, b = _noisy_run(model, seed=3, steps=200), _noisy_run(model, seed=3, steps=200)
    np.testing.assert_array_equal(a.qpos, b.qpos)


def test_physics_options_for_friction_grasps() -> None:
    model = _load("scene")
    assert model.opt.timestep == pytest.approx(0.002)
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    assert model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    assert model.opt.impratio == pytest.approx(10.0)


def test_home_keyframe_within_joint_limits_and_collision_free() -> None:
    model = _load("scene")
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    mujoco.mj_forward(model, data)
    for j in range(model.njnt):
        if model.jnt_limited[j]:
            q = data.qpos[model.jnt_qposadr[j]]
            lo, hi = model.jnt_range[j]
            assert lo <= q <= hi, model.joint(j).name
    lo, hi = model.actuator_ctrlrange.T
    assert np.all((lo <= data.ctrl) & (data.ctrl <= hi))
    robot_bodies = {b for b in range(model.nbody) if model.body(b).name.startswith(("l_", "r_"))}
    for c in data.contact[: data.ncon]:
        pair = {int(model.geom_bodyid[c.geom1]), int(model.geom_bodyid[c.geom2])}
        assert not pair & robot_bodies, "the robot touches something at home"


def _scene_names() -> list[tuple[mujoco.mjtObj, str]]:
    obj = mujoco.mjtObj
    want: list[tuple[mujoco.mjtObj, str]] = [
        (obj.mjOBJ_BODY, names.TORSO_BODY),
        (obj.mjOBJ_BODY, names.TABLE_BODY),
        (obj.mjOBJ_GEOM, names.TABLE_TOP_GEOM),
        (obj.mjOBJ_GEOM, names.FLOOR_GEOM),
        (obj.mjOBJ_BODY, names.HUMAN_MOCAP_BODY),
        (obj.mjOBJ_GEOM, names.HUMAN_PALM_GEOM),
        (obj.mjOBJ_SITE, names.HUMAN_PALM_SITE),
        (obj.mjOBJ_KEY, names.HOME_KEY),
        (obj.mjOBJ_CAMERA, names.HEAD_CAMERA),
    ]
    want += [(obj.mjOBJ_JOINT, j) for j in names.HEAD_JOINTS]
    want += [(obj.mjOBJ_ACTUATOR, a) for a in names.HEAD_ACTUATORS]
    want += [(obj.mjOBJ_CAMERA, c) for c in (*names.HEAD_CAMERAS, *names.SCENE_CAMERAS)]
    for side in names.SIDES:
        want += [(obj.mjOBJ_JOINT, j) for j in (*names.arm_joints(side), *names.hand_joints(side))]
        want += [
            (obj.mjOBJ_ACTUATOR, a)
            for a in (*names.arm_actuators(side), *names.hand_actuators(side))
        ]
        want += [(obj.mjOBJ_SITE, names.grasp_site(side)), (obj.mjOBJ_SITE, names.palm_site(side))]
        want += [(obj.mjOBJ_BODY, names.hand_body(side))]
        for finger in names.FINGERS:
            want += [(obj.mjOBJ_SITE, names.fingertip_site(side, finger))]
            want += [(obj.mjOBJ_BODY, b) for b in names.finger_bodies(side, finger)]
    for i in range(4):
        want += [
            (obj.mjOBJ_BODY, names.leg_body(i)),
            (obj.mjOBJ_JOINT, names.leg_joint(i)),
            (obj.mjOBJ_GEOM, names.leg_geom(i)),
        ]
    for side in ("r", "l"):
        person = (*names.person_hand_joints(side), *names.person_arm_joints(side))
        want += [(obj.mjOBJ_JOINT, j) for j in person]
        want += [(obj.mjOBJ_BODY, names.person_hand_body(side))]
        want += [(obj.mjOBJ_BODY, b) for b in names.person_arm_bodies(side)]
        want += [(obj.mjOBJ_SITE, names.person_wrist_site(side))]
        want += [(obj.mjOBJ_SITE, names.person_wrist_point(side))]
        for finger in names.PERSON_HAND_FINGERS:
            want += [(obj.mjOBJ_SITE, names.person_fingertip_site(side, finger))]
            want += [(obj.mjOBJ_BODY, b) for b in names.person_finger_bodies(side, finger)]
    want += [(obj.mjOBJ_JOINT, j) for j in (*names.TORSO_JOINTS, *names.NECK_JOINTS)]
    want += [(obj.mjOBJ_JOINT, names.HUMAN_HAND_TURN), (obj.mjOBJ_SITE, names.PERSON_EYES_SITE)]
    want += [(obj.mjOBJ_BODY, names.PERSON_TORSO_BODY), (obj.mjOBJ_BODY, names.PERSON_HEAD_BODY)]
    want += [
        (obj.mjOBJ_BODY, names.HUMAN_PALM_BODY),
        (obj.mjOBJ_JOINT, names.HUMAN_PALM_JOINT),
        (obj.mjOBJ_EQUALITY, names.HUMAN_PALM_WELD),
        (obj.mjOBJ_SITE, names.HUMAN_PALM_BODY_SITE),
        (obj.mjOBJ_BODY, names.BIN_BODY),
    ]
    want += [(obj.mjOBJ_GEOM, g) for g in (*names.HUMAN_PALM_RIM_GEOMS, *names.BIN_GEOMS)]
    return want


def test_every_name_in_names_module_exists_in_scene() -> None:
    model = _load("scene")
    missing = [n for kind, n in _scene_names() if mujoco.mj_name2id(model, kind, n) < 0]
    assert not missing


def test_bench_has_left_hand_names_and_slides() -> None:
    model = _load("bench")
    wanted = [*names.hand_joints("l"), *names.HAND_TEST_SLIDES]
    assert all(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, n) >= 0 for n in wanted)
    acts = [*names.hand_actuators("l"), *names.HAND_TEST_SLIDES]
    assert all(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_ACTUATOR, n) >= 0 for n in acts)
    assert mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, names.grasp_site("l")) >= 0


def test_the_articulated_person_never_collides_and_the_palm_does() -> None:
    model = _load("scene")
    palm = model.body(names.HUMAN_PALM_BODY).id
    for root in (names.PERSON_BODY, names.HUMAN_MOCAP_BODY):
        top = model.body(root).id
        for g in range(model.ngeom):
            body = int(model.geom_bodyid[g])
            while body not in (0, top):
                body = int(model.body_parentid[body])
            if body == top:
                assert model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0
    assert model.geom(names.HUMAN_PALM_GEOM).bodyid[0] == palm
    assert model.geom(names.HUMAN_PALM_GEOM).contype[0] != 0


@pytest.mark.parametrize("side", names.SIDES)
def test_arm_joint_limits_torques_and_gains_match_lwr(side: names.Side) -> None:
    model = _load("robot")
    for i, joint in enumerate(names.arm_joints(side)):
        limit = spec.ARM_JOINT_LIMITS[i]
        np.testing.assert_allclose(model.joint(joint).range, [-limit, limit], atol=1e-4)
        act = model.actuator(joint)
        np.testing.assert_allclose(act.ctrlrange, [-limit, limit], atol=1e-4)
        tau = spec.ARM_TORQUE_LIMITS[i]
        np.testing.assert_allclose(act.forcerange, [-tau, tau])
        assert act.gainprm[0] > 0 and act.biasprm[2] < 0  # kp and kv (damping) both set
        assert model.joint(joint).armature[0] > 0
    assert spec.ARM_VELOCITY_LIMITS_DEG == (110, 110, 128, 128, 204, 184, 184)


@pytest.mark.parametrize("side", names.SIDES)
def test_arm_link_lengths(side: names.Side) -> None:
    model = _load("robot")
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)  # qpos0: the arm straight
    bodies = names.arm_bodies(side)  # base, link1 .. link7
    base, shoulder, elbow, wrist = (data.xpos[model.body(bodies[i]).id] for i in (0, 2, 4, 6))
    flange = data.xpos[model.body(names.hand_body(side)).id]
    lengths = [np.linalg.norm(b - a) for a, b in ((base, shoulder), (shoulder, elbow))]
    lengths += [np.linalg.norm(b - a) for a, b in ((elbow, wrist), (wrist, flange))]
    np.testing.assert_allclose(lengths, spec.ARM_LINK_LENGTHS, atol=1e-6)
    assert shoulder[2] == pytest.approx(spec.SHOULDER_HEIGHT)


def _descends(model: mujoco.MjModel, body: int, ancestor: int) -> bool:
    while body > 0:
        if body == ancestor:
            return True
        body = int(model.body_parentid[body])
    return False


@pytest.mark.parametrize("side", names.SIDES)
def test_masses_and_inertias_plausible(side: names.Side) -> None:
    """Links 1-6 weigh 1-4 kg, the arm 12-18 kg, the hand 1.5-2.5 kg; inertias are physical."""
    model = _load("robot")
    links = [model.body(name) for name in names.arm_bodies(side)[1:]]
    assert all(1.0 <= b.mass[0] <= 4.0 for b in links[:6])
    assert 12.0 <= sum(b.mass[0] for b in links) <= 18.0
    palm = model.body(names.hand_body(side)).id
    hand_mass = model.body_subtreemass[palm]
    assert 1.5 <= hand_mass <= 2.5
    hand_bodies = [b for b in range(model.nbody) if _descends(model, b, palm)]
    assert len(hand_bodies) == 10  # palm + 3 fingers x (base, proximal, distal)
    for b in [*(link.id for link in links), *hand_bodies]:
        a, c, e = sorted(model.body_inertia[b])
        assert a > 0 and a + c >= e * (1 - 1e-9)  # triangle inequality of principal moments
        assert e <= 0.1
    for link in links[:6]:
        assert 1e-3 <= max(link.inertia) <= 0.05
    arm_and_hand = [link.id for link in links] + hand_bodies
    assert all(model.body_gravcomp[b] == 1.0 for b in arm_and_hand)


def test_thumb_has_twice_the_finger_gain_and_force() -> None:
    model = _load("robot")
    finger, thumb = model.actuator("l_f1_prox"), model.actuator("l_thumb_prox")
    assert thumb.gainprm[0] == pytest.approx(2 * finger.gainprm[0])
    assert thumb.forcerange[1] == pytest.approx(2 * finger.forcerange[1])
    pads = [g for g in range(model.ngeom) if model.geom(g).name.endswith("_pad")]
    assert len(pads) == 12 and all(model.geom_friction[g, 0] >= 0.5 for g in pads)


def test_knuckles_are_coupled() -> None:
    model = _load("bench")
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    data.ctrl[model.actuator("l_knuckle1").id] = 0.8
    for _ in range(500):
        mujoco.mj_step(model, data)
    k1 = data.joint("l_knuckle1").qpos[0]
    assert k1 == pytest.approx(0.8, abs=0.02)
    assert data.joint("l_knuckle2").qpos[0] == pytest.approx(k1, abs=0.01)


def test_arm_tracks_a_step_without_oscillation() -> None:
    """A 0.2 rad step on every left-arm joint settles within 0.3 s, overshoot below 10 %.

    The robot alone (in the scene the stepped hand would come down onto leg 0)."""
    model = _load("robot")
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    acts = [model.actuator(j).id for j in names.arm_actuators("l")]
    adr = [model.joint(j).qposadr[0] for j in names.arm_joints("l")]
    data.ctrl[acts] += 0.2
    errors = []
    for _ in range(500):
        mujoco.mj_step(model, data)
        errors.append(data.qpos[adr] - data.ctrl[acts])
    errors = np.array(errors)
    assert np.abs(errors[150:]).max() < 0.01
    assert errors.max() < 0.02  # overshoot past the target, 10 % of the step


def test_legs_left_alone_do_not_roll() -> None:
    """Each leg's centre moves less than 1 mm in 2 s lying on the table."""
    model = _load("legs4")
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    mujoco.mj_forward(model, data)
    legs = [model.body(names.leg_body(i)).id for i in range(4)]
    start = data.xpos[legs].copy()
    for _ in range(1000):
        mujoco.mj_step(model, data)
    assert np.linalg.norm(data.xpos[legs] - start, axis=1).max() < 1e-3


def test_spec_table_matches_model() -> None:
    model = _load("scene")
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    top = model.geom(names.TABLE_TOP_GEOM)
    centre = data.geom_xpos[top.id]
    assert centre[2] + top.size[2] == pytest.approx(spec.TABLE_TOP_Z)
    assert centre[0] - top.size[0] == pytest.approx(spec.TABLE_X_RANGE[0])
    assert centre[0] + top.size[0] == pytest.approx(spec.TABLE_X_RANGE[1])
    assert centre[1] - top.size[1] == pytest.approx(spec.TABLE_Y_RANGE[0])
    assert centre[1] + top.size[1] == pytest.approx(spec.TABLE_Y_RANGE[1])
    leg = model.geom(names.leg_geom(0))
    assert leg.size[0] == pytest.approx(spec.LEG_RADIUS)
    assert 2 * (leg.size[1] + leg.size[0]) == pytest.approx(spec.LEG_LENGTH)
    assert model.body(names.leg_body(0)).mass[0] == pytest.approx(spec.LEG_MASS)
    palm = model.body(names.hand_body("l")).id
    site = model.site(names.grasp_site("l"))
    assert site.bodyid[0] == palm
    np.testing.assert_allclose(site.pos, [0, 0, spec.GRASP_SITE_FROM_FLANGE])


# --- the person's palm: a dynamic body welded to the mocap hand ---------------------------------
PALM_SITE_IN_HAND = np.array([-0.03, 0.0, 0.012])  # human_palm_site in the hand frame
MOCAP_UPDATE_STEPS = 10  # the mocap pose changes every 10 physics steps (50 Hz control loop)


def _palm_scene(leg_on_palm: bool) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The default scene with the hand held out at the handover point (palm up) and, if asked,
    leg 0 lying along x on the palm (its initial pose in the model; nothing is moved later)."""
    model_spec = build_spec()
    hand = np.array(SceneLayout().handover) - PALM_SITE_IN_HAND
    model_spec.body(names.HUMAN_MOCAP_BODY).pos = hand
    model_spec.body(names.HUMAN_PALM_BODY).pos = hand
    if leg_on_palm:
        model_spec.body(names.leg_body(0)).pos = np.add(SceneLayout().handover, [0, 0, 0.02])
    model = model_spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    for _ in range(250):  # 0.5 s: the leg settles on the palm
        mujoco.mj_step(model, data)
    return model, data


def _move_mocap(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    delta: np.ndarray,
    mean_speed: float,
    roll: float = 0.0,
    each_step=None,
) -> None:
    """Minimum-jerk motion of the mocap hand by ``delta`` (and a roll about x) at mean speed,
    the mocap pose set once per 20 ms control tick as the project's controllers do."""
    mocap = int(model.body_mocapid[model.body(names.HUMAN_MOCAP_BODY).id])
    start = data.mocap_pos[mocap].copy()
    steps = round(max(np.linalg.norm(delta) / mean_speed, 1.5) / model.opt.timestep)
    for i in range(1, steps + 1):
        if (i - 1) % MOCAP_UPDATE_STEPS == 0:  # the project's control loop: new pose every 20 ms
            s = min(1.0, (i - 1 + MOCAP_UPDATE_STEPS) / steps)
            s = 10 * s**3 - 15 * s**4 + 6 * s**5
            data.mocap_pos[mocap] = start + s * np.asarray(delta)
            if roll:
                data.mocap_quat[mocap] = [math.cos(s * roll / 2), math.sin(s * roll / 2), 0, 0]
        mujoco.mj_step(model, data)
        if each_step is not None:
            each_step()


def _no_warnings(data: mujoco.MjData) -> None:
    counts = {mujoco.mjtWarning(i).name: data.warning[i].number for i in range(len(data.warning))}
    assert all(n == 0 for n in counts.values()), counts


def test_palm_is_a_dynamic_body_welded_to_the_mocap_hand() -> None:
    model = _load("scene")
    palm = model.body(names.HUMAN_PALM_BODY)
    assert model.body_mocapid[palm.id] == -1 and palm.mass[0] == pytest.approx(1.0)
    assert model.joint(names.HUMAN_PALM_JOINT).type[0] == mujoco.mjtJoint.mjJNT_FREE
    assert model.geom(names.HUMAN_PALM_GEOM).bodyid[0] == palm.id
    assert model.site(names.HUMAN_PALM_BODY_SITE).bodyid[0] == palm.id
    hand = model.body(names.HUMAN_MOCAP_BODY).id
    assert model.site(names.HUMAN_PALM_SITE).bodyid[0] == hand
    np.testing.assert_allclose(model.site(names.HUMAN_PALM_SITE).pos, PALM_SITE_IN_HAND)
    np.testing.assert_allclose(model.site(names.HUMAN_PALM_BODY_SITE).pos, PALM_SITE_IN_HAND)
    weld = model.equality(names.HUMAN_PALM_WELD)
    assert {int(weld.obj1id[0]), int(weld.obj2id[0])} == {palm.id, hand}


def test_palm_touches_table_legs_only() -> None:
    """The person's palm geoms collide with the legs and nothing else (not the robot)."""
    model = _load("legs4")
    palm_geoms = [model.geom(g).id for g in (names.HUMAN_PALM_GEOM, *names.HUMAN_PALM_RIM_GEOMS)]
    legs = {model.geom(names.leg_geom(i)).id for i in range(4)}
    for p in palm_geoms:
        for g in range(model.ngeom):
            if model.geom_bodyid[g] == model.geom_bodyid[p]:
                continue
            touches = bool(
                model.geom_contype[p] & model.geom_conaffinity[g]
                or model.geom_contype[g] & model.geom_conaffinity[p]
            )
            assert touches == (g in legs), model.geom(g).name


@pytest.mark.slow
def test_palm_follows_the_mocap_hand_smoothly() -> None:
    """The weld (time constant 0.02 s) low-passes the 50 Hz steps of the mocap pose: moved 0.4 m
    at 0.35 m/s peak (the person's free speed) and rolled 2 rad in 1.5 s, the physical palm lags
    by < 2 cm / 0.15 rad (about 0.05 s of motion); at the carrying speed (0.25 m/s peak) it never
    accelerates harder than 10 m/s^2 (friction can carry a leg); holding still, it sits within
    0.1 mm of the hand, at rest."""
    model, data = _palm_scene(leg_on_palm=False)
    palm, hand = model.body(names.HUMAN_PALM_BODY).id, model.body(names.HUMAN_MOCAP_BODY).id
    errors: list[tuple[float, float]] = []
    accelerations: list[float] = []
    velocity = np.zeros(3)

    def record() -> None:
        nonlocal velocity
        turn = data.xmat[hand].reshape(3, 3).T @ data.xmat[palm].reshape(3, 3)
        angle = math.acos(min(1.0, (np.trace(turn) - 1) / 2))
        errors.append((float(np.linalg.norm(data.xpos[palm] - data.xpos[hand])), angle))
        now = data.cvel[palm][3:].copy()
        accelerations.append(float(np.linalg.norm(now - velocity)) / model.opt.timestep)
        velocity = now

    carry, free = 0.25 / 1.875, 0.35 / 1.875  # mean speeds (min-jerk peak = 1.875 x mean)
    _move_mocap(model, data, np.array([0.4, 0.0, 0.0]), carry, each_step=record)
    assert max(accelerations[1:]) < 10.0  # carrying a leg along x
    _move_mocap(model, data, np.array([-0.4, 0.0, 0.0]), free, each_step=record)
    _move_mocap(model, data, np.array([0.0, -0.3, 0.1]), free, roll=2.0, each_step=record)
    position_error, angle_error = np.max(errors, axis=0)
    assert position_error < 0.02 and angle_error < 0.15
    errors.clear()
    for _ in range(500):  # 1 s holding still: no jitter
        mujoco.mj_step(model, data)
        record()
    assert np.max(errors, axis=0)[0] < 1e-4
    assert np.linalg.norm(data.cvel[palm]) < 1e-3
    _no_warnings(data)


@pytest.mark.slow
def test_palm_carries_a_leg_by_friction_and_tips_it_off() -> None:
    """A leg lying on the palm stays on it (within 1 cm of where it lay, in the palm frame) while
    the hand moves 0.4 m at 0.12 m/s along x and back, then along y and back; rolling the palm
    2 rad about x tips it off."""
    model, data = _palm_scene(leg_on_palm=True)
    palm, leg = model.body(names.HUMAN_PALM_BODY).id, model.body(names.leg_body(0)).id

    def on_palm() -> np.ndarray:
        return data.xmat[palm].reshape(3, 3).T @ (data.xpos[leg] - data.xpos[palm])

    start = on_palm()
    np.testing.assert_allclose(start, PALM_SITE_IN_HAND + np.array([0, 0, 0.02]), atol=1e-3)
    drift: list[float] = []
    for delta in ([0.4, 0, 0], [-0.4, 0, 0], [0, -0.4, 0], [0, 0.4, 0]):
        _move_mocap(
            model,
            data,
            np.array(delta),
            0.12,
            each_step=lambda: drift.append(float(np.linalg.norm(on_palm() - start))),
        )
    assert max(drift) < 0.01
    _move_mocap(model, data, np.zeros(3), 1.0, roll=2.0)
    for _ in range(500):
        mujoco.mj_step(model, data)
    assert np.linalg.norm(on_palm() - start) > 0.1  # off the palm
    assert data.xpos[leg][2] < data.xpos[palm][2] - 0.05  # fell below it
    _no_warnings(data)
