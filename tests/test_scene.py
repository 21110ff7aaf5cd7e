"""Scene layouts: validation errors and legs placed where the layout says."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from pil.errors import RobinPilError
from pil.task.layout import parse_layout
from robin_sim.model import names
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import (
    DEFAULT_BIN,
    DEFAULT_HANDOVER,
    LayoutError,
    SceneLayout,
    build_model,
    build_spec,
    leg_count,
    leg_ends,
    leg_gap,
)


def test_default_layout_matches_scene_file() -> None:
    model = mujoco.MjModel.from_xml_path(str(names.SCENE_XML))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    layout = SceneLayout()
    assert leg_count(model) == len(layout.legs) == 4
    for i, (x, y, yaw) in enumerate(layout.legs):
        body = data.body(names.leg_body(i))
        np.testing.assert_allclose(body.xpos, [x, y, spec.GRASP_HEIGHT], atol=1e-9)
        axis = body.xmat.reshape(3, 3)[:, 0]
        np.testing.assert_allclose(axis, [math.cos(yaw), math.sin(yaw), 0.0], atol=1e-9)


def test_layout_errors_are_robin_pil_errors() -> None:
    assert issubclass(LayoutError, RobinPilError)


def test_leg_off_the_table_names_leg_value_and_range() -> None:
    with pytest.raises(LayoutError) as info:
        SceneLayout(legs=((0.52, 0.16, 0.0), (0.52, 0.70, 0.0)))
    text = str(info.value)
    assert "leg 1" in text and "y=0.700" in text and "y -0.60..0.60" in text


def test_leg_out_of_reach_names_reach_region() -> None:
    with pytest.raises(
        LayoutError, match=r"leg 0 at \(x=0\.900, y=0\.300\) is out of reach.*x 0\.40"
    ):
        SceneLayout(legs=((0.90, 0.30, 0.0),))


def test_unreachable_spot_is_named() -> None:
    with pytest.raises(LayoutError, match=r"spot 1 at \(x=0\.700, y=-0\.300\).*out of reach"):
        SceneLayout(spots=((0.42, 0.02), (0.70, -0.30)))


def test_spot_on_a_leg_and_overlapping_legs_are_refused() -> None:
    with pytest.raises(LayoutError, match=r"spot 0 .* lies on leg 0"):
        SceneLayout(spots=((0.52, 0.16),))
    with pytest.raises(LayoutError, match="legs 0 and 1 overlap"):
        SceneLayout(legs=((0.52, 0.16, 0.0), (0.52, 0.19, 0.0)))
    with pytest.raises(LayoutError, match="legs 0 and 1 overlap"):
        SceneLayout(legs=((0.52, 0.20, 0.0), (0.52, 0.20, math.pi / 2)), spots=())


def test_bad_handover_and_leg_count() -> None:
    with pytest.raises(LayoutError, match=r"handover palm .* z 0\.80\.\.1\.00"):
        SceneLayout(handover=(0.62, 0.05, 1.4))
    with pytest.raises(LayoutError, match="1 to 12 legs, got 0"):
        SceneLayout(legs=())


def test_a_parsed_section_parses_lists_dicts_and_degrees() -> None:
    layout = SceneLayout.of(
        parse_layout(
            {
                "legs": [[0.5, 0.1], {"x": 0.5, "y": 0.4, "yaw_deg": 90}],
                "spots": [{"x": 0.45, "y": -0.06}],
                "handover": [0.6, 0.0, 0.9],
            }
        )
    )
    assert layout.legs == ((0.5, 0.1, 0.0), (0.5, 0.4, math.pi / 2))
    assert layout.spots == ((0.45, -0.06),)
    assert layout.handover == (0.6, 0.0, 0.9)
    assert SceneLayout.of(parse_layout(None)) == SceneLayout()
    assert SceneLayout.of(parse_layout({})).handover == DEFAULT_HANDOVER


@pytest.mark.parametrize(
    ("mapping", "pattern"),
    [
        ({"legz": []}, r"unknown layout key\(s\) \['legz'\]; valid keys: \['legs', 'spots'"),
        ({"legs": "many"}, "layout 'legs' must be a list"),
        ({"legs": [[0.5]]}, r"leg 0 must be \[x, y\] or \[x, y, yaw_deg\]"),
        ({"legs": [[0.5, "a"]]}, "leg 0 y must be a finite number, got 'a'"),
        ({"legs": [{"x": 0.5, "yaw": 3}]}, "leg 0 needs keys x, y and optionally yaw_deg"),
        ({"spots": [[0.5, 0.1, 0.2]]}, r"spot 0 must be \[x, y\]"),
        ({"handover": [0.6, 0.0]}, r"handover must be \[x, y, z\]"),
        ([1, 2], "layout must be a mapping"),
    ],
)
def test_a_malformed_section_is_refused(mapping: object, pattern: str) -> None:
    with pytest.raises(LayoutError, match=pattern):
        parse_layout(mapping)


@pytest.mark.parametrize(
    "legs",
    [
        ((0.45, 0.30, 0.3),),
        ((0.40, 0.10, math.pi / 2), (0.57, 0.22, -0.4), (0.65, 0.42, 0.0)),
        tuple((x, y, math.pi / 2) for x in (0.42, 0.50, 0.60, 0.68) for y in (0.14, 0.46)),
    ],
)
def test_build_model_puts_legs_where_asked(legs: tuple[tuple[float, float, float], ...]) -> None:
    """After 1 s of settling each leg's centre is within 1 mm of the layout, axis within 1 deg."""
    model = build_model(SceneLayout(legs=legs, spots=((0.45, -0.07),)))
    assert leg_count(model) == len(legs)
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    for _ in range(500):
        mujoco.mj_step(model, data)
    for i, (x, y, yaw) in enumerate(legs):
        body = data.body(names.leg_body(i))
        assert np.linalg.norm(body.xpos - [x, y, spec.GRASP_HEIGHT]) < 1e-3
        axis = body.xmat.reshape(3, 3)[:, 0]
        assert abs(float(np.dot(axis, [math.cos(yaw), math.sin(yaw), 0.0]))) > math.cos(
            math.radians(1)
        )
        assert model.geom(names.leg_geom(i)).rgba[3] == 1.0


