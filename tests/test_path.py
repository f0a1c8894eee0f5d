"""Paths from polylines: where the turtle turns in place, and what a path adds up to."""

import math

import numpy as np
import pytest

from turtle_traj.core.geometry.path import Path, Polyline, Pose2D, Turn, legs_from_polyline

CORNER = 0.35  # rad


@pytest.mark.parametrize(('theta', 'points', 'kinds', 'sweeps'), [
    # already facing along the line: one curve, no turn
    (0.0, [(0, 0), (1, 0), (2, 0)], 'C', []),
    # facing away: turn first (shortest way, here +90 deg), then drive
    (0.0, [(0, 0), (0, 1)], 'TC', [math.pi / 2]),
    # a square corner in the middle splits the line
    (0.0, [(0, 0), (1, 0), (1, -1)], 'CTC', [-math.pi / 2]),
    # a gentle bend between short segments samples a curve: one curve
    (0.0, [(0, 0), (0.01, 0), (0.02, 0.002)], 'C', []),
    # the same bend between long ones is a corner (its curve would pass 25 mm inside)
    (0.0, [(0, 0), (1, 0), (2, 0.2)], 'CTC', [math.atan2(0.2, 1.0)]),
    # so is a start facing a long segment a little off (the curve onto it: 10 mm)
    (0.1, [(0, 0), (2, 0)], 'TC', [-0.1]),
    # but not one off by a hair
    (1e-4, [(0, 0), (2, 0)], 'C', []),
    # repeated points are dropped, not turned at
    (0.0, [(0, 0), (1, 0), (1, 0), (2, 0)], 'C', []),
])
def test_turns_in_place_only_at_sharp_corners(theta, points, kinds, sweeps):
    legs = legs_from_polyline(Pose2D(0.0, 0.0, theta), np.array(points, dtype=float),
                              corner_angle_rad=CORNER)
    assert ''.join('T' if isinstance(leg, Turn) else 'C' for leg in legs) == kinds
    assert [leg.sweep_rad for leg in legs if isinstance(leg, Turn)] == pytest.approx(sweeps)


def test_a_paths_length_turning_and_bound_add_up():
    legs = legs_from_polyline(Pose2D(0.0, 0.0, 0.0), np.array([(0, 0), (3, 0), (3, 4)], float),
                              corner_angle_rad=CORNER)
    path = Path(tuple(legs))
    assert path.length == pytest.approx(7.0)
    assert path.turning == pytest.approx(math.pi / 2)
    assert path.end == (3.0, 4.0)
    assert path.lower_bound_s(2.0, 0.5) == pytest.approx(3.5 + math.pi)
    assert len(path.points()) == 2 + 1 + 2  # two curves of two points, one turn point


def test_a_curve_knows_its_length_and_curvature():
    angles = np.linspace(0.0, math.pi, 200)
    arc = Polyline(np.column_stack((np.cos(angles), np.sin(angles))))
    assert arc.length == pytest.approx(math.pi, rel=1e-4)
    assert np.median(arc.curvatures) == pytest.approx(1.0, rel=1e-3)


def test_a_sampled_arc_turns_as_an_arc_up_to_its_ends():
    """The curve's curvature (`tangent_curvatures`) carries the arc's on to its end chords; a
    chord's view (`curvatures`) counts the end vertices as straight, and gives them half."""
    radius = 0.5
    angles = np.linspace(0.0, math.pi / 2, 40)
    arc = Polyline(radius * np.column_stack((np.sin(angles), 1.0 - np.cos(angles))))
    chord = 2 * radius * math.sin((angles[1] - angles[0]) / 2)  # each vertex turns by one step
    expected = (angles[1] - angles[0]) / chord
    assert arc.tangent_curvatures == pytest.approx(np.full(39, expected), rel=1e-9)
    assert arc.curvatures[[0, -1]] == pytest.approx([expected / 2, expected / 2], rel=1e-9)
    assert arc.curvatures[1:-1] == pytest.approx(arc.tangent_curvatures[1:-1], rel=1e-12)
    straight = Polyline(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]))
    assert straight.tangent_curvatures.tolist() == [0.0, 0.0]
    assert Polyline(np.array([[0.0, 0.0], [1.0, 0.0]])).tangent_curvatures.tolist() == [0.0]


@pytest.mark.parametrize('seed', range(5))
def test_nearest_on_polyline_agrees_with_the_brute_force_distance(seed):
    """Blocks pruned by their boxes never hide the nearest segment (independent check)."""
    from turtle_traj.core.geometry.projection import NearestOnPolyline
    from turtle_traj.testing.geometry import distance_to_polyline

    rng = np.random.default_rng(seed)
    # a long wandering polyline (many blocks), a short one (one block), a single point
    for vertices in (np.cumsum(rng.normal(0.0, 0.05, (3000, 2)), axis=0) + 5.0,
                     rng.uniform(0.0, 11.0, (7, 2)), rng.uniform(0.0, 11.0, (1, 2))):
        nearest = NearestOnPolyline(vertices)
        points = rng.uniform(-1.0, 12.0, (200, 2))
        drawn = vertices if len(vertices) > 1 else np.repeat(vertices, 2, axis=0)
        expected = distance_to_polyline(points, drawn)
        measured = [nearest.distance(x, y) for x, y in points]
        assert np.allclose(measured, expected, rtol=0.0, atol=1e-12)
        assert np.allclose(nearest.distances(points), expected, rtol=0.0, atol=1e-12)


