"""Tests of robin_sim.render.checks: render checks agree with what physics did.

Every leg position here comes from physics: legs start on the table or above the palm (the
initial layout) and the gripper, a pusher and the person's mocap hand move them by contact.
No object's qpos is written during a run.
"""

from __future__ import annotations

from robin_sim.render.gl_backend import ensure_gl_backend

ensure_gl_backend()  # before mujoco is imported (see robin_sim.render.gl_backend)

import copy  # noqa: E402
from collections.abc import Iterator  # noqa: E402

import mujoco  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from person_steps import Acted  # noqa: E402

from pil.errors import InvalidChoiceError, RobinPilError  # noqa: E402
from pil.task.world import Intent, Outcome, Target  # noqa: E402
from pil.types import Action, Feedback, Gesture  # noqa: E402
from robin_sim.model import names  # noqa: E402
from robin_sim.render.checks import (  # noqa: E402
    verify_at_spot,
    verify_in_hand,
    verify_on_palm,
)
from robin_sim.render.renderer import CloseUpRenderer  # noqa: E402

TABLE_TOP_Z = 0.75
SPOT = (0.6, -0.25)
# Where each test leg starts (x y z) and its colour: 0 on the table, 1 on the spot, 2 in the air
# over the person's palm.
LEGS = (
    (f"0.3 0 {TABLE_TOP_Z + 0.021}", "1 0 0 1"),
    (f"{SPOT[0]} {SPOT[1]} {TABLE_TOP_Z + 0.021}", "0 0 1 1"),
    ("0.7 0.35 0.99", "0 .7 0 1"),
)


def _leg_xml(index: int, pos: str, rgba: str) -> str:
    """One capsule leg (radius 0.02 m) with the model's leg names."""
    return f"""
    <body name="{names.leg_body(index)}" pos="{pos}">
      <freejoint name="{names.leg_joint(index)}"/>
      <geom name="{names.leg_geom(index)}" type="capsule" size="0.02 0.1" euler="0 90 0"
            mass="0.2" rgba="{rgba}"/>
    </body>"""


# A two-finger gripper (``l_palm``) on a vertical slide over a table, a pusher plate that can push
# leg 0 along its axis out from between the open fingers, the person's mocap hand, and three
# capsule legs (radius 0.02 m).
SCENE = f"""
<mujoco model="verify-test">
  <option timestep="0.002" integrator="implicitfast" cone="elliptic" impratio="10"/>
  <visual><global offwidth="640" offheight="480"/></visual>
  <default><geom friction="1 0.02 0.001" condim="6"/></default>
  <worldbody>
    <light pos="0 0 3" dir="0 0 -1"/>
    <geom name="floor" type="plane" size="3 3 .1" rgba=".6 .6 .6 1"/>
    <body name="table" pos="0.4 0 0">
      <geom name="table_top" type="box" size="0.4 0.5 0.02" pos="0 0 {TABLE_TOP_Z - 0.02}"/>
    </body>
    <body name="l_palm" pos="0.3 0 0.9">
      <joint name="lift" type="slide" axis="0 0 1" damping="50"/>
      <geom type="box" size="0.04 0.06 0.015" rgba=".3 .3 .8 1" mass="0.5"/>
      <site name="l_grasp_site" pos="0 0 -0.09" size="0.005"/>
      <body name="l_f1" pos="0 0.05 -0.06">
        <joint name="f1" type="slide" axis="0 -1 0" range="0 0.05" damping="5"/>
        <geom type="box" size="0.015 0.008 0.045" rgba=".2 .2 .2 1" mass="0.05"/>
      </body>
      <body name="l_f2" pos="0 -0.05 -0.06">
        <joint name="f2" type="slide" axis="0 1 0" range="0 0.05" damping="5"/>
        <geom type="box" size="0.015 0.008 0.045" rgba=".2 .2 .2 1" mass="0.05"/>
      </body>
    </body>
    <body name="pusher" pos="0.15 0 {TABLE_TOP_Z + 0.02}">
      <joint name="push" type="slide" axis="1 0 0" damping="20"/>
      <geom type="box" size="0.01 0.03 0.015" rgba=".8 .8 .2 1" mass="1"/>
    </body>
    <body name="human_hand" mocap="true" pos="0.7 0.35 0.95">
      <geom name="human_palm" type="box" size="0.06 0.05 0.01" rgba=".9 .7 .6 1"/>
    </body>
{"".join(_leg_xml(i, pos, rgba) for i, (pos, rgba) in enumerate(LEGS))}  </worldbody>
  <actuator>
    <position name="lift" joint="lift" kp="2000" kv="200" ctrlrange="-0.3 0.3"/>
    <position name="f1" joint="f1" kp="200" ctrlrange="0 0.05" forcerange="-20 20"/>
    <position name="f2" joint="f2" kp="200" ctrlrange="0 0.05" forcerange="-20 20"/>
    <position name="push" joint="push" kp="500" kv="50" ctrlrange="0 0.3"/>
  </actuator>
</mujoco>
"""
ACTUATORS = ("lift", "f1", "f2", "push")
LOWER, UP, CLOSED = -0.04, 0.25, 0.05  # gripper slide and finger targets