def test_build_model_caches_nothing() -> None:
    one = build_model(SceneLayout(legs=((0.5, 0.3, 0.0),)))
    four = build_model()
    assert (leg_count(one), leg_count(four)) == (1, 4)
    assert one is not build_model(SceneLayout(legs=((0.5, 0.3, 0.0),)))


# --- the default spots: four places for "location", one per leg of a table ----------------------
OPEN_HAND_HALF = (spec.FINGER_ALONG, spec.FINGER_SPREAD)  # m: open fingers along / across the axis
CLOSED_HAND_HALF_WIDTH = 0.045  # m: closed fingers and the palm cylinder, across the leg axis
PALM_FOOTPRINT_HALF = (0.09 + 0.01, 0.05 + 0.01)  # m: the person's palm box + 1 cm jitter


def _axis_points(pose: tuple[float, float, float]) -> np.ndarray:
    a, b = leg_ends(pose)
    return a + np.linspace(0.0, 1.0, 61)[:, None] * (b - a)


def _placed(yaw: float) -> list[tuple[float, float, float]]:
    return [(x, y, yaw) for x, y in SceneLayout().spots]


def test_default_layout_has_four_spots_in_reach() -> None:
    spots = SceneLayout().spots
    assert len(spots) == 4
    assert all(spec.in_left_reach(x, y) for x, y in spots)
    assert all(spec.in_left_reach(x, y) for x, y, _ in SceneLayout().legs)


