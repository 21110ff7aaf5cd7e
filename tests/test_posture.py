"""The person's posture (robin_sim.figure.posture): the lean is what reaching needs, the torso
bends in two segments, the idle left arm keeps clear of the table and the bin.

*The lean* is the chest's tilt from vertical (rad, positive forwards): the sum of the two lean
joints ``human_waist_lean`` and ``human_chest_lean`` (about one axis, so the sum is the tilt;
:func:`robin_sim.figure.torso.lean_of`, checked against MuJoCo's kinematics below). Its limit is
the sum of their upper limits, 0.9 rad (:func:`~robin_sim.figure.torso.lean_limit`).

The episode tests run real episodes (MuJoCo physics, EGL renders at a small size, their states
files; three seeds of one_handover, two of table_one), apply each recorded state and read the
lean the run wrote (issue 40: the single-box
torso sat at its 0.9 rad limit in 58 % of one_handover's frames).
"""

from __future__ import annotations

from recorded_episode import record_episode

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()  # before mujoco is imported (see robin_sim.render.gl_backend)

import mujoco  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from robin_sim.figure.articulated import ArticulatedHand, subtree_geoms  # noqa: E402
from robin_sim.figure.idle_arm import TABLE_CLEARANCE  # noqa: E402
from robin_sim.figure.posture import SWIVEL_TRY, Posture  # noqa: E402
from robin_sim.figure.torso import COMFORT, Torso, TorsoPose, lean_limit, lean_of  # noqa: E402
from robin_sim.model import names, person_joints  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402
from robin_sim.render.state_log import RecordedStates  # noqa: E402
from robin_sim.render.worker import apply_state  # noqa: E402

REST = (1.22, 0.28, 0.92)  # the hand's rest place (issue 40's reproduction)
REST_LEAN = 0.35  # rad: at the rest place no gesture leans more (the limit is 0.9)
EPISODES = [("one_handover", 0), ("one_handover", 1), ("one_handover", 2)]
EPISODES += [("table_one", 0), ("table_one", 1)]
BELOW_LIMIT = 0.95  # share of an episode's frames whose lean stays below the limit
# rad: an episode's median lean. The person stands upright while the arm reaches and steps
# before leaning; what leans is the reach over the table: about 0.56 rad at the full step to
# hold the hand out at the handover point (x = 0.63 m, 0.54 m in front of the stepped feet,
# 0.58 m below the shoulder, for an arm of 0.60 m), 0.6 to point at the far legs. one_handover
# holds the hand out for about half its frames, table_one (three handovers, more gestures at
# the rest place) for a tenth. Measured (seeds 0-2): one_handover 0.40-0.56, table_one
# 0.01-0.07; with the single box 0.90 and 0.49-0.63 (issue 40). With the right arm kept
# clear of legs and Robin (posture.CLEAR_LEANS): one_handover 0.40, 0.44, 0.57 (seeds 0-2),
# table_one 0.013 (seeds 0-1).
MEDIAN_LEAN = {"one_handover": 0.6, "table_one": 0.15}
# rad of lean beyond the least with which any step and turn bring the shoulder within the
# comfortable reach of the wrist: in half the frames at most EXCESS_MEDIAN (measured 0.013),
# in nine in ten at most EXCESS_P90 (0.03-0.04; more where a lean buys the wrist its turn).
# Frames where the cheapest torso's arm would reach into a leg or Robin are left out: there the
# person leans further to keep the arm clear (posture.CLEAR_LEANS; measured on 10 fps records:
# one_handover seeds 0-2 15-37 % of frames, table_one seed 0 7 %; there 0.16-0.20 rad more
# than the least in median); tests/test_person_clearance checks that arm
EXCESS_MEDIAN = 0.03
EXCESS_P90 = 0.1
ARM_CLEAR = 0.01  # m: the idle arm's geoms from the table's and the bin's, on every frame


@pytest.fixture(scope="module")
def scene() -> tuple[mujoco.MjModel, mujoco.MjData, Posture, ArticulatedHand]:
    model = build_model()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    return model, data, Posture(model, data), ArticulatedHand(model, data)


