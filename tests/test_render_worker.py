"""Frame states: captured from one simulation, applied to another copy of the same scene."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from robin_sim.figure.articulated import ArticulatedHand
from robin_sim.model import names
from robin_sim.model.scene import SceneLayout, build_model
from robin_sim.render.worker import FrameState, RenderPoolError, apply_state, check_state


def test_a_captured_state_puts_another_copy_of_the_scene_in_the_same_place() -> None:
    model, other = build_model(), build_model()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    data.ctrl[:7] += 0.3  # move the left arm
    data.mocap_pos[0] += [0.0, 0.1, 0.05]  # and the person's hand
    for _ in range(200):
        mujoco.mj_step(model, data)
    ArticulatedHand(model, data).show("grasp")  # the person's joints: userdata, body frames
    mujoco.mj_forward(model, data)
    tip = model.site(names.person_fingertip_site("r", "index")).id
    tip_at = data.site_xpos[tip].copy()
    state = FrameState.capture(model, data)
    data.qpos[:] = 0.0  # later changes do not reach the captured state
    copy = mujoco.MjData(other)
    apply_state(other, copy, state)
    assert copy.time == pytest.approx(0.4)
    np.testing.assert_array_equal(np.concatenate([copy.qpos, copy.userdata]), state.qpos)
    np.testing.assert_allclose(copy.site_xpos[tip], tip_at, atol=1e-12)  # the fist, there
    mujoco.mj_forward(model, data := mujoco.MjData(model))
    hand = other.body("l_palm").id
    assert np.linalg.norm(copy.xpos[hand] - data.xpos[hand]) > 0.01  # really moved, not home


def test_a_state_from_another_scene_is_refused_naming_the_field() -> None:
    two_legs = build_model(SceneLayout(legs=((0.45, 0.2, 0.0), (0.45, 0.4, 0.0))))
    state = FrameState.capture(two_legs, mujoco.MjData(two_legs))
    with pytest.raises(RenderPoolError, match="qpos has shape"):
        check_state(build_model(), state)
