"""The person's hand fits around a leg on its palm (robin_sim.figure.hand_fit).

A table leg is laid on the collision palm (where a handover leaves it: along the mocap frame's
x, resting on the palm's top) and the hand shows each of the poses in turn, with seeded
performances: no geom of the hand may reach into the leg (measured by
:mod:`robin_sim.person.clearance`), and the hand is turned palm up about its normal. With the
leg back on the table the same pose is written as the library makes it.
"""

from __future__ import annotations

import mujoco
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robin_sim.figure.hand_fit import HOLD_TURN
from robin_sim.figure.hand_poses import Performance
from robin_sim.model import names
from robin_sim.model.person_joints import figure, pose
from robin_sim.model.scene import build_model
from robin_sim.person.clearance import Clearance
from robin_sim.person.gestures import GestureDisplay

MODEL = build_model()
POSES = names.HUMAN_VIS_POSES
LEG_RADIUS = float(MODEL.geom(names.leg_geom(0)).size[0])


def _scene(on_palm: bool, dx: float = 0.0, dy: float = 0.0) -> mujoco.MjData:
    data = mujoco.MjData(MODEL)
    mujoco.mj_resetDataKeyframe(MODEL, data, 0)
    if on_palm:
        palm = MODEL.geom(names.HUMAN_PALM_GEOM)
        mocap = MODEL.body(names.HUMAN_MOCAP_BODY).mocapid[0]
        top = palm.pos + np.array([dx, dy, palm.size[2] + LEG_RADIUS + 1e-4])
        adr = MODEL.joint(names.leg_joint(0)).qposadr[0]
        data.qpos[adr : adr + 3] = data.mocap_pos[mocap] + top
        data.qpos[adr + 3 : adr + 7] = (1.0, 0.0, 0.0, 0.0)
    mujoco.mj_forward(MODEL, data)
    return data


@settings(max_examples=30, deadline=None)
@given(
    pose=st.sampled_from(POSES),
    seed=st.integers(0, 2**16),
    dx=st.floats(-0.04, 0.02),
    dy=st.floats(-0.02, 0.02),
)
def test_no_pose_reaches_into_a_leg_on_the_palm(pose: str, seed: int, dx: float, dy: float) -> None:
    data = _scene(True, dx, dy)
    display = GestureDisplay(MODEL, data)
    assert display.hand is not None
    display.show(pose, Performance.draw(np.random.default_rng(seed)))
    mujoco.mj_kinematics(MODEL, data)
    into_leg = [r for r in Clearance(MODEL).measure(data) if r.category == "legs"]
    assert into_leg == [], (pose, [(r.person, round(r.depth * 1000, 2)) for r in into_leg])
    np.testing.assert_allclose(np.abs(display.hand.turn()), np.abs(HOLD_TURN), atol=1e-9)


@settings(max_examples=10, deadline=None)
@given(pose=st.sampled_from(POSES), seed=st.integers(0, 2**16))
def test_with_nothing_near_the_pose_is_the_librarys(pose: str, seed: int) -> None:
    data = _scene(False)
    display = GestureDisplay(MODEL, data)
    assert display.hand is not None
    performance = Performance.draw(np.random.default_rng(seed))
    display.show(pose, performance)
    angles, turn = display.hand.target(pose, performance)
    np.testing.assert_array_equal(display.hand.angles(), angles)
    np.testing.assert_array_equal(display.hand.turn(), turn)


def test_a_fit_leaves_a_hand_another_writer_turned() -> None:
    """Fitting the display's own wanted hand (before each render) must not leave that hand's
    turn in the model when it writes nothing: in a live session the mirror
    (:mod:`robin_sim.live.mirror`) writes the hand, and Robin's eyes, which pose a copy of the
    scene, saw it turned up to 107 degrees off the participant's hand. Here the hand is turned
    half round about the mocap frame's x by another writer; after the fit a copy of the scene
    must show that turn within 1e-6 (rotation matrix entries)."""
    data = _scene(False)
    display = GestureDisplay(MODEL, data)
    assert display.hand is not None
    display.show("neutral", Performance())
    turn = figure().joint(names.HUMAN_HAND_TURN).adr
    data.userdata[turn : turn + 4] = (0.0, 1.0, 0.0, 0.0)
    pose(MODEL, data)
    mujoco.mj_kinematics(MODEL, data)
    hand = MODEL.body(names.person_hand_body("r")).id
    written = data.xmat[hand].copy()
    display.hand.prepare_view()
    view = mujoco.MjData(MODEL)
    mujoco.mj_copyData(view, MODEL, data)
    mujoco.mj_kinematics(MODEL, view)
    np.testing.assert_allclose(view.xmat[hand], written, atol=1e-6)