@pytest.mark.parametrize('seed', range(4))
def test_a_smoothed_curve_keeps_to_its_tolerance_by_the_brute_force_distance(seed):
    """On curves that wander back near themselves, the smoothing search's check passes a curve
    only where the brute-force distance to the whole polyline is within the limit too (it is
    stricter: near the part each point came from), and the curve it returns keeps its ends and
    its tolerance."""
    from turtle_traj.core.geometry import corners, tube
    from turtle_traj.core.geometry.projection import WithinDistance
    from turtle_traj.testing.geometry import distance_to_polyline

    rng = np.random.default_rng(seed)
    points = np.cumsum(rng.normal(0.0, 0.02, (500, 2)), axis=0) + 5.0
    polyline = Polyline(points)
    arc = np.linspace(0.0, polyline.length, int(polyline.length / 0.01) + 1)
    samples = np.stack([np.interp(arc, polyline.cumulative_length, points[:, axis])
                        for axis in (0, 1)], axis=1)
    within = WithinDistance(points, polyline.cumulative_length, arc)
    decisions = set()
    for sigma in (1.0, 5.0, 20.0, 80.0):
        candidate = tube.gaussian_smoothed(samples, sigma)
        distances = distance_to_polyline(candidate, points)
        for limit in [*np.quantile(distances, [0.5, 0.99, 1.0]), 3.0 * distances.max()]:
            decision = within(candidate, float(limit))
            decisions.add(decision)
            assert not decision or distances.max() <= limit, (sigma, limit)
    assert decisions == {True, False}
    for tolerance in (0.005, 0.05):
        smooth = corners.smoothed_curve(points, tolerance)
        assert distance_to_polyline(smooth, points).max() <= tolerance
        assert np.array_equal(smooth[[0, -1]], points[[0, -1]])


def test_smoothing_a_rose_keeps_its_petals():
    """A rose's petals all pass through its centre: smoothed within a tolerance far shorter than
    a petal, the curve still reaches every petal's tip (the rose lies within twice the tolerance
    of it; a rose shrunk into its centre would leave its 2 m petals out)."""
    from turtle_traj.core.geometry import corners
    from turtle_traj.testing.geometry import distance_to_polyline

    angle = np.linspace(0.0, 2.0 * np.pi, 2001)
    radius = 2.0 * np.cos(3.0 * angle)  # three petals 2 m long
    rose = np.stack([5.0 + radius * np.cos(angle), 5.0 + radius * np.sin(angle)], axis=1)
    for tolerance in (0.1, 0.3):
        smooth = corners.smoothed_curve(rose, tolerance)
        assert distance_to_polyline(smooth, rose).max() <= tolerance
        assert distance_to_polyline(rose, smooth).max() <= 2.0 * tolerance


def test_a_sampled_curve_stays_one_curve_and_a_lone_gentle_bend_is_turned():
    """A circle and a sine sampled every 2 cm bend a little at every vertex, each like its
    neighbours: they are curves. The same little bend alone between 0.2 m segments is a
    corner, turned in place."""
    angles = np.linspace(0.0, 2.0 * math.pi, 158)
    circle = np.column_stack((0.5 * np.sin(angles), 0.5 - 0.5 * np.cos(angles)))
    x = np.arange(0.0, 2.0, 0.02)
    sine = np.column_stack((x, 0.3 * np.sin(2.0 * math.pi * x)))
    heading = math.atan2(*(sine[1] - sine[0])[::-1])
    for points, theta in ((circle, 0.0), (sine, heading)):
        legs = legs_from_polyline(Pose2D(0.0, 0.0, theta), points, corner_angle_rad=CORNER)
        assert [type(leg) for leg in legs] == [Polyline]
    bend = float(np.abs(np.diff(np.unwrap(np.arctan2(*np.diff(circle, axis=0).T[::-1])))).max())
    lone = np.array([(0.0, 0.0), (0.2, 0.0), (0.2 + 0.2 * math.cos(bend), 0.2 * math.sin(bend))])
    legs = legs_from_polyline(Pose2D(0.0, 0.0, 0.0), lone, corner_angle_rad=CORNER)
    assert [type(leg) for leg in legs] == [Polyline, Turn, Polyline]


def test_an_exact_path_with_gentle_corners_is_driven_on_its_lines():
    """Two 2 m sides meeting at 0.2 rad, from a start 0.2 rad off the first: steered through
    under the corner angle, the turtle was 13-16 mm off the lines; turned in place, it keeps
    to them within a millimetre (measured with shapely from the poses)."""
    import shapely

    from turtle_traj.apps.score.courses import follow_request
    from turtle_traj.apps.score.loop import drive
    from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
    from turtle_traj.core.planning import planner

    points = np.array([(2.0, 5.0), (4.0, 5.0),
                       (4.0 + 2.0 * math.cos(0.2), 5.0 + 2.0 * math.sin(0.2))])
    start = Pose2D(2.0, 5.0, -0.2)
    plan = planner.plan('follow_path', follow_request(points), start, DEFAULT_SETTINGS)
    record = drive(plan, start, DEFAULT_SETTINGS)
    assert record.run.ending[0], record.run.ending
    lines = shapely.LineString(points)
    assert shapely.distance(lines, shapely.points(record.xy())).max() < 1e-3
