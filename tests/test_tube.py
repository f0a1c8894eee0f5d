"""The corner tolerance spent in a tube: each stretch of a path becomes the fastest of its
corner rounding and its smoothings within the tube, judged by the controller's least time and
checked here against independent geometry (brute-force distances, the polygon's own sides)."""

import math

import numpy as np
import pytest

from turtle_traj.core.control.duration import least_time_s
from turtle_traj.core.geometry import corners, tube
from turtle_traj.core.geometry.path import Path, Polyline, Pose2D
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner
from turtle_traj.testing.geometry import distance_to_polyline


def _hexagon(side: float) -> np.ndarray:
    angles = np.radians(np.arange(0, 361, 60))
    corners_xy = np.stack([np.cos(angles), np.sin(angles)], axis=1) * side + 5.0
    return corners_xy


def test_a_tube_smoothing_keeps_within_the_tube_and_passes_along_all_of_the_path():
    """A hexagon smoothed in a 0.15 m tube by each window: every curve offered keeps within
    the width (brute force), keeps the ends, passes the hexagon's corners no farther than the
    tube's edge lets a cut reach (width / sin 60 degrees, the inner angle's half) and is
    sampled evenly; the narrow windows offer one (the wide ones, whose passes draw the points
    apart at the corners, are refused by the check)."""
    points = _hexagon(1.0)
    width = 0.15
    offered = [curve for window in tube.WINDOWS_M
               if (curve := tube.tube_smoothed(points, width, window)) is not None]
    assert len(offered) >= 3
    for curve in offered:
        assert distance_to_polyline(curve, points).max() <= width
        assert np.allclose(curve[[0, -1]], points[[0, -1]])
        assert distance_to_polyline(points[1:-1], curve).max() <= \
            width / math.sin(math.radians(60))
        spacing = np.hypot(*np.diff(curve, axis=0).T)  # even: no gap the chords could cut across
        assert spacing.min() > 0.99 * spacing.max() and spacing.max() < 1.01 * tube.SPACING_M
        assert distance_to_polyline(points[1:-1], curve).max() > width  # the corners are cut


def test_a_small_loop_is_not_smoothed_away():
    """A loop of 0.3 m across in a 0.2 m tube could shrink to a dot within the tube: no
    smoothing that leaves the loop undrawn is offered."""
    angles = np.linspace(0.0, 2.0 * math.pi, 64)
    loop = np.stack([5.0 + 0.15 * np.cos(angles), 5.0 + 0.15 * np.sin(angles)], axis=1)
    for window in tube.WINDOWS_M:
        curve = tube.tube_smoothed(loop, 0.2, window)
        assert curve is None or distance_to_polyline(loop, curve).max() <= 0.4


@pytest.mark.parametrize('tolerance', [0.02, 0.1, 0.2])
def test_a_polygon_with_a_tolerance_is_no_slower_than_its_rounded_corners_and_within_it(
        tolerance):
    """The hexagon's plan at a tolerance: within it of the sides (brute force), and no slower
    by the controller's least time than its clothoid corners alone (`rounded_path` without a
    duration); at 0.2 m the tube cuts the corners deeper than half a side lets a corner reach,
    so it is faster."""
    from types import SimpleNamespace

    settings = DEFAULT_SETTINGS
    request = SimpleNamespace(sides=6, size=2.0, clockwise=False, linear_speed=0.0,
                              angular_speed=0.0, corner_tolerance=tolerance)
    start = Pose2D(3.0, 3.0, 0.0)
    plan = planner.plan('polygon', request, start, settings)
    exact = planner.plan('polygon', SimpleNamespace(**{**vars(request), 'corner_tolerance': 0.0}),
                         start, settings)
    config = plan.control(settings.control)
    clothoids = corners.rounded_path(exact.path, tolerance)
    assert distance_to_polyline(plan.path.points(), exact.path.points()).max() <= tolerance
    assert least_time_s(plan.path, config) <= least_time_s(clothoids, config)
    if tolerance == 0.2:
        assert least_time_s(plan.path, config) < 0.99 * least_time_s(clothoids, config)


def test_a_circle_is_kept_as_it_is_where_smoothing_would_slow_it():
    """Smoothing a circle shrinks it, and a smaller circle is slower: given how long a base
    takes, the curve stays as it is."""
    angles = np.linspace(0.0, 2.0 * math.pi, 400)
    circle = np.stack([5.0 + np.cos(angles), 5.0 + np.sin(angles)], axis=1)
    path = Path(legs=(Polyline(circle),))
    config = DEFAULT_SETTINGS.control
    rounded = corners.rounded_path(path, 0.05, duration=lambda leg: least_time_s(
        Path(legs=(leg,)), config))
    assert least_time_s(rounded, config) <= least_time_s(path, config)