class Rig:
    """The test scene and a few scripted phases, each run by physics for ``seconds``."""

    def __init__(self) -> None:
        self.model = mujoco.MjModel.from_xml_string(SCENE)
        self.data = mujoco.MjData(self.model)
        self.ctrl = dict.fromkeys(ACTUATORS, 0.0)

    def run(self, seconds: float, **targets: float) -> Rig:
        """Ramp the targets linearly over the first half of the phase, then hold them."""
        start = np.array([self.ctrl[k] for k in ACTUATORS])
        self.ctrl.update(targets)
        end = np.array([self.ctrl[k] for k in ACTUATORS])
        steps = round(seconds / self.model.opt.timestep)
        for step in range(steps):
            self.data.ctrl[:] = start + (end - start) * min(1.0, 2 * (step + 1) / steps)
            mujoco.mj_step(self.model, self.data)
        return self

    def leg(self, index: int) -> np.ndarray:
        return self.data.body(names.leg_body(index)).xpos.copy()

    def snapshot(self) -> mujoco.MjData:
        return copy.copy(self.data)


@pytest.fixture(scope="module")
def handover() -> Iterator[dict[str, object]]:
    """Grasp leg 0, lift it, bring the person's palm under it, release it onto the palm."""
    rig = Rig().run(0.4)
    rest = rig.snapshot()
    rig.run(0.6, lift=LOWER).run(0.5, f1=CLOSED, f2=CLOSED).run(1.0, lift=UP)
    held = rig.snapshot()
    rig.data.mocap_pos[0] = [0.3, 0.0, 0.99]  # the person holds the palm 4 cm under the leg
    rig.run(0.3)
    hovering = rig.snapshot()
    rig.run(1.5, f1=0.0, f2=0.0)  # open: the leg drops onto the palm
    released = rig.snapshot()
    with CloseUpRenderer(rig.model) as renderer:
        yield {
            "rig": rig,
            "rest": rest,
            "held": held,
            "hovering": hovering,
            "released": released,
            "verifier": renderer,
        }


@pytest.mark.slow
def test_projection_agrees_with_the_segmentation() -> None:
    model = mujoco.MjModel.from_xml_string(SCENE)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with CloseUpRenderer(model) as verifier:
        centre = data.body("leg2").xpos.copy()
        obs = verifier.observe(data, centre + np.array([0.05, 0.0, 0.0]), 60.0, -30.0, 0.5)
    mask = obs.body == model.body("leg2").id
    pixel, depth = obs.project(centre)
    col, row = np.round(pixel[0]).astype(int)
    # the leg's centre projects onto the leg, and the surface seen there lies in front of the
    # centre by about the radius (0.02 m) along the view axis
    assert mask[row, col]
    assert depth[0] - 0.03 < obs.depth[row, col] < depth[0] - 0.01
    # every lifted surface point lies 0.02 m (the radius) from the leg's axis, within 3 mm
    points = obs.lift(mask)
    axis = data.geom("leg2_geom").xmat.reshape(3, 3)[:, 2]
    offsets = points - centre
    radial = np.linalg.norm(offsets - np.outer(offsets @ axis, axis), axis=1)
    along = np.abs(offsets @ axis)
    assert np.sum(along < 0.1) > 500
    assert np.abs(radial[along < 0.1] - 0.02).max() < 0.003
    assert 0.4 < depth[0] < 0.6


@pytest.mark.slow
def test_in_hand_after_a_physical_grasp(handover: dict[str, object]) -> None:
    rig, verifier = handover["rig"], handover["verifier"]
    held, rest = handover["held"], handover["rest"]
    # physics: the leg rose with the gripper (by about UP - LOWER = 0.23 m)
    assert held.body("leg0").xpos[2] - rest.body("leg0").xpos[2] > 0.15
    check = verify_in_hand(rig.model, held, 0, "l", verifier)
    assert check.ok, check.detail
    assert check.pixels >= 20
    assert not verify_in_hand(rig.model, held, 1, "l", verifier).ok  # leg 1 lies at its spot
    assert not verify_in_hand(rig.model, rest, 0, "l", verifier).ok  # gripper still above