@pytest.mark.parametrize("yaw_deg", [-3.0, 0.0, 3.0])
def test_legs_placed_on_all_default_spots_touch_no_other_leg(yaw_deg: float) -> None:
    """A placed leg keeps the grasp's yaw (0 for the default legs; PhysicalWorld placed them
    within 0.8-1.7 deg): legs on all four spots and the four resting legs, placed legs turned by
    up to 3 deg, are pairwise >= 1 cm apart."""
    legs = [*SceneLayout().legs, *_placed(math.radians(yaw_deg))]
    gaps = [leg_gap(a, b) for i, a in enumerate(legs) for b in legs[i + 1 :]]
    assert min(gaps) >= 0.01


def test_open_hand_at_any_default_leg_or_spot_clears_every_other_leg() -> None:
    """The open fingers around one leg (resting or placed) stay >= 1 cm from every other leg."""
    legs = [*SceneLayout().legs, *_placed(0.0)]
    along, across = OPEN_HAND_HALF
    for i, (x, y, _) in enumerate(legs):
        for j, other in enumerate(legs):
            if i == j:
                continue
            points = _axis_points(other)
            inside = (np.abs(points[:, 0] - x) < along + spec.LEG_RADIUS + 0.01) & (
                np.abs(points[:, 1] - y) < across + spec.LEG_RADIUS + 0.01
            )
            assert not inside.any(), (i, j)


def test_default_spots_lie_clear_of_the_held_out_palm() -> None:
    """A leg going down onto any spot (and the hand around it) never passes under the palm."""
    hx, hy, _ = SceneLayout().handover
    half_x, half_y = PALM_FOOTPRINT_HALF
    for pose in _placed(0.0):
        points = _axis_points(pose)
        margin = CLOSED_HAND_HALF_WIDTH + 0.01
        under = (np.abs(points[:, 0] - hx) < half_x + margin) & (
            np.abs(points[:, 1] - hy) < half_y + margin
        )
        assert not under.any(), pose


@pytest.mark.slow
def test_robot_places_the_four_default_legs_on_the_four_spots() -> None:
    """With the project's controller (PhysicalWorld): leg k is grasped and placed on spot 3 - k
    for k = 0..3 in one scene; each lands within the placement tolerance of its spot, lying on
    the table, and no other leg (resting or placed) moves more than 2 mm."""
    from person_steps import Acted, intent

    from pil.task.world import Target
    from pil.types import Action
    from robin_sim.robot.planning import PLACEMENT_TOLERANCE

    acted = Acted(seed=1)
    world = acted.world
    spots = world.layout.spots
    for leg in range(4):
        spot = 3 - leg
        before = world.legs.positions()
        steps = [
            (Action.OBJECT, intent("pointing", "object", Target("leg", leg))),
            (Action.CLOSE, intent("grasp", "close")),
            (Action.LOCATION, intent("pointing", "location", Target("spot", spot))),
            (Action.OPEN, intent("release", "open")),
        ]
        for action, wanted in steps:
            outcome = acted.act(action, wanted)
            assert outcome.succeeded, (leg, action, outcome.detail)
        after = world.legs.positions()
        assert np.linalg.norm(after[leg, :2] - spots[spot]) <= PLACEMENT_TOLERANCE
        assert after[leg, 2] == pytest.approx(spec.GRASP_HEIGHT, abs=2e-3)
        others = [k for k in range(4) if k != leg]
        assert np.linalg.norm(after[others] - before[others], axis=1).max() < 0.002
    assert all(w.number == 0 for w in world.data.warning)


