"""Joining a path from the robot's heading (`core.geometry.join`): the join's ends checked by
finite differences, the choice against turning in place, and a base with inertia that curves
onto a sine it does not face, measured from its poses against the drawn path (shapely)."""

import math

import numpy as np
import pytest
import shapely

from turtle_traj.core.geometry.join import hermite_join, joined_start
from turtle_traj.core.geometry.path import Path, Polyline, Turn


def _menger(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
    """Signed curvature of the circle through three points."""
    cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    sides = np.linalg.norm(b - a) * np.linalg.norm(c - b) * np.linalg.norm(c - a)
    return 2.0 * cross / sides


def _end_curvature(points: np.ndarray) -> float:
    """The curvature at points[0], extrapolated from the circles through the first three
    samples and through the third to the fifth (evenly spaced samples)."""
    near, far = _menger(*points[:3]), _menger(*points[2:5])
    return near + 0.5 * (near - far)


@pytest.mark.parametrize('heading, start_curvature, end_heading, end_curvature', [
    (0.0, 0.0, 0.8, 0.0), (0.0, 3.0, 0.8, -0.5), (1.0, -2.0, -0.5, 1.5)])
def test_a_join_leaves_along_the_heading_and_meets_the_path_as_it_runs(
        heading, start_curvature, end_heading, end_curvature):
    start, end = np.array([1.0, 2.0]), np.array([2.0, 2.6])
    join = hermite_join(start, heading, start_curvature, end, end_heading, end_curvature,
                        (1.0, 1.2))
    assert np.allclose(join[0], start) and np.allclose(join[-1], end)
    first, last = join[1] - join[0], join[-1] - join[-2]
    assert math.atan2(first[1], first[0]) == pytest.approx(heading, abs=0.01)
    assert math.atan2(last[1], last[0]) == pytest.approx(end_heading, abs=0.01)
    assert _end_curvature(join) == pytest.approx(start_curvature, abs=0.02)
    # backwards, the curve turns the other way
    assert -_end_curvature(join[::-1]) == pytest.approx(end_curvature, abs=0.02)


def _sine(heading: float) -> tuple[Path, np.ndarray]:
    """A sine leaving the origin at 26.6 degrees, from facing `heading`: a turn in place onto
    it, and the sine."""
    x = np.linspace(0.0, 4.0, 201)
    points = np.column_stack([x, 0.5 * np.sin(x)])
    along = math.atan(0.5)
    return Path(legs=(Turn(0.0, 0.0, heading, along - heading), Polyline(points))), points


def _by_length(polyline: Polyline) -> float:
    return polyline.length


def test_the_join_is_taken_only_where_it_beats_the_turn_and_keeps_within_the_tolerance():
    path, points = _sine(-0.5)
    drawn = Polyline(points)
    joined = joined_start(path, drawn, 0.2, _by_length, lambda turn: 10.0)
    assert len(joined.legs) == 1  # no turn in place
    curve = joined.legs[0].points
    assert np.allclose(curve[0], points[0]) and np.allclose(curve[-1], points[-1])
    first = curve[1] - curve[0]
    assert math.atan2(first[1], first[0]) == pytest.approx(-0.5, abs=0.05)  # off as it faced
    assert shapely.distance(shapely.LineString(points), shapely.points(curve)).max() <= 0.2

    def bending(polyline: Polyline) -> float:  # joins bend sharply at their start
        return polyline.length + float(np.abs(polyline.curvatures).max())

    assert joined_start(path, drawn, 0.2, bending, lambda turn: 0.0) is path


def test_a_path_that_begins_facing_the_robots_way_is_kept():
    turned, points = _sine(math.atan(0.5))
    assert joined_start(turned, Polyline(points), 0.05, _by_length,
                        lambda turn: 10.0) is turned
    steered = Path(legs=turned.legs[1:])  # no turn planned
    assert joined_start(steered, Polyline(points), 0.05, _by_length,
                        lambda turn: 10.0) is steered


def _driven(points: np.ndarray, heading: float, tolerance: float):
    """follow_path through `points` from facing `heading`, on the DWPP paper's base with its
    inertia: the plan, and its drive."""
    from turtle_traj.apps.score.courses import PAPER_LIMITS, follow_request
    from turtle_traj.apps.score.loop import drive
    from turtle_traj.core.geometry.path import Pose2D
    from turtle_traj.core.parameters.settings import settings_from_values
    from turtle_traj.core.parameters.table import DEFAULTS
    from turtle_traj.core.planning import planner
    from turtle_traj.sim.physics import Inertia

    settings = settings_from_values({**DEFAULTS, **PAPER_LIMITS, 'arena': 'none'})
    start = Pose2D(float(points[0, 0]), float(points[0, 1]), heading)
    plan = planner.plan('follow_path', follow_request(points, corner_tolerance=tolerance),
                        start, settings)
    limits = settings.control.limits
    record = drive(plan, start, settings, inertia=Inertia(limits.linear_accel,
                                                          limits.angular_accel))
    assert record.run.ending[0], record.run.ending
    deviation = shapely.distance(shapely.LineString(points), shapely.points(record.xy()))
    return plan, record.elapsed_s, float(deviation.max())


def test_a_base_curves_onto_a_sine_it_does_not_face_within_the_tolerance_and_sooner():
    """The DWPP paper's sine, left at 46 degrees to the robot's heading, at the reference's
    error: the robot drives off at once and curves onto it, within the tolerance, and saves
    most of the turn in place it made before (from rest to rest at the angular acceleration
    limit, 2 sqrt(turn / alpha)) against the same sine driven from facing it."""
    x = np.linspace(0.0, 6.0, 601)
    points = np.column_stack([2.0 + x, 5.0 + np.sin(2.0 * math.pi * x / 6.0)])
    tolerance = 0.104
    leg_heading = math.atan2(*(points[1] - points[0])[::-1])
    plan, across_s, across_m = _driven(points, 0.0, tolerance)
    assert not isinstance(plan.path.legs[0], Turn)
    _, facing_s, _ = _driven(points, leg_heading, tolerance)
    turn_s = 2.0 * math.sqrt(leg_heading / 1.0)  # the paper's 1 rad/s² (PAPER_LIMITS)
    assert across_m <= tolerance
    assert across_s < facing_s + turn_s - 1.0


def test_a_base_turns_part_of_the_way_first_where_curving_all_of_it_would_leave_the_tube():
    """A line at 45 degrees to the robot's heading within 5 cm: at the curvature the speed
    profile can time (join.MAX_CURVATURE), a curve through the whole turn leaves the tube, so
    the robot turns half of it in place and curves through the rest, within the tolerance,
    sooner than turning all of it first (the line driven from facing it, plus that turn from
    rest to rest at 1 rad/s²)."""
    points = np.array([[2.0, 5.0], [5.0, 8.0]])
    plan, across_s, deviation = _driven(points, 0.0, 0.05)
    first = plan.path.legs[0]
    assert isinstance(first, Turn) and first.sweep_rad == pytest.approx(math.pi / 8)
    assert deviation <= 0.05
    _, facing_s, _ = _driven(points, math.pi / 4, 0.05)
    assert across_s < facing_s + 2.0 * math.sqrt(math.pi / 4)
