"""Minimum-jerk Cartesian paths for the hand: straight segments and lift-traverse-descend moves.

A :class:`CartesianPath` is a chain of straight segments between :class:`mink.SE3` poses. Each
segment is timed by the minimum-jerk profile ``s(τ) = 10τ³ - 15τ⁴ + 6τ⁵`` so that it starts and ends
at rest with zero acceleration; its duration follows from a peak linear and angular speed (the
profile's peak velocity is 1.875 times its mean). Carried objects are kept clear of the table
and the person by :func:`lift_traverse_descend`: up to a clearance height, across, then down.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import mink
import numpy as np

PEAK_TO_MEAN = 1.875  # peak / mean velocity of a minimum-jerk profile
DEFAULT_SPEED = 0.3  # m/s peak hand speed (0.25-0.5 m/s held grasps; 1 m/s slipped)
DEFAULT_ANGULAR_SPEED = 1.5  # rad/s peak hand angular speed
MIN_SEGMENT_TIME = 0.2  # s; even tiny corrections take this long


def min_jerk(tau: float) -> float:
    """Minimum-jerk time scaling: 0 at ``tau <= 0``, 1 at ``tau >= 1``, smooth in between; never
    outside [0, 1] (the polynomial rounds to 1 + 4e-16 just below ``tau`` 1, which mink's
    rotation interpolation refuses)."""
    t = min(max(tau, 0.0), 1.0)
    return min(t * t * t * (10.0 + t * (-15.0 + 6.0 * t)), 1.0)


def pose(
    position: Sequence[float] | np.ndarray, quat_wxyz: Sequence[float] | np.ndarray | None = None
) -> mink.SE3:
    """An SE3 pose from a position and an optional (w, x, y, z) quaternion (identity if None)."""
    rotation = mink.SO3.identity() if quat_wxyz is None else mink.SO3(np.asarray(quat_wxyz, float))
    return mink.SE3.from_rotation_and_translation(rotation.normalize(), np.asarray(position, float))


def rotation_angle(a: mink.SE3, b: mink.SE3) -> float:
    """Angle in radians of the rotation taking ``a``'s orientation to ``b``'s."""
    return float(np.linalg.norm((a.rotation().inverse() @ b.rotation()).log()))


@dataclass(frozen=True)
class Segment:
    """A straight move from ``start`` to ``end`` in ``duration`` seconds (minimum jerk)."""

    start: mink.SE3
    end: mink.SE3
    duration: float

    def sample(self, t: float) -> mink.SE3:
        """The pose at time ``t`` in [0, duration] (clamped)."""
        if self.duration <= 0.0:
            return self.end
        s = min_jerk(t / self.duration)
        position = (1.0 - s) * self.start.translation() + s * self.end.translation()
        if self._turns:
            rotation = self.start.rotation().interpolate(self.end.rotation(), s)
        else:
            rotation = self.start.rotation()
        return mink.SE3.from_rotation_and_translation(rotation, position)

    @property
    def _turns(self) -> bool:
        """False when both ends have the same orientation (no interpolation needed)."""
        a, b = self.start.wxyz_xyz[:4], self.end.wxyz_xyz[:4]
        return not (np.array_equal(a, b) or np.array_equal(a, -b))


def segment_duration(
    start: mink.SE3,
    end: mink.SE3,
    speed: float = DEFAULT_SPEED,
    angular_speed: float = DEFAULT_ANGULAR_SPEED,
    min_time: float = MIN_SEGMENT_TIME,
) -> float:
    """Duration of a minimum-jerk move whose peak speeds stay within the given limits."""
    distance = float(np.linalg.norm(end.translation() - start.translation()))
    angle = rotation_angle(start, end)
    return max(PEAK_TO_MEAN * distance / speed, PEAK_TO_MEAN * angle / angular_speed, min_time)


@dataclass(frozen=True)
class CartesianPath:
    """Consecutive segments, each starting where the previous one ended."""

    segments: tuple[Segment, ...]

    @property
    def duration(self) -> float:
        """Total time of the path in seconds."""
        return float(sum(s.duration for s in self.segments))

    @property
    def start(self) -> mink.SE3:
        """First pose."""
        return self.segments[0].start

    @property
    def end(self) -> mink.SE3:
        """Last pose."""
        return self.segments[-1].end

    def sample(self, t: float) -> mink.SE3:
        """The pose at time ``t`` (before 0: the start; after the end: the last pose)."""
        for segment in self.segments:
            if t <= segment.duration:
                return segment.sample(t)
            t -= segment.duration
        return self.end

    def waypoints(self) -> list[mink.SE3]:
        """The corner poses: start, then each segment's end."""
        return [self.start, *(s.end for s in self.segments)]


def through(
    waypoints: Sequence[mink.SE3],
    speed: float = DEFAULT_SPEED,
    angular_speed: float = DEFAULT_ANGULAR_SPEED,
) -> CartesianPath:
    """A path through ``waypoints`` (at least two), stopping at each one."""
    if len(waypoints) < 2:
        raise ValueError("a path needs at least two waypoints")
    segments = tuple(
        Segment(a, b, segment_duration(a, b, speed, angular_speed))
        for a, b in itertools.pairwise(waypoints)
    )
    return CartesianPath(segments)


def lift_traverse_descend(
    start: mink.SE3,
    goal: mink.SE3,
    clearance_z: float,
    speed: float = DEFAULT_SPEED,
    angular_speed: float = DEFAULT_ANGULAR_SPEED,
    min_rise: float = 0.0,
) -> CartesianPath:
    """Up from ``start`` to ``clearance_z``, across at that height, down to ``goal``.

    The orientation turns to the goal's during the traverse. The vertical moves are dropped when
    an end already lies at the clearance height (within 1 mm). ``min_rise`` lifts at least that
    much above the start even where the clearance is lower (e.g. to free a grasped leg from the
    table before traversing).
    """
    p0, p1 = start.translation(), goal.translation()
    high = max(clearance_z, p0[2] + min_rise, p1[2])
    above_start = mink.SE3.from_rotation_and_translation(
        start.rotation(), np.array([p0[0], p0[1], high])
    )
    above_goal = mink.SE3.from_rotation_and_translation(
        goal.rotation(), np.array([p1[0], p1[1], high])
    )
    points = [start]
    for point in (above_start, above_goal, goal):
        last = points[-1]
        moved = np.linalg.norm(point.translation() - last.translation()) > 1e-3
        if moved or rotation_angle(last, point) > 1e-3:
            points.append(point)
    if len(points) == 1:
        points.append(goal)
    return through(points, speed, angular_speed)