# --- the bin -------------------------------------------------------------------------------------
def test_bin_sits_where_the_layout_says_with_the_documented_inside() -> None:
    """Floor and walls enclose spec.BIN_INNER_SIZE around the layout's bin centre, on the floor."""
    for where in (DEFAULT_BIN, (1.18, 0.10)):
        model = build_model(SceneLayout(bin=where))
        data = mujoco.MjData(model)
        mujoco.mj_forward(model, data)
        assert data.body(names.BIN_BODY).xpos == pytest.approx([*where, 0.0])
        inner_x, inner_y, depth = spec.BIN_INNER_SIZE
        low, high = np.full(3, np.inf), np.full(3, -np.inf)
        for name in names.BIN_GEOMS:
            geom = model.geom(name)
            centre, half = data.geom_xpos[geom.id], model.geom_size[geom.id]
            low, high = np.minimum(low, centre - half), np.maximum(high, centre + half)
            assert geom.contype[0] and geom.conaffinity[0]  # legs land on it
        wall = spec.BIN_WALL
        np.testing.assert_allclose(
            high - low, [inner_x + 2 * wall, inner_y + 2 * wall, depth + wall]
        )
        np.testing.assert_allclose(
            low, [where[0] - inner_x / 2 - wall, where[1] - inner_y / 2 - wall, 0]
        )
        floor = model.geom(names.BIN_GEOMS[0])
        assert data.geom_xpos[floor.id][2] + floor.size[2] == pytest.approx(spec.BIN_FLOOR_TOP_Z)


def _in_subtree(model: mujoco.MjModel, body: int, root: int) -> bool:
    while body not in (root, 0):
        body = int(model.body_parentid[body])
    return body == root


def _box(model: mujoco.MjModel, data: mujoco.MjData, geom: int) -> tuple[np.ndarray, np.ndarray]:
    """The geom's world-aligned bounding box (low, high corners)."""
    rotation = data.geom_xmat[geom].reshape(3, 3)
    centre = data.geom_xpos[geom] + rotation @ model.geom_aabb[geom][:3]
    half = np.abs(rotation) @ model.geom_aabb[geom][3:]
    return centre - half, centre + half


CLEARANCE = 0.005  # m: the bin's walls and the person's body (feet beside it) apart at least


def test_bin_clears_the_table_and_the_person() -> None:
    """The bin's top stays below the table top it may reach under, and no part of the standing
    person's body (its feet stand beside the bin) comes within CLEARANCE of the bin's boxes."""
    model = build_model()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    mujoco.mj_forward(model, data)
    _, _, depth = spec.BIN_INNER_SIZE
    assert depth + spec.BIN_WALL < spec.TABLE_TOP_Z - 0.4
    person = model.body("human").id  # the person's body tree (its hand is the mocap's)
    body = [g for g in range(model.ngeom) if _in_subtree(model, int(model.geom_bodyid[g]), person)]
    assert len(body) > 20
    for name in names.BIN_GEOMS:
        low, high = _box(model, data, model.geom(name).id)
        for g in body:
            other_low, other_high = _box(model, data, g)
            gap = np.maximum(other_low - high, low - other_high).max()  # > 0: apart on an axis
            assert gap >= CLEARANCE, (name, model.body(model.geom_bodyid[g]).name, gap)


@pytest.mark.slow
def test_a_leg_dropped_over_the_bin_lands_inside() -> None:
    """A leg let go 0.6 m above the bin centre (its initial pose) comes to rest on its floor."""
    model_spec = build_spec()
    x, y = SceneLayout().bin
    model_spec.body(names.leg_body(0)).pos = [x, y, 0.6]
    model = model_spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(names.HOME_KEY).id)
    for _ in range(1000):
        mujoco.mj_step(model, data)
    leg = data.body(names.leg_body(0)).xpos
    assert leg[2] == pytest.approx(spec.BIN_FLOOR_TOP_Z + spec.LEG_RADIUS, abs=2e-3)
    assert np.all(np.abs(leg[:2] - [x, y]) < np.array(spec.BIN_INNER_SIZE[:2]) / 2)


def test_bad_bin_is_refused_and_a_section_reads_it() -> None:
    with pytest.raises(LayoutError, match=r"bin at \(0\.9, 0\.0\).*valid: x 1\.15\.\.1\.30"):
        SceneLayout(bin=(0.9, 0.0))
    assert SceneLayout.of(parse_layout({"bin": [1.2, 0.1]})).bin == (1.2, 0.1)
    with pytest.raises(LayoutError, match=r"bin must be \[x, y\]"):
        parse_layout({"bin": [1.2]})
