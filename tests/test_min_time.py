"""The minimum-time limit against what physics says of simple paths: a straight line's
trapezoid, a circle at the turn rate's speed, and a corner between turning in place and driving
straight through. The distances are measured independently of the solver (shapely)."""

import math

import numpy as np
import pytest
import shapely

from turtle_traj.core.control.config import Limits
from turtle_traj.core.planning.min_time import EXACT_M, minimum_time
from turtle_traj.core.turtlesim_contract import STEP_S

PAPER = Limits(linear_speed=0.5, angular_speed=1.0, linear_accel=0.5, angular_accel=1.0,
               period_s=STEP_S)
TURTLESIM = Limits(linear_speed=2.0, angular_speed=1.0, linear_accel=0.0, angular_accel=0.0,
                   period_s=STEP_S)


def _trapezoid_s(distance: float, top: float, accel: float) -> float:
    if distance * accel < top * top:
        return 2.0 * math.sqrt(distance / accel)
    return distance / top + top / accel


def _within(limit, points, tolerance_m):
    path = shapely.LineString(points)
    nodes = shapely.distance(path, shapely.points(limit.poses[:, :2]))
    assert nodes.max() <= tolerance_m + 1e-6
    # between nodes, integrated finely: a chord across the tube's inner corner leaves it a little
    assert limit.max_error_m <= tolerance_m * 1.1


def test_a_straight_line_with_inertia_takes_its_trapezoid():
    points = np.array([[0.0, 0.0], [3.0, 0.0]])
    limit = minimum_time(points, 0.01, PAPER, nodes=40)
    assert limit.solved
    assert limit.time_s == pytest.approx(_trapezoid_s(3.0, 0.5, 0.5), rel=0.01)
    assert np.all(limit.velocities[:, 0] <= 0.5 + 1e-6)
    assert limit.velocities[0] == pytest.approx([0.0, 0.0], abs=1e-6)
    assert limit.velocities[-1] == pytest.approx([0.0, 0.0], abs=1e-6)
    _within(limit, points, 0.01)


def test_a_circle_on_turtlesim_goes_at_the_speed_its_turn_rate_allows():
    radius = 0.5  # at 1 rad/s: 0.5 m/s, below the top speed
    angles = np.linspace(0.0, 2.0 * math.pi, 181)
    points = np.column_stack([radius * np.sin(angles), radius * (1.0 - np.cos(angles))])
    limit = minimum_time(points, 0.0, TURTLESIM)
    assert limit.solved
    # one lap at v = omega * r, of 2 pi r: 2 pi / omega
    assert limit.time_s == pytest.approx(2.0 * math.pi / TURTLESIM.angular_speed, rel=0.005)
    assert np.all(np.abs(limit.velocities[:, 1]) <= TURTLESIM.angular_speed + 1e-9)
    _within(limit, points, EXACT_M)


def test_a_square_on_turtlesim_at_tolerance_zero_stops_and_turns_at_each_corner():
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]])
    limit = minimum_time(points, 0.0, TURTLESIM, start_heading=math.pi / 2)
    # a quarter turn to face the first side, then four sides and three quarter turns
    expected = 4.0 / TURTLESIM.linear_speed + 4 * (math.pi / 2) / TURTLESIM.angular_speed
    assert limit.time_s == pytest.approx(expected, rel=1e-3)
    _within(limit, points, EXACT_M)


CORNER = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
CORNER_TOLERANCES_M = (0.05, 0.2)


@pytest.fixture(scope='module')
def corner_limits():
    """The limit through a right-angled corner of two 1 m legs, at each tolerance."""
    return {tolerance: minimum_time(CORNER, tolerance, PAPER, nodes=30)
            for tolerance in CORNER_TOLERANCES_M}


@pytest.mark.parametrize('tolerance_m', CORNER_TOLERANCES_M)
def test_a_corner_is_faster_than_stopping_and_slower_than_its_shortest_way(corner_limits,
                                                                           tolerance_m):
    limit = corner_limits[tolerance_m]
    assert limit.solved
    stop_and_turn = 2 * _trapezoid_s(1.0, 0.5, 0.5) + _trapezoid_s(math.pi / 2, 1.0, 1.0)
    # the shortest way through the tube: by its inner corner, at the top speed throughout
    shortest = 2.0 * math.hypot(1.0 - tolerance_m, tolerance_m)
    assert _trapezoid_s(shortest, 0.5, 0.5) < limit.time_s < stop_and_turn
    _within(limit, CORNER, tolerance_m)


def test_a_wider_tube_is_never_slower(corner_limits):
    narrow, wide = (corner_limits[tolerance].time_s for tolerance in CORNER_TOLERANCES_M)
    assert wide < narrow


