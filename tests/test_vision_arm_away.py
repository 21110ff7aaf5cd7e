"""Robin's arm at home hides a hand held above a far place; swung away, it hides none.

``arm_states.away_qpos`` is the what-if ``bench/bench_hand_hidden.py --away`` reads the paired
table's samples with: the active arm swung back behind Robin. The renders here count pixels by
the segmentation renderer (ground truth): the arm's own pixels in each eye, and the true hand's.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from robin_sim.model import names
from robin_sim.vision.classifier import CLASSES
from robin_sim.vision.dataset import sample_spec
from robin_sim.vision.render_set import POSE_OF, SampleRenderer
from robin_sim.vision.segment import MIN_PIXELS

# held-out samples of seed 0 held above the legs and spots furthest to Robin's left, which no
# eye sees with the arm at home (bench/results/hand_hidden/hidden.csv: 0 true hand pixels)
HIDDEN_AT_HOME = (75, 142, 198)


@pytest.fixture(scope="module")
def renderer() -> SampleRenderer:
    return SampleRenderer()


def _arm_geoms(renderer: SampleRenderer) -> list[int]:
    model = renderer.model
    bodies = {model.body(b).id for b in names.arm_bodies(names.ACTIVE_SIDE)}
    return [g for g in range(model.ngeom) if int(model.geom_bodyid[g]) in bodies]


@pytest.mark.parametrize("sample", HIDDEN_AT_HOME)
def test_the_arm_away_leaves_the_hand_it_hid_at_home_in_both_eyes(
    renderer: SampleRenderer, sample: int
) -> None:
    spec = sample_spec(0, "heldout", sample)
    pose = POSE_OF[CLASSES[spec.label]]
    arm = _arm_geoms(renderer)
    seen: dict[str, list[tuple[int, int]]] = {}
    for state in ("home", "away"):
        renderer.render(replace(spec, arm=state))
        seen[state] = [
            (int(renderer.truth_mask(pose, eye).sum()), int(renderer.geom_mask(arm, eye).sum()))
            for eye in (0, 1)
        ]
    # at home: the arm fills part of each eye's view and hides the hand from both eyes
    assert all(hand < MIN_PIXELS and arm_px > 500 for hand, arm_px in seen["home"]), seen
    # away: no pixel of the arm in either eye, and each eye sees the hand
    assert all(hand >= MIN_PIXELS and arm_px == 0 for hand, arm_px in seen["away"]), seen


def test_the_arm_away_moves_only_the_active_arm(renderer: SampleRenderer) -> None:
    renderer.set_arm("home")
    home = renderer.data.qpos.copy()
    renderer.set_arm("away")
    away = renderer.data.qpos.copy()
    model = renderer.model
    arm = [model.jnt_qposadr[model.joint(j).id] for j in names.arm_joints(names.ACTIVE_SIDE)]
    changed = np.flatnonzero(~np.isclose(home, away))
    assert set(changed.tolist()) <= set(arm) and len(changed) > 0
    with pytest.raises(ValueError, match=r"unknown arm state 'aside'.*home, held_leg, away"):
        renderer.set_arm("aside")