@pytest.mark.slow
def test_grasp_that_misses_a_pushed_leg_is_not_in_hand() -> None:
    rig = Rig().run(0.4).run(0.6, lift=LOWER)
    rig.run(1.0, push=0.25)  # the plate pushes the leg along its axis, out of the fingers
    rig.run(0.6, push=0.0).run(0.5, f1=CLOSED, f2=CLOSED).run(1.0, lift=UP)
    leg = rig.leg(0)
    assert leg[2] < TABLE_TOP_Z + 0.03  # physics: the leg stayed on the table
    assert leg[0] - 0.3 > 0.15  # ... pushed along x, its near end beyond the fingers
    with CloseUpRenderer(rig.model) as verifier:
        check = verify_in_hand(rig.model, rig.data, 0, "l", verifier)
    assert not check.ok, check.detail


@pytest.mark.slow
def test_on_palm_only_once_the_released_leg_rests_there(handover: dict[str, object]) -> None:
    rig, verifier = handover["rig"], handover["verifier"]
    hovering, released = handover["hovering"], handover["released"]
    palm_top = released.geom("human_palm").xpos[2] + 0.01
    # physics: hovering, the leg's underside is ~4 cm above the palm; released, it rests on it
    assert hovering.body("leg0").xpos[2] - 0.02 - palm_top > 0.03
    assert abs(released.body("leg0").xpos[2] - 0.02 - palm_top) < 0.003
    assert not verify_on_palm(rig.model, hovering, 0, verifier).ok
    check = verify_on_palm(rig.model, released, 0, verifier)
    assert check.ok, check.detail
    assert not verify_in_hand(rig.model, released, 0, "l", verifier).ok
    assert not verify_on_palm(rig.model, released, 1, verifier).ok  # leg 1 is on the table


@pytest.mark.slow
def test_leg_dropped_on_the_palm_in_the_layout_is_on_palm() -> None:
    rig = Rig().run(1.0)  # leg 2 starts 2 cm above the palm and settles there
    with CloseUpRenderer(rig.model) as verifier:
        check = verify_on_palm(rig.model, rig.data, 2, verifier)
    assert check.ok, check.detail


@pytest.mark.slow
def test_at_spot(handover: dict[str, object]) -> None:
    rig, verifier = handover["rig"], handover["verifier"]
    rest, held = handover["rest"], handover["held"]
    check = verify_at_spot(rig.model, rest, 1, SPOT, renderer=verifier)
    assert check.ok, check.detail
    off = verify_at_spot(rig.model, rest, 1, (SPOT[0], SPOT[1] + 0.1), renderer=verifier)
    assert not off.ok  # 0.1 m away, beyond the 0.04 m tolerance
    assert verify_at_spot(rig.model, rest, 0, (0.3, 0.0), renderer=verifier).ok
    lifted = verify_at_spot(rig.model, held, 0, (0.3, 0.0), renderer=verifier)
    assert not lifted.ok, lifted.detail  # right above the spot, but in the air


@pytest.mark.slow
def test_checks_do_not_change_the_simulation() -> None:
    plain, checked = Rig(), Rig()
    for rig in (plain, checked):
        rig.run(0.3).run(0.3, lift=LOWER)
    with CloseUpRenderer(checked.model) as verifier:
        before = checked.snapshot()
        verify_in_hand(checked.model, checked.data, 0, "l", verifier)
        verify_on_palm(checked.model, checked.data, 2, verifier)
        verify_at_spot(checked.model, checked.data, 1, SPOT, renderer=verifier)
    for field in ("qpos", "qvel", "act", "ctrl", "time"):
        np.testing.assert_array_equal(getattr(before, field), getattr(checked.data, field))
    for rig in (plain, checked):
        rig.run(0.5, f1=CLOSED, f2=CLOSED)
    np.testing.assert_array_equal(plain.data.qpos, checked.data.qpos)


def test_bad_names_are_explained() -> None:
    model = mujoco.MjModel.from_xml_string(SCENE)
    data = mujoco.MjData(model)
    with pytest.raises(InvalidChoiceError, match=r"leg 7.*'0', '1', '2'"):
        verify_in_hand(model, data, 7, "l")
    with pytest.raises(RobinPilError, match="no grasp site named 'r_grasp_site'"):
        verify_in_hand(model, data, 0, "r")
    no_palm = mujoco.MjModel.from_xml_string(SCENE.replace('name="human_palm" ', ""))
    with pytest.raises(RobinPilError, match="no palm geom named 'human_palm'"):
        verify_on_palm(no_palm, mujoco.MjData(no_palm), 0)


