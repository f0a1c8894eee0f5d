"""`turtle-traj score`'s fairness: its planner course is a grid planner's path (5 cm cells,
45-degree staircases, clear of the walls), and a run counts as finished only when it ends within
the goal tolerance of the path's end."""

import copy
import math
from dataclasses import replace

import numpy as np
import pytest

from turtle_traj.apps.score.courses import planner_path, standard_courses
from turtle_traj.apps.score.report import ranking
from turtle_traj.apps.score.runner import GOAL_TOLERANCE_M, run_course


class GivesUp:
    """A controller that declares every stroke done at once: the robot never moves."""

    def start(self, stroke, limits) -> None:
        pass

    def command(self, state):
        return None


def test_the_planner_course_is_a_grid_staircase_clear_of_the_walls():
    points = planner_path()
    steps = np.diff(points, axis=0)
    lengths = np.hypot(*steps.T)
    assert np.allclose(np.sort(np.unique(lengths.round(9))), [0.05, 0.05 * math.sqrt(2)])
    headings = np.degrees(np.arctan2(steps[:, 1], steps[:, 0]))
    assert np.allclose(headings / 45.0, np.round(headings / 45.0))  # multiples of 45 degrees
    assert np.count_nonzero(np.abs(np.diff(headings)) > 1.0) >= 50  # a staircase: many steps
    inside_walls = [(3.5 <= x <= 4.5 and y <= 7.0) or (6.5 <= x <= 7.5 and y >= 4.0)
                    for x, y in points]
    assert not any(inside_walls)
    assert math.dist(points[0], (1.5, 1.5)) < 0.04 and math.dist(points[-1], (9.5, 9.2)) < 0.04
    # the shortest path of the 8-connected grid: no longer than the straight line by more
    # than the detours around the walls' ends allow
    assert 13.0 < lengths.sum() < 19.0


@pytest.mark.parametrize('name', ['move', 'square', 'triangle', 'circle'])
def test_a_controller_that_gives_up_at_once_does_not_finish(tmp_path, name):
    """Closed strokes too: there the robot stands at the path's end as it starts."""
    course = next(c for c in standard_courses(('turtlesim',)) if c.name == name)
    result = run_course(course, f'{__name__}:GivesUp', work_dir=tmp_path)
    assert not result.success and 'claimed the end after 0.00 m of' in result.message
    exact = run_course(course, 'exact', work_dir=tmp_path)
    assert exact.success and exact.end_mm < 1e3 * GOAL_TOLERANCE_M
    ranked = ranking([result, exact])
    assert [row.controller for row in ranked] == ['exact', f'{__name__}:GivesUp']


def test_the_exact_follower_is_matched_at_a_rival_s_error_measured_on_the_drawn_path(tmp_path):
    from turtle_traj.apps.score.matched import matched_runs
    from turtle_traj.testing.geometry import distance_to_polyline

    courses = {c.name: c for c in standard_courses(('turtlesim',))}
    square = courses['square']
    results = [run_course(square, name, work_dir=tmp_path) for name in ('exact', 'dwpp')]
    [matched] = matched_runs(square, results, tmp_path)
    rival = results[1]
    assert matched.rival is rival and matched.tolerance_m == rival.max_mm / 1e3
    assert matched.exact.controller == 'exact @ dwpp'
    # its error is measured against the square as drawn (not its rounded plan): independently
    drawn = results[0].plan
    assert matched.exact.max_mm == pytest.approx(
        1e3 * distance_to_polyline(matched.exact.path, drawn).max(), abs=1e-6)
    assert 0.0 < matched.exact.max_mm <= 1e3 * matched.tolerance_m
    assert matched.ahead == (matched.exact.time_s <= rival.time_s)
    assert matched.limit_s is None  # a polygon gives no points: no limit computed
    # a request that takes no tolerance is not matched
    go_to = courses['go_to']
    assert not hasattr(go_to.request, 'corner_tolerance')
    assert matched_runs(go_to, [run_course(go_to, name, work_dir=tmp_path)
                                for name in ('exact', 'dwpp')], tmp_path) == []


