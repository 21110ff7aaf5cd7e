"""Minimum-jerk timing, segment durations and lift-traverse-descend paths (no physics)."""

from __future__ import annotations

import mink
import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from robin_sim.control.trajectory import (
    PEAK_TO_MEAN,
    CartesianPath,
    Segment,
    lift_traverse_descend,
    min_jerk,
    pose,
    rotation_angle,
    segment_duration,
    through,
)


def _speeds(path: CartesianPath, dt: float = 1e-3) -> np.ndarray:
    times = np.arange(0.0, path.duration + dt, dt)
    points = np.array([path.sample(t).translation() for t in times])
    return np.linalg.norm(np.diff(points, axis=0), axis=1) / dt


def test_min_jerk_ends_at_rest_and_is_symmetric() -> None:
    assert min_jerk(0.0) == 0.0 and min_jerk(1.0) == 1.0
    assert min_jerk(-1.0) == 0.0 and min_jerk(2.0) == 1.0
    assert min_jerk(0.5) == pytest.approx(0.5)
    taus = np.linspace(0.0, 1.0, 101)
    values = np.array([min_jerk(t) for t in taus])
    assert np.all(np.diff(values) >= 0.0)
    assert values + values[::-1] == pytest.approx(np.ones_like(values))
    h = 1e-4  # zero velocity at both ends
    assert min_jerk(h) / h < 1e-6 and (1.0 - min_jerk(1.0 - h)) / h < 1e-6


def test_segment_duration_keeps_peak_speed() -> None:
    a, b = pose([0.0, 0.0, 0.0]), pose([0.3, 0.4, 0.0])  # 0.5 m
    duration = segment_duration(a, b, speed=0.25)
    assert duration == pytest.approx(PEAK_TO_MEAN * 0.5 / 0.25)
    peak = _speeds(CartesianPath((Segment(a, b, duration),))).max()
    assert peak == pytest.approx(0.25, rel=2e-3)


def test_rotation_bounds_duration_of_turn_in_place() -> None:
    a = pose([0.1, 0.2, 0.3])
    b = mink.SE3.from_rotation_and_translation(mink.SO3.from_z_radians(1.2), a.translation())
    assert rotation_angle(a, b) == pytest.approx(1.2)
    assert segment_duration(a, b, speed=0.3, angular_speed=1.0) == pytest.approx(1.875 * 1.2)


def test_path_samples_are_continuous_and_end_exactly() -> None:
    path = through([pose([0, 0, 1]), pose([0.2, 0, 1]), pose([0.2, 0.3, 0.8])], speed=0.4)
    assert len(path.segments) == 2
    assert path.sample(-1.0).translation() == pytest.approx([0, 0, 1])
    assert path.sample(path.duration + 5.0).translation() == pytest.approx([0.2, 0.3, 0.8])
    assert _speeds(path).max() <= 0.4 * 1.002


def test_lift_traverse_descend_stays_above_clearance_between_ends() -> None:
    start, goal = pose([0.5, 0.1, 0.77]), pose([0.62, -0.05, 0.9])
    path = lift_traverse_descend(start, goal, clearance_z=0.95, speed=0.3)
    corners = path.waypoints()
    assert [round(p.translation()[2], 6) for p in corners] == [0.77, 0.95, 0.95, 0.9]
    times = np.linspace(0.0, path.duration, 400)
    xy = np.array([path.sample(t).translation() for t in times])
    first_leave = path.segments[0].duration
    last_arrive = path.duration - path.segments[-1].duration
    middle = xy[(times > first_leave) & (times < last_arrive)]
    assert middle[:, 2].min() == pytest.approx(0.95)
    assert np.abs(xy[times <= first_leave][:, :2] - [0.5, 0.1]).max() < 1e-9  # straight up


def test_lift_traverse_descend_drops_empty_moves_and_turns_on_the_way() -> None:
    start = pose([0.5, 0.1, 0.95])
    turned = mink.SE3.from_rotation_and_translation(
        mink.SO3.from_z_radians(0.5), np.array([0.6, 0, 0.95])
    )
    path = lift_traverse_descend(start, turned, clearance_z=0.95)
    assert len(path.segments) == 1
    assert rotation_angle(path.sample(path.duration / 2), start) == pytest.approx(0.25, abs=1e-6)
    stay = lift_traverse_descend(start, start, clearance_z=0.9)
    assert stay.duration > 0.0 and stay.end.translation() == pytest.approx([0.5, 0.1, 0.95])


def test_through_needs_two_waypoints() -> None:
    with pytest.raises(ValueError, match="two waypoints"):
        through([pose([0, 0, 0])])


@settings(max_examples=300, deadline=None)
@given(tau=st.floats(-1.0, 2.0) | st.floats(0.99999, 1.0))
@example(tau=0.99999495)
def test_min_jerk_stays_within_zero_and_one(tau: float) -> None:
    """Rounding must not carry the scaling past 1 (mink refuses an interpolation beyond it:
    a vision episode, seed 225712630, stopped there)."""
    assert 0.0 <= min_jerk(tau) <= 1.0


def test_a_turning_segment_samples_just_before_its_end() -> None:
    start = pose([0.4, 0.0, 1.0])
    end = pose([0.5, 0.1, 1.1], [np.cos(0.4), 0.0, 0.0, np.sin(0.4)])
    segment = Segment(start, end, 2.0)
    for tau in (0.99999495, 0.9999954, 0.99999555):  # min_jerk rounded past 1 here
        got = segment.sample(tau * 2.0)
        np.testing.assert_allclose(got.translation(), end.translation(), atol=1e-9)
