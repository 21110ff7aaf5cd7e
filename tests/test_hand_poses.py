"""Tests of robin_sim.figure.hand_poses: distinct pose shapes and varied performances."""

from __future__ import annotations

import mujoco
import numpy as np

from robin_sim.figure.hand_poses import SHAPES, Performance, part_segments, skin_colour
from robin_sim.model import names
from robin_sim.model.scene import build_model
from robin_sim.person.gestures import GestureDisplay

HAND = names.PERSON_HAND_FINGERS


def _tip(pose: str, part: str, performance: Performance | None = None) -> np.ndarray:
    return part_segments(pose, performance)[part][1]


def test_thumbs_point_up_and_down_and_pointing_index_points_down_to_robin() -> None:
    assert _tip("thumb_up", "thumb")[2] > 0.05  # m above the palm centre
    assert _tip("thumb_down", "thumb")[2] < -0.05
    index = _tip("pointing", "index")
    assert index[0] < -0.05 and index[2] < -0.05  # ahead (towards Robin) and below
    for finger in ("middle", "ring", "little"):  # folded: stay within 5 cm of the palm
        assert np.linalg.norm(_tip("pointing", finger)) < 0.07


def test_release_spreads_fingers_wider_than_give_me_and_raises_them() -> None:
    def width(pose: str) -> float:
        ys = [_tip(pose, f)[1] for f in ("index", "little")]
        return abs(ys[0] - ys[1])

    assert width("release") > width("give_me") + 0.03
    assert min(_tip("release", f)[2] for f in ("index", "middle", "ring")) > 0.06
    # give me: flat, the fingertips within 1 cm of the palm's plane (the collision palm's)
    assert max(abs(_tip("give_me", f)[2]) for f in ("index", "middle", "ring", "little")) < 0.01


def test_performances_vary_the_shape_and_the_same_seed_repeats_it() -> None:
    a = Performance.draw(np.random.default_rng(1))
    b = Performance.draw(np.random.default_rng(1))
    c = Performance.draw(np.random.default_rng(2))
    assert a == b and a != c
    moved = np.linalg.norm(_tip("grasp", "index", a) - _tip("grasp", "index", c))
    assert moved > 1e-3
    assert not np.allclose(skin_colour(0.0), skin_colour(4.0))


def test_display_forms_the_articulated_hand_and_physics_is_untouched() -> None:
    model = build_model()
    data = mujoco.MjData(model)
    before = model.body_mass.copy(), model.geom_contype.copy()
    display = GestureDisplay(model, data)
    assert display.shaper is None and display.hand is not None
    display.show("thumb_up", Performance(skin=3.0))
    mujoco.mj_kinematics(model, data)
    tips = {f: data.site(names.person_fingertip_site("r", f)).xpos[2] for f in HAND}
    # the thumb up: its tip at least 3 cm above every fingertip of the fist
    assert all(tips["thumb"] > tips[f] + 0.03 for f in HAND[1:]), tips
    hand = display.geoms("thumb_up")
    np.testing.assert_allclose(model.geom_rgba[list(hand), :3], [skin_colour(3.0)] * len(hand))
    assert np.all(model.body_mass == before[0]) and np.all(model.geom_contype == before[1])
    assert set(SHAPES) == set(names.HUMAN_VIS_POSES)