@pytest.mark.parametrize('tolerance', [0.02, 0.07])
def test_a_heart_rounded_within_a_tolerance_is_driven_within_it(tmp_path, tolerance):
    """The heart's top is a cusp whose sides curve apart: turned short of it, the robot turns
    again where the way across meets the far side (it had steered through that bend at speed,
    80 mm off at a 20 mm tolerance)."""
    from turtle_traj.testing.geometry import distance_to_polyline

    course = next(c for c in standard_courses(('turtlesim',)) if c.name == 'heart')
    drawn = run_course(course, 'exact', work_dir=tmp_path).plan
    request = copy.copy(course.request)
    request.corner_tolerance = tolerance
    rounded = run_course(replace(course, request=request), 'exact', work_dir=tmp_path)
    assert rounded.success
    assert distance_to_polyline(rounded.path, drawn).max() <= tolerance


def test_the_limit_beside_a_matched_run_is_no_slower_than_the_run(tmp_path):
    """The minimum-time limit of a path given as points bounds the exact follower's time at
    the same tolerance from below, and the shortest way through the tube bounds it."""
    from turtle_traj.apps.score.courses import Course, follow_request
    from turtle_traj.apps.score.matched import limit_s
    from turtle_traj.core.geometry.path import Pose2D

    tolerance = 0.05
    points = np.array([[2.0, 2.0], [4.0, 2.0], [4.0, 4.0]])
    request = follow_request(points, corner_tolerance=tolerance)
    course = Course('corner', 'turtlesim', 'follow_path', request, Pose2D(2.0, 2.0, 0.0))
    limit = limit_s(course, tolerance)
    ours = run_course(course, 'exact', work_dir=tmp_path)
    assert ours.success
    control = course.settings.control
    shortest = 2.0 * math.hypot(2.0 - tolerance, tolerance) / control.linear_speed
    assert shortest < limit <= ours.time_s


def test_the_limit_of_a_closed_path_drives_it_from_the_start_round_the_loop():
    """The score's follow_path course starts away from its first point and is closed (back to
    that point): its limit at tolerance zero on turtlesim is the whole of that, each leg at
    the top speed (lengths by shapely) and each corner turned in place at the top turn rate,
    not the points given alone."""
    import shapely

    from turtle_traj.apps.score.matched import limit_s

    course = next(c for c in standard_courses(('turtlesim',)) if c.name == 'follow_path')
    given = [(point.x, point.y) for point in course.request.points]
    loop = np.array([(course.start.x, course.start.y), *given, given[0]])
    legs = np.diff(loop, axis=0)
    headings = np.arctan2(legs[:, 1], legs[:, 0])
    turns = np.abs(np.remainder(np.diff(np.concatenate(([course.start.theta], headings)))
                                + math.pi, 2.0 * math.pi) - math.pi)
    control = course.settings.control
    expected = (shapely.LineString(loop).length / control.linear_speed
                + turns.sum() / control.angular_speed)
    assert limit_s(course, 0.0) == pytest.approx(expected, rel=1e-6)


