"""How deep the person's body reaches into the things around it: legs, table, bin and robot.

The articulated person is kinematic and its geoms never collide (``contype`` = ``conaffinity``
= 0), so nothing in the physics keeps it out of anything; this module measures what a render
would show. :class:`Clearance` collects the person's geoms (every geom of the bodies
``human`` and ``human_hand`` and below them; the collision palm ``human_palm_body`` is physics,
not the figure) and the geoms of four categories: ``legs`` (the loose table legs that are
handed over), ``table`` (its top and its four fixed legs), ``bin`` and ``robot``. For one state
of ``model`` / ``data`` (kinematics computed), :meth:`Clearance.measure` returns every person
geom's penetration into each of them: ``mujoco.mj_geomDistance`` (signed distance, negative
when they overlap; it works whatever the geoms' collision bits) after a bounding-sphere broad
phase, so the few pairs that can touch are the only ones it computes.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from robin_sim.model import names
from robin_sim.model.geom_groups import CATEGORIES, body_geoms, category_geoms, geom_label

# m: pairs whose bounding spheres lie further apart than this are never measured
BROAD_MARGIN = 1e-3


@dataclass(frozen=True)
class Reach:
    """One person geom overlapping one other geom: ``depth`` m into it (> 0)."""

    person: str
    other: str
    category: str
    depth: float


class Clearance:
    """Measures the person's geoms against the legs, the table, the bin and the robot."""

    def __init__(self, model: mujoco.MjModel) -> None:
        self.model = model
        self.person = body_geoms(model, (names.PERSON_BODY, names.HUMAN_MOCAP_BODY))
        groups = category_geoms(model)
        self.others = np.concatenate([groups[c] for c in CATEGORIES])
        self.category = np.concatenate([[c] * len(groups[c]) for c in CATEGORIES])
        self._fromto = np.zeros(6)

    def measure(self, data: mujoco.MjData) -> list[Reach]:
        """Every overlapping pair (person geom, other geom) in ``data``'s computed kinematics,
        deepest first."""
        model = self.model
        centres = data.geom_xpos
        radius = model.geom_rbound
        gap = np.linalg.norm(
            centres[self.person][:, None, :] - centres[self.others][None, :, :], axis=2
        )
        gap -= radius[self.person][:, None] + radius[self.others][None, :]
        out = []
        for i, j in zip(*np.nonzero(gap < BROAD_MARGIN), strict=True):
            a, b = int(self.person[i]), int(self.others[j])
            distance = mujoco.mj_geomDistance(model, data, a, b, BROAD_MARGIN, self._fromto)
            if distance < 0.0:
                label_a, label_b = geom_label(model, a), geom_label(model, b)
                out.append(Reach(label_a, label_b, str(self.category[j]), -float(distance)))
        return sorted(out, key=lambda r: -r.depth)

    def deepest(self, data: mujoco.MjData) -> dict[str, float]:
        """The deepest penetration (m, 0 when clear) into each category in ``data``."""
        out = dict.fromkeys(CATEGORIES, 0.0)
        for reach in self.measure(data):
            out[reach.category] = max(out[reach.category], reach.depth)
        return out
