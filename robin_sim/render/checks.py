"""Confirm from off-screen renders what physics says: a leg in the hand, on the palm, at a spot.

Each check renders a close-up of the place in question from a free camera aimed at it, twice:
a segmentation render (which geom, hence which body, covers each pixel) and a depth render
(metres along the view axis). With the camera's pose and intrinsics every pixel of the leg is
lifted back to a 3-D surface point, so a check measures *what the camera sees* in metres:

* **in hand** (:func:`verify_in_hand`): at least ``MIN_PIXELS`` leg pixels whose surface points
  lie within ``IN_HAND_RADIUS_M`` = 0.05 m of the hand's grasp site, and at least
  ``MIN_TOUCH_PIXELS`` leg pixels touching hand pixels (within ``TOUCH_PX`` = 2 px in the image
  and ``TOUCH_DEPTH_M`` = 0.03 m in depth). Four views around the site (azimuth 0/90/180/270°,
  elevation -35°, 0.45 m away); one clear view suffices, since fingers may hide the leg in others.
* **on palm** (:func:`verify_on_palm`) and **at spot** (:func:`verify_at_spot`) look at the
  place from ``SURFACE_VIEWS``: straight down and four oblique views (azimuth 0/90/180/270°,
  elevation -55°), 0.6 m away, so that the hand that just let go cannot hide the leg from all
  of them. The leg points of all views are fused (one per 5 mm cube, ``VOXEL_M``); the leg's
  *top* is the 98th percentile of their heights.
* on palm: at least ``MIN_PIXELS`` leg pixels whose points lie over the palm's footprint (its
  box, plus ``FOOTPRINT_TOL_M`` = 0.01 m), and the top of the leg's points over the palm at
  the leg's thickness above the palm's top face, within ``HEIGHT_TOL_M`` = 0.005 m (resting on
  it; a leg still held 1.2 cm above the palm, the robot's release gap, fails).
* at spot: the centre of the fused points lies within ``tol_m`` (default ``AT_SPOT_TOL_M`` =
  0.04 m) of the spot in x-y; in the view that shows it best, the spot (raised to the leg's
  top) projects inside the leg's pixel blob or within ``tol_m`` converted to pixels (focal
  length x ``tol_m`` / depth), where pixels of things more than ``HEIGHT_TOL_M`` above the
  leg's top (the hand) count as possibly hiding the leg; and the leg's top lies at its
  thickness above the table within ``HEIGHT_TOL_M`` (lying there, not held above it).

Pixel counts are for the default 320x240 views. Rendering reads ``data`` and never changes it.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import mujoco
import numpy as np

from pil.errors import InvalidChoiceError, RobinPilError
from robin_sim.model import names
from robin_sim.render.renderer import CloseUpRenderer, Observation

IN_HAND_RADIUS_M = 0.05
TOUCH_PX = 2
TOUCH_DEPTH_M = 0.03
FOOTPRINT_TOL_M = 0.01
HEIGHT_TOL_M = 0.005
AT_SPOT_TOL_M = 0.04
MIN_PIXELS = 20
MIN_TOUCH_PIXELS = 5
IN_HAND_VIEWS: tuple[tuple[float, float], ...] = ((0, -35), (90, -35), (180, -35), (270, -35))
CLOSE_UP_DISTANCE_M = 0.45
# straight down (exactly -90 makes the up vector degenerate) and four oblique views
SURFACE_VIEWS: tuple[tuple[float, float], ...] = (
    (90, -89),
    (0, -55),
    (90, -55),
    (180, -55),
    (270, -55),
)
SURFACE_DISTANCE_M = 0.6
VOXEL_M = 0.005  # fused surface points: one per 5 mm cube
TOP_PERCENTILE = 98  # "top" of a leg: this percentile of its points' heights (not the maximum)


@dataclass(frozen=True, slots=True)
class RenderCheck:
    """Result of one render check; ``pixels`` is the evidence count the decision rests on."""

    ok: bool
    detail: str
    pixels: int  # leg pixels that satisfy the check's geometric condition
    leg_pixels: int = 0  # all leg pixels in the deciding view
    view: str = ""  # which view decided, e.g. "azimuth 90, elevation -35"


def _subtree(model: mujoco.MjModel, root: int) -> np.ndarray:
    """Boolean mask over bodies: ``root`` and its descendants."""
    inside = np.zeros(model.nbody, dtype=bool)
    inside[root] = True
    for body in range(root + 1, model.nbody):  # parents precede children in MuJoCo
        inside[body] = inside[model.body_parentid[body]]
    return inside


def _id(model: mujoco.MjModel, kind: mujoco.mjtObj, name: str, what: str) -> int:
    index = mujoco.mj_name2id(model, kind, name)
    if index < 0:
        raise RobinPilError(f"the model has no {what} named {name!r}")
    return index


def _leg_ids(model: mujoco.MjModel, leg: int) -> tuple[int, int]:
    """Body and geom id of leg ``leg``; unknown legs list the valid indices."""
    count = 0
    while mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, names.leg_body(count)) >= 0:
        count += 1
    if not 0 <= leg < count:
        raise InvalidChoiceError("leg", leg, range(count))
    body = _id(model, mujoco.mjtObj.mjOBJ_BODY, names.leg_body(leg), "leg body")
    geom = _id(model, mujoco.mjtObj.mjOBJ_GEOM, names.leg_geom(leg), "leg geom")
    return body, geom


def leg_thickness(model: mujoco.MjModel, geom: int) -> float:
    """Height of a lying leg: its diameter (capsule, cylinder, sphere) or smallest box extent."""
    size = model.geom_size[geom]
    if model.geom_type[geom] == mujoco.mjtGeom.mjGEOM_BOX:
        return float(2 * size.min())
    return float(2 * size[0])


def _view_name(azimuth: float, elevation: float) -> str:
    return f"azimuth {azimuth:g}, elevation {elevation:g}"


_SURFACE_VIEWS_NAME = "; ".join(_view_name(*view) for view in SURFACE_VIEWS)


def _touching(obs: Observation, leg: np.ndarray, hand: np.ndarray) -> np.ndarray:
    """Leg pixels next to a hand pixel (``TOUCH_PX``) at a similar depth (``TOUCH_DEPTH_M``)."""
    size = 2 * TOUCH_PX + 1
    kernel = np.ones((size, size), np.uint8)
    hand_depth = np.where(hand, obs.depth, np.inf).astype(np.float32)
    nearest_front = cv2.erode(hand_depth, kernel)  # min depth of hand pixels in reach
    farthest = cv2.dilate(np.where(hand, obs.depth, -np.inf).astype(np.float32), kernel)
    near_hand = cv2.dilate(hand.astype(np.uint8), kernel).astype(bool)
    close = (obs.depth >= nearest_front - TOUCH_DEPTH_M) & (obs.depth <= farthest + TOUCH_DEPTH_M)
    return leg & near_hand & close


def verify_in_hand(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    leg: int,
    side: names.Side,
    renderer: CloseUpRenderer | None = None,
) -> RenderCheck:
    """Is leg ``leg`` seen between the fingers of hand ``side``? (see module doc)."""
    leg_body, _ = _leg_ids(model, leg)
    site = _id(model, mujoco.mjtObj.mjOBJ_SITE, names.grasp_site(side), "grasp site")
    hand_root = _id(model, mujoco.mjtObj.mjOBJ_BODY, names.hand_body(side), "hand body")
    leg_bodies, hand_bodies = _subtree(model, leg_body), _subtree(model, hand_root)
    centre = data.site_xpos[site].copy()
    own = renderer or CloseUpRenderer(model)
    best: RenderCheck | None = None
    try:
        for azimuth, elevation in IN_HAND_VIEWS:
            obs = own.observe(data, centre, azimuth, elevation, CLOSE_UP_DISTANCE_M)
            valid = obs.body >= 0
            leg_mask = valid & leg_bodies[np.maximum(obs.body, 0)]
            hand_mask = valid & hand_bodies[np.maximum(obs.body, 0)]
            points = obs.lift(leg_mask)
            near = int(np.sum(np.linalg.norm(points - centre, axis=1) <= IN_HAND_RADIUS_M))
            touch = int(_touching(obs, leg_mask, hand_mask).sum())
            check = RenderCheck(
                near >= MIN_PIXELS and touch >= MIN_TOUCH_PIXELS,
                f"{near} leg pixels within {IN_HAND_RADIUS_M} m of {names.grasp_site(side)}, "
                f"{touch} touching the hand (need {MIN_PIXELS} and {MIN_TOUCH_PIXELS})",
                near,
                int(leg_mask.sum()),
                _view_name(azimuth, elevation),
            )
            if check.ok:
                return check
            if best is None or check.pixels > best.pixels:
                best = check
        assert best is not None
        return best
    finally:
        if renderer is None:
            own.close()


def _look_around(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    leg: int,
    lookat: np.ndarray,
    renderer: CloseUpRenderer | None,
) -> tuple[list[tuple[Observation, np.ndarray]], float]:
    """``SURFACE_VIEWS`` of ``lookat``: (observation, leg pixel mask) each, and leg thickness."""
    leg_body, leg_geom = _leg_ids(model, leg)
    leg_bodies = _subtree(model, leg_body)
    own = renderer or CloseUpRenderer(model)
    views = []
    try:
        for azimuth, elevation in SURFACE_VIEWS:
            obs = own.observe(data, lookat, azimuth, elevation, SURFACE_DISTANCE_M)
            views.append((obs, (obs.body >= 0) & leg_bodies[np.maximum(obs.body, 0)]))
    finally:
        if renderer is None:
            own.close()
    return views, leg_thickness(model, leg_geom)


def _fused_points(views: list[tuple[Observation, np.ndarray]]) -> np.ndarray:
    """Leg surface points of all views, one per ``VOXEL_M`` cube (no view counts twice)."""
    points = np.concatenate([obs.lift(mask) for obs, mask in views])
    _, first = np.unique(np.floor(points / VOXEL_M).astype(np.int64), axis=0, return_index=True)
    return points[np.sort(first)]


def verify_on_palm(
    model: mujoco.MjModel, data: mujoco.MjData, leg: int, renderer: CloseUpRenderer | None = None
) -> RenderCheck:
    """Does leg ``leg`` rest on the person's palm? (see module doc)."""
    palm = _id(model, mujoco.mjtObj.mjOBJ_GEOM, names.HUMAN_PALM_GEOM, "palm geom")
    if model.geom_type[palm] != mujoco.mjtGeom.mjGEOM_BOX:
        raise RobinPilError(f"verify_on_palm needs a box {names.HUMAN_PALM_GEOM!r} geom")
    axes = data.geom_xmat[palm].reshape(3, 3)  # columns: the box's axes in the world
    half = model.geom_size[palm]
    normal_axis = int(np.argmax(np.abs(axes[2])))  # the box axis closest to vertical
    up = np.sign(axes[2, normal_axis])
    top_face = data.geom_xpos[palm] + axes[:, normal_axis] * up * half[normal_axis]
    views, thickness = _look_around(model, data, leg, top_face, renderer)
    lateral = [a for a in range(3) if a != normal_axis]
    local = (_fused_points(views) - top_face) @ axes
    inside = np.all(np.abs(local[:, lateral]) <= half[lateral] + FOOTPRINT_TOL_M, axis=1)
    seen = sum(int(mask.sum()) for _, mask in views)
    over = int(sum(_count_over(obs, mask, top_face, axes, lateral, half) for obs, mask in views))
    heights = local[inside, normal_axis] * up
    top = float(np.percentile(heights, TOP_PERCENTILE)) if heights.size else 0.0
    ok = over >= MIN_PIXELS and abs(top - thickness) <= HEIGHT_TOL_M
    return RenderCheck(
        ok,
        f"{over} of {seen} leg pixels ({len(views)} views) over the palm (need {MIN_PIXELS}); "
        f"leg top {top:.3f} m above the palm (a resting leg: {thickness:.3f} ± {HEIGHT_TOL_M} m)",
        over,
        seen,
        _SURFACE_VIEWS_NAME,
    )


