"""Where the actions go: the learner's targets mapped to points and grasp-site goal poses.

``Target("leg", k)`` means leg ``k`` where physics has it now (measured, so a nudged leg is
still grasped where it lies); ``Target("spot", k)`` is the layout's table spot ``k``. Bad
indices and kinds raise a :class:`~pil.errors.RobinPilError` that lists the valid ones; a goal
the arm's plan does not reach raises :class:`UnreachableTargetError` (:func:`check_reached`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import mink
import numpy as np

from pil.errors import RobinPilError
from pil.task.world import Target
from robin_sim.control.ik import JointPlan
from robin_sim.model import robot_spec as spec
from robin_sim.model.scene import SceneLayout

TARGET_KINDS = ("leg", "spot")


class UnreachableTargetError(RobinPilError):
    """A motion target the arm cannot reach; raised before anything moves."""

    def __init__(
        self,
        target: str,
        position: Sequence[float],
        missed_by: float,
        turned_short_by: float,
        region: str,
    ) -> None:
        where = "(" + ", ".join(f"{v:.3f}" for v in position) + ")"
        super().__init__(
            f"{target} at {where} m is out of the arm's reach (the IK stops {missed_by * 100:.1f}"
            f" cm and {math.degrees(turned_short_by):.1f} degrees short); reachable: {region}."
            " Move it into the reachable region of the layout."
        )
        self.target = target
        self.position = tuple(float(v) for v in position)
        self.missed_by = missed_by
        self.turned_short_by = turned_short_by
        self.region = region


def check_reached(plan: JointPlan, target: str, goal: mink.SE3, region: str) -> None:
    """Raise :class:`UnreachableTargetError` unless ``plan`` ends at ``goal`` (both tolerances)."""
    if not plan.reaches_goal:
        raise UnreachableTargetError(
            target, goal.translation().tolist(), plan.position_error, plan.orientation_error, region
        )


def reach_text() -> str:
    """The reachable region, for error messages."""
    corners = ", ".join(f"({x:.2f}, {y:.2f})" for x, y in spec.LEFT_REACH_POLYGON)
    return f"top-down at table height, (x, y) inside the polygon {corners} m"


def grasp_goal(
    leg_centre: np.ndarray, leg_axis: np.ndarray, current: mink.SE3, height: float
) -> mink.SE3:
    """Top-down grasp pose: site ``height`` above the leg centre, fingers closing across it.

    The site's z axis points down and its y axis runs along the leg (the sign that turns the
    wrist least from ``current``).
    """
    axis = np.asarray(leg_axis, float).copy()
    axis[2] = 0.0
    axis /= np.linalg.norm(axis)
    if axis @ current.rotation().as_matrix()[:, 1] < 0.0:
        axis = -axis
    z = np.array([0.0, 0.0, -1.0])
    rotation = mink.SO3.from_matrix(np.column_stack([np.cross(axis, z), axis, z]))
    return mink.SE3.from_rotation_and_translation(rotation, leg_centre + np.array([0, 0, height]))


def release_goal(point: np.ndarray, offset_in_site: np.ndarray, rotation: mink.SO3) -> mink.SE3:
    """Site pose that puts a held leg's centre (``offset_in_site`` from the site) at ``point``."""
    site_position = np.asarray(point, float) - rotation.apply(offset_in_site)
    return mink.SE3.from_rotation_and_translation(rotation, site_position)


def check_leg(index: int, count: int) -> int:
    """``index`` if leg ``index`` exists, else a clear error."""
    if not 0 <= index < count:
        raise RobinPilError(f"leg {index} does not exist; valid: 0..{count - 1}")
    return index


def spot_surface(layout: SceneLayout, index: int) -> np.ndarray:
    """Table-top point (z = table top) of spot ``index``."""
    if not 0 <= index < len(layout.spots):
        raise RobinPilError(f"spot {index} does not exist; valid: 0..{len(layout.spots) - 1}")
    x, y = layout.spots[index]
    return np.array([x, y, spec.TABLE_TOP_Z])


def check_kind(target: Target | None) -> None:
    """Raise a clear error for a target kind other than 'leg' or 'spot'."""
    if target is not None and target.kind not in TARGET_KINDS:
        valid = ", ".join(repr(k) for k in TARGET_KINDS)
        raise RobinPilError(f"unknown target kind {target.kind!r}; valid: {valid}")


def target_point(
    target: Target | None,
    layout: SceneLayout,
    leg_position: Callable[[int], np.ndarray],
    default_leg: Callable[[], int],
) -> np.ndarray:
    """The pointed leg's centre or the spot at leg-centre height; no target: ``default_leg()``."""
    check_kind(target)
    if target is not None and target.kind == "spot":
        return spot_surface(layout, target.index) + np.array([0.0, 0.0, spec.LEG_RADIUS])
    index = default_leg() if target is None else target.index
    return leg_position(check_leg(index, len(layout.legs)))


def location_surface(target: Target | None, layout: SceneLayout, near: np.ndarray) -> np.ndarray:
    """The table point "location" means: the pointed spot, else the spot nearest ``near``."""
    check_kind(target)
    if target is not None and target.kind == "spot":
        return spot_surface(layout, target.index)
    spots = np.array(layout.spots)
    nearest = int(np.argmin(np.linalg.norm(spots - np.asarray(near)[:2], axis=1)))
    return spot_surface(layout, nearest)


AXIS_SAMPLE = 0.01  # m between the points of a leg's axis tested against a region


def axis_points(centre: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Points (x, y) every :data:`AXIS_SAMPLE` m along the axis of a leg lying at ``centre``
    along ``axis`` (the capsule's segment, without its round caps), shape (n, 2)."""
    reach = spec.LEG_LENGTH / 2 - spec.LEG_RADIUS
    along = np.linspace(-reach, reach, int(np.ceil(2 * reach / AXIS_SAMPLE)) + 1)
    direction = np.asarray(axis, float)[:2]
    return np.asarray(centre, float)[:2] + along[:, None] * direction


def reaches_into(
    points: np.ndarray, centre: np.ndarray, along: np.ndarray, half: tuple[float, float]
) -> bool:
    """True when a leg whose axis passes through ``points`` reaches into the rectangle around
    ``centre`` (x, y) with half sizes ``half`` along the unit vector ``along`` and across it:
    some point lies within the rectangle grown by a leg's radius."""
    u = np.asarray(along, float)[:2]
    u = u / np.linalg.norm(u)
    v = np.array([-u[1], u[0]])
    rel = points - np.asarray(centre, float)[:2]
    inside = (np.abs(rel @ u) <= half[0] + spec.LEG_RADIUS) & (
        np.abs(rel @ v) <= half[1] + spec.LEG_RADIUS
    )
    return bool(inside.any())


def fingers_blocked(
    centre: np.ndarray, axis: np.ndarray, others: list[tuple[np.ndarray, np.ndarray]]
) -> bool:
    """True when another leg (centre and axis, in ``others``) lies where the open fingers come
    down to grasp a leg at ``centre`` along ``axis``: within :data:`~robot_spec.FINGER_SPREAD`
    either side of its axis, :data:`~robot_spec.FINGER_ALONG` along it. A leg dropped there,
    against another, is put back by the person instead."""
    half = (spec.FINGER_ALONG, spec.FINGER_SPREAD)
    return any(reaches_into(axis_points(c, a), centre, axis, half) for c, a in others)