def _obstacles(model: mujoco.MjModel) -> np.ndarray:
    return np.concatenate(
        [subtree_geoms(model, names.TABLE_BODY), subtree_geoms(model, names.BIN_BODY)]
    )


def _arm_clearance(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """The nearest the idle arm's geoms (upper arm to fingertips) come to the table or bin."""
    arm = subtree_geoms(model, names.person_arm_bodies("l")[0])
    fromto = np.zeros(6)
    return min(
        mujoco.mj_geomDistance(model, data, int(a), int(b), 1.0, fromto)
        for a in arm
        for b in _obstacles(model)
    )


def _miss(data: mujoco.MjData) -> float:
    """How far the right arm's wrist lies from the hand's wrist point (m)."""
    arm = data.site(names.person_wrist_site("r")).xpos
    return float(np.linalg.norm(arm - data.site(names.person_wrist_point("r")).xpos))


def test_the_lean_is_the_chest_tilt_from_vertical(scene) -> None:
    model, _, _, _ = scene
    data = mujoco.MjData(model)
    fig = person_joints.figure()
    rng = np.random.default_rng(1)
    for _ in range(20):
        for name in names.TORSO_JOINTS:
            data.userdata[fig.joint(name).adr] = rng.uniform(*fig.joint(name).range)
        person_joints.pose(model, data)
        mujoco.mj_kinematics(model, data)
        up = data.body(names.PERSON_CHEST_BODY).xmat.reshape(3, 3)[:, 2]
        turn = data.userdata[fig.joint("human_waist_turn").adr]
        forwards = np.array([-np.cos(turn), -np.sin(turn), 0.0])  # the turned person's front
        side = np.array([-np.sin(turn), np.cos(turn), 0.0])
        tilt = float(np.arctan2(up @ forwards, up[2]))
        assert abs(tilt - lean_of(data.userdata)) < 1e-9 and abs(up @ side) < 1e-9
    assert lean_limit() == pytest.approx(0.9)


def test_the_torso_places_the_shoulder_as_the_model_does(scene) -> None:
    """:meth:`Torso.shoulders` and :meth:`Torso.chest_frame` (what the search costs) against
    MuJoCo's kinematics of the posed person, for random steps, turns and leans."""
    model, _, posture, _ = scene
    data = mujoco.MjData(model)
    fig = person_joints.figure()
    torso = posture.torso
    rng = np.random.default_rng(2)
    for _ in range(20):
        pose = TorsoPose(
            rng.uniform(*torso.step_range), rng.uniform(*torso.turn_range), rng.uniform(0, 0.9)
        )
        values = (pose.step, pose.turn, *torso.lean_joints(pose.lean))
        for name, value in zip(names.TORSO_JOINTS, values, strict=True):
            data.userdata[fig.joint(name).adr] = value
        person_joints.pose(model, data)
        mujoco.mj_kinematics(model, data)
        shoulder = torso.shoulders(*(np.array([v]) for v in (pose.step, pose.turn, pose.lean)))
        upper_arm = data.body(names.person_arm_bodies("r")[0])
        np.testing.assert_allclose(shoulder[0], upper_arm.xpos, atol=1e-9)
        origin, rotation = torso.chest_frame(pose)
        np.testing.assert_allclose(origin, data.body(names.PERSON_CHEST_BODY).xpos, atol=1e-9)
        chest = data.body(names.PERSON_CHEST_BODY).xmat.reshape(3, 3)
        np.testing.assert_allclose(rotation, chest, atol=1e-9)


@pytest.mark.parametrize("gesture", names.HUMAN_VIS_POSES)
def test_at_the_rest_place_no_gesture_bows(scene, gesture: str) -> None:
    """Issue 40's reproduction: the hand at the rest place showed give me, release, grasp or
    thumb up with the waist at its 0.9 rad limit; now the person stands nearly upright."""
    model, data, posture, hand = scene
    data.mocap_pos[model.body(names.HUMAN_MOCAP_BODY).mocapid[0]] = REST
    hand.show(gesture)
    posture.update()
    mujoco.mj_kinematics(model, data)
    assert lean_of(data.userdata) < REST_LEAN, (gesture, lean_of(data.userdata))
    assert posture.gap < 2e-3
    if gesture == "neutral":  # the hand where the file puts it: the person as the file stands
        fig = person_joints.figure()
        assert all(abs(data.userdata[fig.joint(j).adr]) < 1e-5 for j in names.TORSO_JOINTS)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(
    x=st.floats(0.75, 1.35),
    y=st.floats(-0.1, 0.5),
    z=st.floats(0.8, 1.3),
    gesture=st.sampled_from(["neutral", "pointing", "give_me"]),
)
def test_the_lean_is_what_reaching_needs_and_no_more(scene, x, y, z, gesture) -> None:
    """Wherever the hand goes: upright while the upright shoulder reaches the wrist; else no
    torso pose on a fine grid costs less than the one chosen (the lean costs most, so none
    with less lean reaches as well at the same cost); the arm meets the hand where it can."""
    model, data, posture, hand = scene
    data.mocap_pos[model.body(names.HUMAN_MOCAP_BODY).mocapid[0]] = (x, y, z)
    hand.show(gesture)
    values = posture.solve()
    wrist, hand_turn = posture.hand_frame()
    torso = posture.torso
    chosen = TorsoPose(values["human_step"], values["human_waist_turn"], lean_of_values(values))
    upright = torso.shoulders(np.zeros(1), np.zeros(1), np.zeros(1))[0]
    reaches = np.linalg.norm(wrist - upright) <= COMFORT * torso.reach - 1e-6
    _, _, upright_error, upright_depth = posture.reach(wrist, hand_turn, TorsoPose(0.0, 0.0, 0.0))
    if reaches and upright_error < SWIVEL_TRY and upright_depth == 0.0:
        # (else a lean may buy the wrist its turn, or the arm its clearance from legs and Robin)
        assert chosen == TorsoPose(0.0, 0.0, 0.0)
    grid = np.stack(
        np.meshgrid(
            np.linspace(*torso.step_range, 39),
            np.linspace(*torso.turn_range, 29),
            np.linspace(0.0, torso.lean_limit, 46),
            indexing="ij",
        ),
        axis=-1,
    ).reshape(-1, 3)
    least = float(torso.cost(wrist, *grid.T).min())
    cost = torso.cost_of(wrist, chosen)
    cheapest, _ = torso.best(wrist)
    _, _, cheapest_error, cheapest_depth = posture.reach(wrist, hand_turn, cheapest)
    if cheapest_error <= SWIVEL_TRY and cheapest_depth == 0.0:  # else other torsos are tried
        assert cost <= least * 1.02 + 1e-3, (chosen, cost, least)  # (LEAN_TRIES, CLEAR_LEANS)
    if least < 1e-2:  # reachable at little cost: the arm's wrist is on the hand's
        posture.update()
        mujoco.mj_kinematics(model, data)
        assert _miss(data) < 2e-3, (chosen, _miss(data))


def lean_of_values(values: dict[str, float]) -> float:
    return sum(values[n] for n in names.PERSON_LEAN_JOINTS)


@settings(max_examples=30, deadline=None, derandomize=True)
@given(
    step=st.floats(-0.38, 0.0),
    turn=st.floats(-0.7, 0.7),
    lean=st.floats(0.0, 0.9),
)
def test_the_idle_arm_keeps_clear_of_the_table_and_bin_whatever_the_torso(
    scene, step, turn, lean
) -> None:
    model, _, posture, _ = scene
    data = mujoco.MjData(model)
    pose = TorsoPose(step, turn, lean)
    fig = person_joints.figure()
    waist, chest = posture.torso.lean_joints(lean)
    values = dict(zip(names.TORSO_JOINTS, (step, turn, waist, chest), strict=True))
    values.update(posture.idle_arm.solve(*posture.torso.chest_frame(pose), lean))
    for name, value in values.items():
        data.userdata[fig.joint(name).adr] = value
    person_joints.pose(model, data)
    mujoco.mj_kinematics(model, data)
    assert (
        posture.idle_arm.clearance >= TABLE_CLEARANCE - 1e-9 or lean > 0.8
    )  # swung as far as it goes
    assert _arm_clearance(model, data) >= ARM_CLEAR, (pose, posture.idle_arm.clearance)


@pytest.fixture(scope="module", params=EPISODES, ids=lambda e: f"{e[0]}-{e[1]}")
def episode(request, tmp_path_factory: pytest.TempPathFactory) -> tuple[str, RecordedStates]:
    """One real episode per scenario and seed (small frames at 5 fps), run once for the
    module's tests."""
    scenario, seed = request.param
    folder = tmp_path_factory.mktemp(f"{scenario}_{seed}")
    states, summary = record_episode(folder, scenario, seed, (80, 60), 5, render_workers=0)
    assert summary["status"] == "finished"
    return scenario, states


def _least_lean(torso: Torso, wrist: np.ndarray) -> float:
    """The least lean with which some step and turn (a fine grid) bring the shoulder within
    the comfortable reach of ``wrist`` (bisection to 1 mrad; the limit where none does)."""
    step, turn = np.meshgrid(
        np.linspace(*torso.step_range, 39), np.linspace(*torso.turn_range, 29), indexing="ij"
    )
    step, turn = step.ravel(), turn.ravel()

    def reaches(lean: float) -> bool:
        shoulders = torso.shoulders(step, turn, np.full_like(step, lean))
        return bool(np.linalg.norm(wrist - shoulders, axis=1).min() <= COMFORT * torso.reach)

    low, high = 0.0, torso.lean_limit
    if reaches(low) or not reaches(high):
        return low if reaches(low) else high
    while high - low > 1e-3:
        mid = (low + high) / 2.0
        low, high = (low, mid) if reaches(mid) else (mid, high)
    return high


@pytest.mark.slow
def test_over_a_whole_episode_the_lean_stays_below_its_limit(episode) -> None:
    scenario, recorded = episode
    size = person_joints.figure().size
    leans = np.array([lean_of(s.qpos[-size:]) for s in recorded.states])
    assert len(leans) > 100
    assert np.mean(leans < lean_limit() - 1e-3) >= BELOW_LIMIT
    assert float(np.median(leans)) < MEDIAN_LEAN[scenario]


@pytest.mark.slow
def test_over_a_whole_episode_the_lean_is_what_reaching_needs(episode) -> None:
    _, recorded = episode
    model = build_model(recorded.layout)
    data = mujoco.MjData(model)
    posture = Posture(model, data)
    torso = posture.torso
    wrist = model.site(names.person_wrist_point("r")).id
    excess = []
    for state in recorded.states[::2]:
        apply_state(model, data, state)
        assert _miss(data) < 2e-3, state.time  # and the arm meets the hand
        hand_wrist, hand = posture.hand_frame()
        if posture.reach(hand_wrist, hand, torso.best(hand_wrist)[0])[3] > 0.0:
            continue  # the cheapest torso's arm into a leg or Robin: leant to clear it
        excess.append(lean_of(data.userdata) - _least_lean(torso, data.site_xpos[wrist]))
    assert len(excess) >= len(recorded.states[::2]) // 2
    assert np.median(excess) <= EXCESS_MEDIAN
    assert np.percentile(excess, 90) <= EXCESS_P90


@pytest.mark.slow
def test_over_a_whole_episode_the_idle_arm_keeps_clear(episode) -> None:
    _, recorded = episode
    model = build_model(recorded.layout)
    data = mujoco.MjData(model)
    leans = []
    for state in recorded.states[::2]:
        apply_state(model, data, state)
        leans.append(lean_of(data.userdata))
        clear = _arm_clearance(model, data)
        assert clear >= ARM_CLEAR, (state.time, clear)
    assert max(leans) > 0.3  # the person leant: the arm was kept clear while leaning
