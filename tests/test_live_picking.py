"""Clicks on the scene frame resolve to the leg or spot seen under the pixel (mj_ray)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from pil.task.world import Target
from robin_sim.live.inputs import LiveInputError
from robin_sim.live.picking import Picker
from robin_sim.model import names
from robin_sim.model.scene import SceneLayout
from robin_sim.robot.targets import spot_surface


@pytest.fixture(scope="module")
def picker() -> Picker:
    return Picker(SceneLayout(), 640, 480)


def _leg(picker: Picker, leg: int) -> np.ndarray:
    return picker.data.body(names.leg_body(leg)).xpos.copy()


def test_a_click_on_each_leg_and_spot_picks_it(picker: Picker) -> None:
    for leg in range(len(picker.layout.legs)):
        assert picker.pick(*picker.project(_leg(picker, leg))) == Target("leg", leg)
    for spot in range(len(picker.layout.spots)):
        x, y = picker.project(spot_surface(picker.layout, spot))
        assert picker.pick(x, y) == Target("spot", spot)
        assert (x, y) == pytest.approx(picker.spot_pixels()[spot])


def test_the_camera_model_matches_the_rendered_image(picker: Picker) -> None:
    """Image y runs down: the rendered frame shows each leg's body at its projected pixel."""
    renderer = mujoco.Renderer(picker.model, 480, 640)
    try:
        renderer.enable_segmentation_rendering()
        renderer.update_scene(picker.data, picker.camera)
        segmentation = renderer.render()
    finally:
        renderer.close()
    for leg in range(len(picker.layout.legs)):
        x, y = picker.project(_leg(picker, leg))
        geom = segmentation[int(y), int(x), 0]
        assert picker.model.geom_bodyid[geom] == picker.model.body(names.leg_body(leg)).id
    # and the projection inverts the ray: the ray through a leg's pixel passes its centre
    origin, direction = picker.ray(*picker.project(_leg(picker, 2)))
    offset = _leg(picker, 2) - origin
    miss = np.linalg.norm(offset - np.dot(offset, direction) * direction)
    assert miss < 1e-9


@pytest.mark.parametrize(("x", "y"), [(5.0, 5.0), (600.0, 460.0), (0.0, 479.9)])
def test_a_click_on_the_floor_or_the_sky_is_refused(picker: Picker, x: float, y: float) -> None:
    with pytest.raises(
        LiveInputError,
        match=r"not on a leg or a spot\. Click one of the "
        r"numbered legs \(1-4\) or spots \(1-4, the rings on the table\)",
    ) as error:
        picker.pick(x, y)
    assert "(of " not in str(error.value) and "geom" not in str(error.value)  # plain words


def test_a_click_on_the_table_away_from_the_spots_is_refused(picker: Picker) -> None:
    far = spot_surface(picker.layout, 0) - np.array([0.0, 0.13, 0.0])  # 13 cm beside spot 0
    with pytest.raises(LiveInputError, match="That click was on the table away from the spots"):
        picker.pick(*picker.project(far))