def _count_over(
    obs: Observation,
    mask: np.ndarray,
    origin: np.ndarray,
    axes: np.ndarray,
    lateral: list[int],
    half: np.ndarray,
) -> int:
    """Leg pixels of one view whose surface points lie over the palm's footprint."""
    local = (obs.lift(mask) - origin) @ axes
    return int(np.sum(np.all(np.abs(local[:, lateral]) <= half[lateral] + FOOTPRINT_TOL_M, axis=1)))


def _spot_pixel_offset(obs: Observation, mask: np.ndarray, spot_top: np.ndarray) -> float:
    """Pixels from the projected spot to the leg's blob, counting pixels of things above the
    leg's top (e.g. the hand that placed it) as possibly hiding the leg; inf if out of view."""
    pixel, depth = obs.project(spot_top)
    col, row = np.round(pixel[0]).astype(int)
    height, width = mask.shape
    if depth[0] <= 0 or not (0 <= col < width and 0 <= row < height):
        return float("inf")
    hidden = (obs.body >= 0) & ~mask & (obs.depth < float(depth[0]) - HEIGHT_TOL_M)
    distance = cv2.distanceTransform((~(mask | hidden)).astype(np.uint8), cv2.DIST_L2, 5)
    return float(distance[row, col])


def verify_at_spot(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    leg: int,
    spot_xy: tuple[float, float],
    tol_m: float = AT_SPOT_TOL_M,
    renderer: CloseUpRenderer | None = None,
) -> RenderCheck:
    """Does leg ``leg`` lie on the table at ``spot_xy``? (see module doc)."""
    table = _id(model, mujoco.mjtObj.mjOBJ_GEOM, names.TABLE_TOP_GEOM, "table top geom")
    table_z = float(data.geom_xpos[table][2] + model.geom_size[table][2])
    spot = np.array([spot_xy[0], spot_xy[1], table_z])
    views, thickness = _look_around(model, data, leg, spot, renderer)
    seen = sum(int(mask.sum()) for _, mask in views)
    if seen < MIN_PIXELS:
        return RenderCheck(
            False, f"only {seen} leg pixels in view of the spot", seen, seen, _SURFACE_VIEWS_NAME
        )
    points = _fused_points(views)
    offset = float(np.linalg.norm(points[:, :2].mean(axis=0) - spot[:2]))
    top = float(np.percentile(points[:, 2], TOP_PERCENTILE) - table_z)
    spot_top = spot + np.array([0.0, 0.0, thickness])
    # the pixel test in the view that shows the spot best, in units of that view's tolerance
    ratios = []
    for obs, mask in views:
        tol_px = tol_m * obs.focal[0] / float(obs.project(spot_top)[1][0])
        ratios.append((_spot_pixel_offset(obs, mask, spot_top) / tol_px, tol_px))
    ratio, tol_px = min(ratios)
    ok = offset <= tol_m and ratio <= 1.0 and abs(top - thickness) <= HEIGHT_TOL_M
    return RenderCheck(
        ok,
        f"leg centre {offset:.3f} m from the spot (tol {tol_m} m), spot {ratio * tol_px:.1f} px "
        f"from the leg (tol {tol_px:.1f} px), leg top {top:.3f} m above the table (a lying leg: "
        f"{thickness:.3f} ± {HEIGHT_TOL_M} m); {seen} leg pixels in {len(views)} views",
        seen,
        seen,
        _SURFACE_VIEWS_NAME,
    )
