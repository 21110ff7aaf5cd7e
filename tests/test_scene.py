"""Scene layouts: validation errors and legs placed where the layout says."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from pil.errors import RobinPilError
from robin_sim import names
from robin_sim import robot_spec as spec
from robin_sim.scene import (
    DEFAULT_HANDOVER,
    LayoutError,
    SceneLayout,
    build_model,
    leg_count,
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


def test_from_mapping_parses_lists_dicts_and_degrees() -> None:
    layout = SceneLayout.from_mapping(
        {
            "legs": [[0.5, 0.1], {"x": 0.5, "y": 0.4, "yaw_deg": 90}],
            "spots": [{"x": 0.45, "y": -0.06}],
            "handover": [0.6, 0.0, 0.9],
        }
    )
    assert layout.legs == ((0.5, 0.1, 0.0), (0.5, 0.4, math.pi / 2))
    assert layout.spots == ((0.45, -0.06),)
    assert layout.handover == (0.6, 0.0, 0.9)
    assert SceneLayout.from_mapping(None) == SceneLayout()
    assert SceneLayout.from_mapping({}).handover == DEFAULT_HANDOVER


@pytest.mark.parametrize(
    ("mapping", "pattern"),
    [
        ({"legz": []}, r"unknown layout key\(s\) \['legz'\]; valid keys: \['legs', 'spots'"),
        ({"legs": "many"}, "layout 'legs' must be a list"),
        ({"legs": [[0.5]]}, r"leg 0 must be \[x, y\] or \[x, y, yaw_deg\]"),
        ({"legs": [[0.5, "a"]]}, "leg 0 y must be a number, got 'a'"),
        ({"legs": [{"x": 0.5, "yaw": 3}]}, "leg 0 needs keys x, y and optionally yaw_deg"),
        ({"spots": [[0.5, 0.1, 0.2]]}, r"spot 0 must be \[x, y\]"),
        ({"handover": [0.6, 0.0]}, r"handover must be \[x, y, z\]"),
        ([1, 2], "layout must be a mapping"),
    ],
)
def test_from_mapping_rejects_malformed_input(mapping: object, pattern: str) -> None:
    with pytest.raises(LayoutError, match=pattern):
        SceneLayout.from_mapping(mapping)  # type: ignore[arg-type]


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