def test_a_base_planning_corners_by_minimum_time_is_no_slower_than_by_the_tube(corner_limits):
    """With `corner_planning` 'minimum_time', a right-angled corner's plan on the DWPP paper's
    base keeps within the tolerance of the points given (shapely), takes no longer by the
    controller's least time than the tube's plan, and no less than the limit itself. That plan
    is the limit's motion with its timing, which the base drives within 2% of its time and
    within the tolerance."""
    from turtle_traj.apps.score.courses import PAPER_LIMITS, follow_request
    from turtle_traj.apps.score.loop import drive
    from turtle_traj.core.geometry.path import Pose2D
    from turtle_traj.core.parameters.settings import settings_from_values
    from turtle_traj.core.parameters.table import DEFAULTS
    from turtle_traj.core.planning import planner
    from turtle_traj.sim.physics import Inertia

    tolerance, points = CORNER_TOLERANCES_M[0], CORNER + 1.0  # off the simulator's walls
    start = Pose2D(1.0, 1.0, 0.0)
    plans = {}
    for way in ('tube', 'minimum_time'):
        settings = settings_from_values({**DEFAULTS, **PAPER_LIMITS, 'arena': 'none',
                                         'corner_planning': way})
        request = follow_request(points, corner_tolerance=tolerance)
        plan = planner.plan('follow_path', request, start, settings)
        plans[way] = plan.least_time_s(settings.control)
        drawn = shapely.LineString(points)
        assert shapely.distance(drawn, shapely.points(plan.path.points())).max() <= tolerance
    assert corner_limits[tolerance].time_s <= plans['minimum_time'] <= plans['tube']
    timed = [profile for profile in plan.profiles if profile is not None]
    assert len(timed) == 1 and timed[0].times is not None
    run = drive(plan, start, settings, inertia=Inertia(PAPER.linear_accel, PAPER.angular_accel))
    assert run.run.ending[0], run.run.ending
    assert run.elapsed_s <= 1.02 * plans['minimum_time']
    assert shapely.distance(drawn, shapely.points(run.xy())).max() <= tolerance
    # commands that act a period late, one in five: still within the tolerance, and done
    late = drive(plan, start, settings, late_if=lambda step, _: step % 5 == 4,
                 inertia=Inertia(PAPER.linear_accel, PAPER.angular_accel))
    assert late.run.ending[0], late.run.ending
    assert shapely.distance(drawn, shapely.points(late.xy())).max() <= tolerance


def test_planning_by_minimum_time_from_another_heading_is_no_slower_than_by_the_tube():
    """The limit is solved from the path's own heading. From facing along x, 43 degrees off a
    sine's start, where the tube's plan curves onto the path from the robot's heading,
    planning by minimum time takes the faster plan as a whole: no slower by the controller's
    least time than the tube's (the limit's motion after a turn in place first is 14%
    slower)."""
    from turtle_traj.apps.score.courses import PAPER_LIMITS, follow_request
    from turtle_traj.core.geometry.path import Pose2D
    from turtle_traj.core.parameters.settings import settings_from_values
    from turtle_traj.core.parameters.table import DEFAULTS
    from turtle_traj.core.planning import planner

    along = np.linspace(0.0, 2.0, 41)
    points = np.stack([1.0 + along, 2.0 + 0.3 * np.sin(math.pi * along)], axis=1)
    start = Pose2D(1.0, 2.0, 0.0)
    least = {}
    for way in ('tube', 'minimum_time'):
        settings = settings_from_values({**DEFAULTS, **PAPER_LIMITS, 'arena': 'none',
                                         'corner_planning': way})
        plan = planner.plan('follow_path', follow_request(points, corner_tolerance=0.1),
                            start, settings)
        least[way] = plan.least_time_s(settings.control)
    assert least['minimum_time'] <= least['tube']


def test_a_limit_that_cuts_across_the_tube_between_nodes_is_solved_again_with_more():
    """With few nodes the limit's motion leaves the tube between them, and is faster than a
    motion that keeps within it may be. Asked to, it is solved again from itself with twice the
    nodes: then it strays less (measured here with shapely from its motion) and takes longer."""
    tolerance = CORNER_TOLERANCES_M[0]
    coarse = minimum_time(CORNER, tolerance, PAPER, nodes=15)
    refined = minimum_time(CORNER, tolerance, PAPER, nodes=15, most_nodes=30)
    drawn = shapely.LineString(CORNER)

    def stray_m(limit) -> float:
        return float(shapely.distance(drawn, shapely.points(limit.motion)).max()) - tolerance

    assert coarse.solved and refined.solved
    assert stray_m(coarse) > 0.005 * tolerance  # the coarse one cuts across
    assert len(refined.times) == 31
    assert stray_m(refined) < 0.5 * stray_m(coarse)
    assert refined.time_s > coarse.time_s


def test_the_solver_prints_nothing_on_standard_output():
    """IPOPT's banner would land in the middle of `turtle-traj score`'s tables: a fresh process
    (the banner comes once, at a process's first solve) solves a corner and prints only its
    own line."""
    import subprocess
    import sys

    program = ('import numpy as np\n'
               'from turtle_traj.core.control.config import Limits\n'
               'from turtle_traj.core.planning.min_time import minimum_time\n'
               'limits = Limits(linear_speed=0.5, angular_speed=1.0, linear_accel=0.5,'
               ' angular_accel=1.0, period_s=0.016)\n'
               'limit = minimum_time(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]), 0.05,'
               ' limits, nodes=20, most_nodes=20)\n'
               'print(limit.solved)\n')
    done = subprocess.run([sys.executable, '-c', program], capture_output=True, text=True,
                          timeout=120, check=True)
    assert done.stdout == 'True\n'
