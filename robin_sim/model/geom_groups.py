"""Groups of geoms in the scene: a body's subtree, and the things the person must keep out of.

The loose table legs that are handed over (``legs``), the table (its top and fixed legs), the bin
and the robot: :data:`CATEGORIES`, read from the names of :mod:`robin_sim.model.names`.
"""

from __future__ import annotations

import mujoco
import numpy as np

from robin_sim.model import names
from robin_sim.model.scene import leg_count

CATEGORIES: tuple[str, ...] = ("legs", "table", "bin", "robot")


def subtree_bodies(model: mujoco.MjModel, root: str) -> np.ndarray:
    """Ids of body ``root`` and every body below it."""
    top = model.body(root).id
    inside = np.zeros(model.nbody, dtype=bool)
    inside[top] = True
    for body in range(top + 1, model.nbody):  # a child's id is above its parent's
        inside[body] = inside[model.body_parentid[body]]
    return np.flatnonzero(inside)


def body_geoms(model: mujoco.MjModel, roots: tuple[str, ...]) -> np.ndarray:
    """Geom ids of the bodies ``roots`` and every body below them."""
    bodies = np.concatenate([subtree_bodies(model, root) for root in roots])
    return np.flatnonzero(np.isin(model.geom_bodyid, bodies))


def geom_label(model: mujoco.MjModel, geom: int) -> str:
    """A geom's name, or ``<body>#<n>`` (its n-th geom) for an unnamed one."""
    name = model.geom(geom).name
    if name:
        return str(name)
    body = int(model.geom_bodyid[geom])
    first = int(model.body_geomadr[body])
    return f"{model.body(body).name}#{geom - first}"


def category_geoms(model: mujoco.MjModel) -> dict[str, np.ndarray]:
    """The geom ids of each of :data:`CATEGORIES` in ``model``."""
    legs = [model.geom(names.leg_geom(i)).id for i in range(leg_count(model))]
    return {
        "legs": np.array(legs, dtype=int),
        "table": body_geoms(model, (names.TABLE_BODY,)),
        "bin": body_geoms(model, (names.BIN_BODY,)),
        "robot": body_geoms(model, (names.TORSO_BODY,)),
    }
