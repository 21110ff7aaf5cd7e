"""Where the person's head and hands appear in a camera's image: pixel boxes that hold them.

:func:`part_boxes` projects, for the simulation as it is now, the bounding box of every geom of
the person's head (:data:`~robin_sim.model.names.PERSON_HEAD_BODY` and below) and of each hand
(:func:`~robin_sim.model.names.person_hand_body` and below) through a camera, and returns the
pixel box (x0, y0, x1, y1) that holds each part: the corners of each geom's own box (from its
type and size now) are projected with the pinhole model MuJoCo renders with
(:func:`robin_sim.render.spots.project`), so a box holds every pixel the part covers. The
overlay's panels are placed clear of these boxes (:mod:`robin_sim.render.overlay`,
``tests/test_overlay_clear.py``).
"""

from __future__ import annotations

import itertools

import mujoco
import numpy as np

from robin_sim.figure.articulated import subtree_geoms
from robin_sim.model import names
from robin_sim.render.spots import project

Box = tuple[float, float, float, float]  # x0, y0, x1, y1 in pixels
_SIGNS = np.array(list(itertools.product((-1.0, 1.0), repeat=3)))


def person_parts(model: mujoco.MjModel) -> dict[str, np.ndarray]:
    """Geom ids of the person's head and hands, by part name."""
    return {
        "head": subtree_geoms(model, names.PERSON_HEAD_BODY),
        "right hand": subtree_geoms(model, names.person_hand_body("r")),
        "left hand": subtree_geoms(model, names.person_hand_body("l")),
    }


def half_extents(model: mujoco.MjModel, geom: int) -> np.ndarray:
    """Half sizes (3,) of the box that holds ``geom`` in its own frame."""
    size, kind = model.geom_size[geom], int(model.geom_type[geom])
    if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
        return np.full(3, size[0])
    if kind == mujoco.mjtGeom.mjGEOM_CAPSULE:
        return np.array([size[0], size[0], size[1] + size[0]])
    if kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
        return np.array([size[0], size[0], size[1]])
    if kind in (mujoco.mjtGeom.mjGEOM_BOX, mujoco.mjtGeom.mjGEOM_ELLIPSOID):
        return size.copy()
    raise ValueError(
        f"geom {geom} has type {kind}: only spheres, capsules, cylinders, boxes "
        "and ellipsoids are boxed"
    )


def geom_corners(model: mujoco.MjModel, data: mujoco.MjData, geoms: np.ndarray) -> np.ndarray:
    """World corners (8 per geom, (8 n, 3)) of the boxes holding ``geoms`` now."""
    corners = []
    for g in geoms:
        local = _SIGNS * half_extents(model, int(g))
        corners.append(data.geom_xpos[g] + local @ data.geom_xmat[g].reshape(3, 3).T)
    return np.concatenate(corners)


def part_boxes(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    camera: int,
    size: tuple[int, int],
    parts: dict[str, np.ndarray] | None = None,
) -> dict[str, Box]:
    """Pixel box of each part (default :func:`person_parts`) seen by ``camera`` at ``size``
    (w, h); the positions are ``data``'s as they are (call ``mj_fwdPosition`` first)."""
    boxes = {}
    for name, geoms in (parts or person_parts(model)).items():
        pixels = project(model, data, camera, geom_corners(model, data, geoms), size)
        if np.isnan(pixels).any():
            raise ValueError(f"the person's {name} lies partly behind camera {camera}")
        (x0, y0), (x1, y1) = pixels.min(axis=0), pixels.max(axis=0)
        boxes[name] = (float(x0), float(y0), float(x1), float(y1))
    return boxes


def overlaps(a: Box, b: Box) -> bool:
    """Whether two pixel boxes (x0, y0, x1, y1; x1, y1 exclusive) share a pixel."""
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]