def test_a_staircase_given_with_a_corner_tolerance_is_driven_along_its_diagonals():
    """A path given as points is simplified within a share of its corner tolerance before its
    corners are rounded: the grid planner's staircase loses its steps, the plan keeps within the
    tolerance of the points given, is measured against them, and is driven within it in well
    under half the time of the exact staircase."""
    from turtle_traj.apps.score.courses import follow_request
    from turtle_traj.apps.score.loop import drive
    from turtle_traj.core.geometry.path import Pose2D
    from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
    from turtle_traj.core.planning import planner
    from turtle_traj.testing.geometry import distance_to_polyline

    points = planner_path()
    start = Pose2D(float(points[0, 0]), float(points[0, 1]), math.pi / 4)
    plans = {}
    for tolerance in (0.0, 0.2):
        request = follow_request(points)
        request.corner_tolerance = tolerance
        plans[tolerance] = planner.plan('follow_path', request, start, DEFAULT_SETTINGS)
    exact, rounded = plans[0.0], plans[0.2]
    assert distance_to_polyline(rounded.path.points(), points).max() <= 0.2
    assert np.allclose(rounded.drawn_points(), exact.path.points())  # measured against the given
    assert len(rounded.path.legs) < len(exact.path.legs) / 10  # the steps are gone
    record = drive(rounded, start, DEFAULT_SETTINGS)
    assert record.run.ending[0]
    assert distance_to_polyline(record.xy(), points).max() <= 0.2
    assert record.run.outcome(record.poses[-1], record.elapsed_s).elapsed_s < 0.5 * \
        exact.least_time_s(DEFAULT_SETTINGS.control)


def test_the_matched_table_is_printed_only_when_asked(capsys):
    from turtle_traj.apps.score.main import run

    assert run(['exact', 'dwpp'], None, ['square']) == 0
    assert 'at equal error' not in capsys.readouterr().out
    assert run(['exact', 'dwpp'], None, ['square'], matched=True) == 0
    printed = capsys.readouterr().out
    assert 'square             dwpp' in printed
    assert 'the exact follower is ahead at equal error in 1 of 1' in printed


def test_on_a_base_with_inertia_the_matched_run_is_also_planned_by_the_limit(tmp_path,
                                                                            monkeypatch):
    """A sharp corner (135 degrees) on the DWPP paper's base, at a rival's 100 mm: planned by
    the minimum-time limit, the exact follower keeps within the rival's error, takes no less
    than the limit and less than the tube's plan, and the table prints both against it. (The
    limit at 30 nodes, as the planner solves a path this long: cutting across the tube
    between them, it is no slower than at more, and it takes a sixth of the CPU.)"""
    from turtle_traj.apps.score import matched as score_matched
    from turtle_traj.apps.score.courses import PAPER_LIMITS, Course, follow_request
    from turtle_traj.apps.score.matched import format_matched, matched_runs
    from turtle_traj.core.geometry.path import Pose2D
    from turtle_traj.core.parameters.settings import settings_from_values
    from turtle_traj.core.parameters.table import DEFAULTS
    from turtle_traj.testing.geometry import distance_to_polyline

    monkeypatch.setattr(score_matched, 'LIMIT_NODES', 30)
    monkeypatch.setattr(score_matched, 'LIMIT_MOST_NODES', 30)
    settings = settings_from_values({**DEFAULTS, **PAPER_LIMITS, 'arena': 'none'})
    turn = math.radians(135.0)
    points = np.array([(1.0, 1.5), (2.0, 1.5), (2.0 + math.cos(turn), 1.5 + math.sin(turn))])
    course = Course('sharp corner', 'inertia', 'follow_path', follow_request(points),
                    Pose2D(1.0, 1.5, 0.0), settings)
    exact = run_course(course, 'exact', work_dir=tmp_path)
    rival = replace(exact, controller='rival', max_mm=100.0, time_s=exact.time_s + 5.0)
    [matched] = matched_runs(course, [exact, rival], tmp_path)
    by_limit = matched.by_limit
    assert by_limit.success and by_limit.controller == 'exact'
    assert 1e3 * distance_to_polyline(by_limit.path, points).max() <= rival.max_mm
    assert matched.limit_s <= by_limit.time_s < matched.exact.time_s
    row = format_matched([matched]).splitlines()[1].split()
    assert row[-3:] == [f'{by_limit.time_s:.2f}', f'{by_limit.max_mm:.2f}',
                        f'{by_limit.time_s / matched.limit_s:.3f}']
