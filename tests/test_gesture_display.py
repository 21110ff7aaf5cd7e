"""Tests of robin_sim.person.gestures: pose switching by alpha, with physics untouched."""

from __future__ import annotations

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()  # before mujoco is imported (see robin_sim.render.gl_backend)

import mujoco  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pil.errors import InvalidChoiceError, RobinPilError  # noqa: E402
from pil.types import Feedback, Gesture  # noqa: E402
from robin_sim.model.names import HOME_KEY  # noqa: E402
from robin_sim.model.person_joints import figure  # noqa: E402
from robin_sim.model.scene import build_model  # noqa: E402
from robin_sim.person.gestures import POSES, GestureDisplay, pose_for  # noqa: E402
from robin_sim.render.renderer import FrameRenderer  # noqa: E402

SHOWN = [p for p in POSES if p != "neutral"]
# Each pose: one or two visual geoms at the person's hand; a ball falls right through them.
POSE_GEOMS = "\n".join(
    f'<geom name="human_vis_{pose}_part{k}" type="box" size="0.03 0.01 0.04" '
    f'pos="{0.03 * i} {0.02 * k} 0" rgba="0.9 0.7 0.6 {alpha}" {{collide}}/>'
    for i, pose in enumerate(SHOWN)
    for k, alpha in ((0, 1), (1, 0))
)
SCENE = f"""
<mujoco>
  <worldbody>
    <light pos="0 0 3" dir="0 0 -1"/>
    <geom name="floor" type="plane" size="2 2 .1" rgba=".5 .5 .5 1"/>
    <body name="human_hand" mocap="true" pos="0 0 0.5">
      <geom name="human_palm" type="box" size="0.05 0.04 0.01" pos="0.3 0 0"/>
      {POSE_GEOMS}
    </body>
    <body name="ball" pos="0.05 0 0.8">
      <freejoint/>
      <geom type="sphere" size="0.03" rgba="1 0 0 1"/>
    </body>
    <camera name="front" pos="0.1 -0.6 0.6" xyaxes="1 0 0 0 0.2 1"/>
  </worldbody>
</mujoco>
"""


def make_model(collide: str = 'contype="0" conaffinity="0"') -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(SCENE.replace("{collide}", collide))


def test_pose_names_come_from_gestures_and_feedback() -> None:
    assert [pose_for(g) for g in Gesture] == ["pointing", "give_me", "grasp", "release"]
    assert pose_for(Feedback.OK) == "thumb_up"
    assert pose_for("not OK") == "thumb_down"
    assert pose_for("give me") == "give_me"
    assert pose_for(None) == pose_for(Feedback.NONE) == "neutral"
    with pytest.raises(InvalidChoiceError, match=r"'wave'.*'thumb_up'"):
        pose_for("wave")


def test_show_sets_alpha_of_one_pose() -> None:
    model = make_model()
    display = GestureDisplay(model)
    every = [g for pose in POSES for g in display.geoms(pose)]
    assert len(every) == 2 * len(SHOWN)
    assert np.all(model.geom_rgba[every, 3] == 0)  # starts neutral: nothing shown
    for pose in SHOWN:
        assert display.show(pose) == pose
        shown = list(display.geoms(pose))
        assert np.all(model.geom_rgba[shown, 3] == 1.0)  # hidden parts get alpha 1
        others = [g for g in every if g not in shown]
        assert np.all(model.geom_rgba[others, 3] == 0)
    display.show(None)
    assert np.all(model.geom_rgba[every, 3] == 0)


def _trajectory(model: mujoco.MjModel, display: GestureDisplay | None) -> np.ndarray:
    data = mujoco.MjData(model)
    positions = []
    for step in range(400):
        if display is not None and step % 20 == 0:
            display.show(POSES[(step // 20) % len(POSES)])
        mujoco.mj_step(model, data)
        positions.append(data.qpos.copy())
    return np.array(positions)


def test_switching_poses_leaves_physics_unchanged() -> None:
    plain = _trajectory(make_model(), None)
    model = make_model()
    shown = _trajectory(model, GestureDisplay(model))
    np.testing.assert_array_equal(plain, shown)
    # The ball really passes through the pose geoms: were they solid, it would bounce off them.
    solid = _trajectory(make_model('contype="1" conaffinity="1"'), None)
    assert np.abs(solid[:, 2] - plain[:, 2]).max() > 0.1


def test_colliding_or_missing_pose_geoms_are_refused() -> None:
    with pytest.raises(RobinPilError, match="visual-only"):
        GestureDisplay(make_model('contype="1" conaffinity="1"'))
    bare = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><geom size='1'/></worldbody></mujoco>"
    )
    with pytest.raises(RobinPilError, match=r"no human_vis_<pose>_\* geoms.*pointing"):
        GestureDisplay(bare)


@pytest.mark.slow
def test_each_pose_renders_differently() -> None:
    model = make_model()
    display = GestureDisplay(model)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    frames = {}
    with FrameRenderer(model, 160, 120, camera="front", shadows=False) as renderer:
        for pose in POSES:
            display.show(pose)
            frames[pose] = renderer.render(data).astype(int)
    for pose in SHOWN:
        changed = np.any(frames[pose] != frames["neutral"], axis=2)
        assert changed.sum() > 30, f"{pose} not visible"
    assert np.any(frames["pointing"] != frames["thumb_up"])


@pytest.mark.slow
def test_project_scene_shows_every_pose_without_changing_physics() -> None:
    def run(display: bool) -> tuple[np.ndarray, GestureDisplay | None]:
        model = build_model()
        data = mujoco.MjData(model)
        mujoco.mj_resetDataKeyframe(model, data, model.key(HOME_KEY).id)
        shown = GestureDisplay(model, data) if display else None
        positions = []
        for step in range(300):  # 0.6 s holding the home pose, legs resting on the table
            if shown is not None and step % 40 == 0:
                shown.show(POSES[(step // 40) % len(POSES)])
            mujoco.mj_step(model, data)
            positions.append(np.concatenate([data.qpos, data.userdata]))  # person: userdata
        return np.array(positions), shown

    plain, _ = run(display=False)
    switched, display = run(display=True)
    assert display is not None and display.hand is not None
    # only the person's hand joints moved (written): the robot's, the palm's and the legs'
    # positions are the same to the bit
    hand = np.zeros(plain.shape[1], bool)
    nq = plain.shape[1] - figure().size  # the person's joints follow the scene's qpos
    hand[nq + display.hand.qadr] = True
    hand[nq + display.hand.turn_q : nq + display.hand.turn_q + 4] = True
    np.testing.assert_array_equal(plain[:, ~hand], switched[:, ~hand])
    assert np.any(plain[:, hand] != switched[:, hand])
    for pose in POSES:
        assert len(display.geoms(pose)) == len(display.hand.hand_geoms) == 17  # palm 2, 15 bones
