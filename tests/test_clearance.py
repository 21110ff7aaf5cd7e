"""The clearance measure (robin_sim.person.clearance) finds penetrations whose depth is known.

A small model with the scene's names (a person sphere, a mocap hand box, a table leg capsule,
a table box, a bin box and a robot sphere) is posed so that a person geom lies a chosen depth
into one of them: the measure must give that depth, that pair and that category, and nothing
when they are apart. On the real scene the broad phase must drop no pair that a brute-force
measure of every pair finds.
"""

from __future__ import annotations

import mujoco
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robin_sim.model.geom_groups import CATEGORIES, category_geoms, geom_label
from robin_sim.model.scene import build_model
from robin_sim.person.clearance import Clearance

SMALL = """
<mujoco>
  <worldbody>
    <body name="human" pos="0 0 1">
      <geom name="head" type="sphere" size="0.1" contype="0" conaffinity="0"/>
    </body>
    <body name="human_hand" mocap="true" pos="0 2 1">
      <geom name="palm" type="box" size="0.04 0.03 0.01" contype="0" conaffinity="0"/>
    </body>
    <body name="leg0" pos="5 0 1"><freejoint/>
      <geom name="leg0_geom" type="capsule" size="0.02" fromto="-0.13 0 0 0.13 0 0"/>
    </body>
    <body name="table" pos="0 -3 0"><geom name="top" type="box" size="0.4 0.6 0.02"/></body>
    <body name="bin" pos="0 -6 0"><geom name="wall" type="box" size="0.2 0.2 0.1"/></body>
    <body name="torso" pos="0 -9 0"><geom name="robot_ball" type="sphere" size="0.05"/></body>
  </worldbody>
</mujoco>
"""


def _small() -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = mujoco.MjModel.from_xml_string(SMALL)
    return model, mujoco.MjData(model)


@settings(max_examples=60, deadline=None)
@given(
    depth=st.floats(0.0005, 0.05),
    direction=st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: np.linalg.norm(v) > 0.1),
)
def test_a_sphere_into_the_robot_sphere_by_a_known_depth(
    depth: float, direction: tuple[float, float, float]
) -> None:
    model, data = _small()
    unit = np.array(direction) / np.linalg.norm(direction)
    ball = model.body("torso").pos + model.geom("robot_ball").pos
    model.body("human").pos = ball + unit * (0.1 + 0.05 - depth)
    mujoco.mj_forward(model, data)
    reaches = Clearance(model).measure(data)
    assert [(r.person, r.other, r.category) for r in reaches] == [("head", "robot_ball", "robot")]
    assert abs(reaches[0].depth - depth) < 1e-9


@settings(max_examples=60, deadline=None)
@given(depth=st.floats(0.0005, 0.009), x=st.floats(-0.35, 0.35), y=st.floats(-0.55, 0.55))
def test_a_box_sunk_into_the_table_top_by_a_known_depth(depth: float, x: float, y: float) -> None:
    model, data = _small()
    top = model.body("table").pos
    data.mocap_pos[0] = top + np.array([x, y, 0.02 + 0.01 - depth])
    mujoco.mj_forward(model, data)
    reaches = Clearance(model).measure(data)
    assert [(r.person, r.other, r.category) for r in reaches] == [("palm", "top", "table")]
    assert abs(reaches[0].depth - depth) < 1e-6


@settings(max_examples=40, deadline=None)
@given(gap=st.floats(1e-5, 0.2))
def test_geoms_apart_measure_nothing(gap: float) -> None:
    model, data = _small()
    data.qpos[:3] = [0.0, 2.0 + 0.03 + 0.02 + gap, 1.0]  # the leg beside the palm
    mujoco.mj_forward(model, data)
    clearance = Clearance(model)
    assert clearance.measure(data) == []
    assert clearance.deepest(data) == dict.fromkeys(CATEGORIES, 0.0)
    data.qpos[1] = 2.0 + 0.03 + 0.02 - gap / 10  # now into it
    mujoco.mj_forward(model, data)
    assert [(r.other, r.category) for r in clearance.measure(data)] == [("leg0_geom", "legs")]


def test_the_categories_of_the_scene() -> None:
    model = build_model()
    groups = category_geoms(model)
    assert len(groups["legs"]) == 4 and len(groups["bin"]) == 5 and len(groups["table"]) == 5
    assert len(groups["robot"]) > 20
    person = set(Clearance(model).person)
    assert model.geom("human_palm").id not in person  # the collision palm is physics
    assert model.geom("human_r_palm_vis").id in person
    assert not person & set(np.concatenate(list(groups.values())))


@settings(max_examples=25, deadline=None)
@given(
    hand=st.tuples(st.floats(0.5, 1.6), st.floats(-0.5, 0.6), st.floats(0.6, 1.3)),
    leg=st.tuples(st.floats(0.9, 1.6), st.floats(-0.3, 0.6), st.floats(0.7, 1.3)),
)
def test_the_broad_phase_misses_no_pair_in_the_scene(
    hand: tuple[float, float, float], leg: tuple[float, float, float]
) -> None:
    model = build_model()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    data.mocap_pos[model.body("human_hand").mocapid[0]] = hand
    data.qpos[model.joint("leg0_free").qposadr[0] :][:3] = leg
    mujoco.mj_forward(model, data)
    clearance = Clearance(model)
    found = {(r.person, r.other): r.depth for r in clearance.measure(data)}
    brute = {}
    fromto = np.zeros(6)
    for a in clearance.person:
        for b in clearance.others:
            distance = mujoco.mj_geomDistance(model, data, int(a), int(b), 10.0, fromto)
            if distance < 0:
                brute[(geom_label(model, int(a)), geom_label(model, int(b)))] = -distance
    assert found.keys() == brute.keys()
    assert all(abs(found[k] - brute[k]) < 1e-9 for k in brute)