# --- with Robin in the project scene (robin_sim.robot.world.PhysicalWorld) ---


def _execute(acted: Acted, action: Action, target: Target | None = None) -> Outcome:
    gesture = {
        Action.OBJECT: Gesture.POINTING,
        Action.CLOSE: Gesture.GRASP,
        Action.HUMAN: Gesture.GIVE_ME,
        Action.LOCATION: Gesture.POINTING,
        Action.OPEN: Gesture.RELEASE,
    }[action]
    return acted.act(action, Intent(gesture, action, target, handover=0, table=0))


@pytest.mark.slow
def test_robin_grasp_is_in_hand_and_handover_ends_on_the_palm() -> None:
    acted = Acted()
    world = acted.world
    model = world.model
    assert _execute(acted, Action.OBJECT, Target("leg", 0)).succeeded
    assert _execute(acted, Action.CLOSE).succeeded
    assert world.held_leg() == 0  # physics: contacts of an opposed grasp
    with CloseUpRenderer(model) as renderer:
        check = verify_in_hand(model, world.data, 0, "l", renderer)
        assert check.ok, check.detail
        assert not verify_in_hand(model, world.data, 1, "l", renderer).ok
        assert _execute(acted, Action.HUMAN).succeeded
        held_over_palm = copy.copy(world.data)
        # The person's release brings the palm back under the held leg; the open's end is kept
        # before the thumb, after which the person carries the leg away on the palm.
        meant = Intent(Gesture.RELEASE, Action.OPEN, None, handover=0, table=0)
        acted.body.perform(meant.gesture, meant.target)
        assert world.execute(Action.OPEN, None, acted.body.watch(meant, acted.reaction)).succeeded
        on_palm = copy.copy(world.data)
        acted.body.show_feedback(Feedback.OK)
        acted.body.after_feedback(Feedback.OK)
        assert world.delivered == [0]
        # physics: released, the leg's axis lies one radius (0.02 m) above the palm surface
        palm_site = on_palm.site("human_palm_site").xpos
        assert abs(on_palm.body("leg0").xpos[2] - palm_site[2] - 0.02) < 0.002
        check = verify_on_palm(model, on_palm, 0, renderer)
        assert check.ok, check.detail
        assert not verify_in_hand(model, on_palm, 0, "l", renderer).ok
        # still in the hand, 1.2 cm above the palm: in hand, not (yet) on the palm
        assert verify_in_hand(model, held_over_palm, 0, "l", renderer).ok
        assert not verify_on_palm(model, held_over_palm, 0, renderer).ok


@pytest.mark.slow
def test_robin_grasp_misses_a_leg_pushed_away_before_close() -> None:
    acted = Acted()
    world = acted.world
    assert _execute(acted, Action.OBJECT, Target("leg", 0)).succeeded
    leg = world.model.body("leg0").id
    start = world.legs.position(0)
    axis = world.data.xmat[leg].reshape(3, 3)[:, 0]
    # A push along the leg's axis (a 4 N force for 0.2 s, integrated by physics) slides it out
    # between the open fingers; nothing writes its position.
    world.data.xfrc_applied[leg, :3] = 4.0 * axis
    world.sim.run(0.2)
    world.data.xfrc_applied[leg, :3] = 0.0
    world.sim.run(1.0)
    assert abs((world.legs.position(0) - start) @ axis) > 0.17  # beyond the fingers
    outcome = _execute(acted, Action.CLOSE)
    assert not outcome.succeeded
    assert world.held_leg() is None
    with CloseUpRenderer(world.model) as renderer:
        check = verify_in_hand(world.model, world.data, 0, "l", renderer)
    assert not check.ok, check.detail


@pytest.mark.slow
def test_robin_placement_is_at_the_spot() -> None:
    acted = Acted()
    world = acted.world
    for action, target in (
        (Action.OBJECT, Target("leg", 0)),
        (Action.CLOSE, None),
        (Action.LOCATION, Target("spot", 0)),
        (Action.OPEN, None),
    ):
        assert _execute(acted, action, target).succeeded
    spot, other = world.layout.spots[0], world.layout.spots[1]
    assert np.linalg.norm(world.legs.position(0)[:2] - spot) < 0.02  # physics
    with CloseUpRenderer(world.model) as renderer:
        check = verify_at_spot(world.model, world.data, 0, spot, renderer=renderer)
        assert check.ok, check.detail
        assert not verify_at_spot(world.model, world.data, 0, other, renderer=renderer).ok
        assert not verify_in_hand(world.model, world.data, 0, "l", renderer).ok
