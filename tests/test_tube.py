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
    the width (brute force), keeps the ends, passes all of the hexagon within twice the width
    (a corner cut to the tube's edge: width / sin 60 degrees, the inner angle's half, on its
    bisector) and is sampled evenly (chords across a bend are a little shorter). The narrow
    windows offer one, the widest of them cutting every corner beyond the width; the wide
    ones, whose passes draw the points apart at the corners, are refused by the check."""
    points = _hexagon(1.0)
    width = 0.15
    offered = [curve for window in tube.WINDOWS_M
               if (curve := tube.tube_smoothed(points, width, window)) is not None]
    assert len(offered) >= 3
    # the widest window offered cuts the corners beyond the width: to the tube's edge
    assert distance_to_polyline(points[1:-1], offered[-1]).min() > width
    for curve in offered:
        assert distance_to_polyline(curve, points).max() <= width
        assert np.allclose(curve[[0, -1]], points[[0, -1]])
        assert distance_to_polyline(points, curve).max() <= 2.0 * width
        spacing = np.hypot(*np.diff(curve, axis=0).T)  # even: no gap the chords could cut across
        assert spacing.min() > 0.95 * spacing.max() and spacing.max() < 1.01 * tube.SPACING_M


def test_a_letter_o_is_not_smoothed_away():
    """The "O" of "Hello ROS" as the text is planned (16 segments, 0.6 m across) in a 0.2 m
    tube: wide windows draw it in to a dot near its start, every point of which is within the
    tube. No smoothing offered leaves the letter undrawn: each passes all of it within twice
    the width, and the narrow windows still offer one."""
    letter = np.array([[4.548, 5.667], [4.452, 5.619], [4.357, 5.524], [4.31, 5.381],
                       [4.31, 5.286], [4.357, 5.143], [4.452, 5.048], [4.548, 5.0], [4.69, 5.0],
                       [4.786, 5.048], [4.881, 5.143], [4.929, 5.286], [4.929, 5.381],
                       [4.881, 5.524], [4.786, 5.619], [4.69, 5.667], [4.548, 5.667]])
    width = 0.2
    offered = [curve for window in tube.WINDOWS_M
               if (curve := tube.tube_smoothed(letter, width, window)) is not None]
    assert 1 <= len(offered) < len(tube.WINDOWS_M)
    for curve in offered:
        assert distance_to_polyline(letter, curve).max() <= 2.0 * width
        assert Polyline(curve).length > 1.0  # the letter is 2.04 m around


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
    """On a base with acceleration limits (the DWPP paper's), a circle of 0.5 m smoothed within
    0.2 mm takes far longer by its time-optimal profile than the circle itself (the smoothing
    leaves ripples of curvature the profile must slow for): given how long a base takes, the
    plan keeps the circle, no slower than it."""
    from turtle_traj.apps.score.courses import PAPER_LIMITS
    from turtle_traj.core.control.profile import profile_for
    from turtle_traj.core.parameters.settings import settings_from_values
    from turtle_traj.core.parameters.table import DEFAULTS

    config = settings_from_values({**DEFAULTS, **PAPER_LIMITS, 'arena': 'none'}).control

    def duration(leg: Polyline) -> float:
        return least_time_s(Path(legs=(leg,)), config, (profile_for(leg, config.limits),))

    angles = np.linspace(0.0, 2.0 * math.pi, 400)
    circle = Polyline(np.stack([5.0 + 0.5 * np.cos(angles), 5.0 + 0.5 * np.sin(angles)], axis=1))
    tolerance = 0.0002
    rounded = corners.rounded_path(Path(legs=(circle,)), tolerance, duration=duration)
    smoothed = Polyline(corners.smoothed_curve(circle.points, tolerance))
    assert duration(smoothed) > 1.5 * duration(circle)
    assert least_time_s(rounded, config, tuple(profile_for(leg, config.limits)
                                               for leg in rounded.legs)) <= duration(circle)
