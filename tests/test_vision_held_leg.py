"""The gesture data set's held-leg samples: Robin holds a leg above the palm, the hand under it.

In an episode the person shows "release" (and at times "give me") with the palm slid under a
leg that Robin holds above it, and a thumb drawn back, raised and aside; the ``held_leg`` split
draws every sample in that arm state (reached by real actions: ``arm_states.held_leg_qpos``),
the training split a ninth of its samples, and the held-out and sweep splits none (the
paired tables' samples stay the same).
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from scipy.stats import binom

from robin_sim.model import names
from robin_sim.model.robot_spec import PERSON_CLEAR_X, POINT_RAISE, THUMB_ASIDE
from robin_sim.vision.arm_states import PALM_LEG
from robin_sim.vision.classifier import CLASSES
from robin_sim.vision.dataset import (
    HANDOVER_HAND,
    SPLITS,
    THUMB_SIGNS,
    UNDER_LEG_DROP,
    UNDER_LEG_SPREAD,
    sample_spec,
)

SAMPLES = 1600


def test_the_held_leg_split_draws_every_sample_under_the_leg_the_training_split_a_ninth() -> None:
    held = [sample_spec(0, "held_leg", i) for i in range(SAMPLES)]
    assert all(s.arm == "held_leg" for s in held)
    assert {s.label for s in held} == set(range(7))  # every class is shown under the leg
    for spec in held:
        offset = spec.held_at - HANDOVER_HAND
        assert spec.lift == 0.0
        if CLASSES[spec.label] in (*THUMB_SIGNS, "pointing"):  # drawn back and raised, as shown
            assert abs(spec.held_at[0] - PERSON_CLEAR_X) < 0.1
            assert abs(offset[2] - POINT_RAISE) < 0.1
            aside = THUMB_ASIDE if CLASSES[spec.label] in THUMB_SIGNS else 0.0
            assert abs(offset[1] - aside) < 0.1
        else:  # under the leg: never raised into it, and near the palm's place
            assert -UNDER_LEG_DROP <= offset[2] <= 0.0
            assert np.all(np.abs(offset[:2]) < 5 * UNDER_LEG_SPREAD)

    # the training split draws a ninth of its samples under the leg (SPLITS), every class
    # among them; the held-out and sweep splits keep the arm at home
    train = [sample_spec(0, "train", i) for i in range(SAMPLES)]
    under = [s for s in train if s.arm == "held_leg"]
    share = SPLITS["train"].held_leg
    low, high = binom.ppf([0.0005, 0.9995], SAMPLES, share)  # a 99.9 % range of the count
    assert share == pytest.approx(1 / 9) and low <= len(under) <= high, len(under)
    assert {s.label for s in under} == set(range(7))
    assert all(sample_spec(0, "heldout", i).arm == "home" for i in range(SAMPLES))
    assert all(sample_spec(0, "sweep", i).arm == "home" for i in range(400))


@pytest.mark.slow
def test_a_held_leg_sample_shows_the_hand_under_the_leg_robin_holds() -> None:
    """Rendered held-leg samples: Robin's hand holds the leg (contact-free distance to its
    fingers under 1 cm), the person's hand stays clear of the leg (no geom of it inside the
    leg: distance >= 0) and below it, and the eyes find a hand in most of them; a home sample
    after them shows the leg back on the table (every sample starts from its own state)."""
    from robin_sim.vision.render_set import POSE_OF, SampleRenderer

    renderer = SampleRenderer()
    model, data = renderer.model, renderer.data
    leg = model.geom(names.leg_geom(PALM_LEG)).id
    grip_bodies = ("l_f1_", "l_f2_", "l_thumb_", "l_palm")  # Robin's left hand holds it
    robin_hand = [
        g
        for g in range(model.ngeom)
        if model.body(model.geom_bodyid[g]).name.startswith(grip_bodies)
    ]
    specs = [sample_spec(0, "held_leg", i) for i in range(12)]
    found = 0
    for spec in specs[:12]:
        crops, _ = renderer.render(spec)
        person = list(renderer.display.geoms(POSE_OF[CLASSES[spec.label]]))  # the shown hand
        found += all(c is not None for c in crops)
        clearance = min(mujoco.mj_geomDistance(model, data, g, leg, 0.2, None) for g in person)
        assert clearance >= 0.0  # the hand never reaches into the held leg
        grip = min(mujoco.mj_geomDistance(model, data, g, leg, 0.2, None) for g in robin_hand)
        assert grip < 0.01  # Robin's fingers are on the leg
        if CLASSES[spec.label] not in (*THUMB_SIGNS, "pointing"):  # the palm is under the leg
            assert data.site(names.HUMAN_PALM_SITE).xpos[2] < data.geom_xpos[leg][2]
    assert found >= 9  # both eyes find the hand in most (the leg and Robin's fingers hide some)
    home = sample_spec(0, "train", 0)
    renderer.render(home)
    assert data.geom_xpos[leg][2] < 0.80  # back lying on the table (top at 0.75 m)
    with pytest.raises(ValueError, match="held_leg"):  # an unknown state names the choices
        renderer.set_arm("elbow_up")
