"""The follower and the run supervisor in a pure closed loop on the simulator's physics.

No ROS: the loop below is the node's (a pose in, one command out per 16 ms step), with the
turtle moved by `sim.physics.World` exactly as the simulator moves it.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.supervisor import SETTLE_PERIODS
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon
from turtle_traj.testing.pure_loop import Loop, shape

SETTINGS = DEFAULT_SETTINGS
ARENA = SETTINGS.arena


@pytest.mark.parametrize(('sides', 'side', 'clockwise'), [(4, 2.0, False), (3, 2.5, True),
                                                          (6, 1.0, False)])
def test_a_polygon_driven_on_the_physics_closes_on_its_corners(sides, side, clockwise):
    loop = Loop('polygon', shape(sides=sides, size=side, clockwise=clockwise), 4.0, 4.0)
    run, poses = loop.run, loop.drive()
    assert run.ending == (True, 'polygon done')
    xy = np.array([(p.x, p.y) for p in poses])
    corners = regular_polygon(4.0, 4.0, 0.0, sides, side, clockwise)
    assert distance_to_polyline(xy, corners).max() < 1e-3
    outcome = run.outcome(poses[-1], now_s=len(poses) * STEP_S)
    assert outcome.success and outcome.final_error < 1e-3
    assert outcome.path_length == pytest.approx(sides * side)


def test_a_circle_keeps_its_radius_on_the_physics():
    loop = Loop('circle', shape(size=1.5, turns=1.0))
    run, poses = loop.run, loop.drive()
    radii = [math.dist((p.x, p.y), (5.5, 7.0)) for p in poses]
    assert max(abs(r - 1.5) for r in radii) < 1e-3
    assert run.ending[0]
    assert run.max_deviation < 1e-3


def test_a_jump_aborts_the_run():
    loop = Loop('move', SimpleNamespace(distance=3.0, speed=0.0))

    def teleport(step, turtle):
        if step == 40:
            turtle.x += 1.0
    loop.drive(disturb=teleport)
    success, message = loop.run.ending
    assert not success and 'jumped 1.0' in message


def test_a_turtle_pushed_into_the_wall_is_stopped_but_may_leave_it():
    loop = Loop('go_to', SimpleNamespace(x=10.0, y=5.5, use_theta=False, theta=0.0,
                                         tolerance=0.0, linear_speed=0.0))

    def push(step, turtle):  # something drags the turtle off course towards the top wall
        turtle.y += 0.04  # faster than the progress timeout (a turtle held back ends so too)
    loop.drive(disturb=push)
    success, message = loop.run.ending
    assert not success and 'came within' in message
    # A run starting at the wall, closer than half the margin, may still drive away from it.
    loop = Loop('move', SimpleNamespace(distance=-2.0, speed=0.0), x=10.95, y=5.5)
    loop.drive()
    assert loop.run.ending == (True, 'move done')


def test_settling_waits_for_standing_still_at_most_a_few_periods():
    run = Loop('rotate', SimpleNamespace(angle=0.5, speed=0.0)).run
    run.follower.step_index = len(run.follower.steps)  # the path is done
    pose = Pose2D(5.5, 5.5, 0.5)
    for period in range(SETTLE_PERIODS):
        run.command(pose, False, SETTINGS.control, ARENA, period * 0.016)
    assert run.ending is None  # still moving: keep waiting
    run.command(pose, False, SETTINGS.control, ARENA, 1.0)
    assert run.ending == (True, 'rotate done')
    assert run.outcome(pose, now_s=1.0).elapsed_s == 0.0  # the settling is not counted


def test_elapsed_time_runs_from_the_first_command():
    """The clock read as a run is set up can be behind (a simulated clock whose messages
    waited while the request was planned): the run is timed from its first command."""
    run = Loop('rotate', SimpleNamespace(angle=0.5, speed=0.0)).run
    assert run.started_s == 0.0
    pose = Pose2D(5.5, 5.5, 0.0)
    run.command(pose, True, SETTINGS.control, ARENA, 0.3)  # the first command, 0.3 s later
    run.follower.step_index = len(run.follower.steps)  # the path is done
    run.command(pose, True, SETTINGS.control, ARENA, 1.3)
    assert run.ending == (True, 'rotate done')
    assert run.outcome(pose, now_s=1.3).elapsed_s == pytest.approx(1.0)


@pytest.mark.parametrize(('forever', 'success'), [(True, True), (False, False)])
@pytest.mark.parametrize('reason', [Ending.STOPPED, Ending.CANCELLED])
def test_a_stop_request_ends_only_an_endless_trajectory_successfully(forever, success, reason):
    run = Loop('circle', shape(size=1.0, forever=forever)).run
    run.request_stop(reason)
    run.end(True, 'later verdicts are ignored', Ending.SUCCEEDED)
    assert run.ending == (success, 'circle stopped by request')
    outcome = run.outcome(None, now_s=1.0)
    assert (outcome.success, outcome.reason) == (success, reason)


def test_the_plans_speeds_override_the_nodes_live_ones():
    plan = planning.plan('move', SimpleNamespace(distance=1.0, speed=2.5), Pose2D(5, 5, 0),
                                SETTINGS)
    assert plan.control(SETTINGS.control).linear_speed == 2.5
    assert plan.control(SETTINGS.control).angular_speed == SETTINGS.control.angular_speed
    default = Plan('move', plan.path)
    assert default.lower_bound_s(SETTINGS.control) == pytest.approx(
        1.0 / SETTINGS.control.linear_speed)


# -- the figures of the report, against an independent measurement of the poses ------------

def _xy(poses: list[Pose2D]) -> np.ndarray:
    return np.array([(p.x, p.y) for p in poses])


def test_the_deviation_of_a_square_is_its_distance_from_the_square_as_drawn():
    loop = Loop('square', shape(size=2.0), 4.0, 4.0)
    poses = loop.drive()
    corners = regular_polygon(4.0, 4.0, 0.0, 4, 2.0, False)
    measured = distance_to_polyline(_xy(poses), corners).max()
    # stopping a little short of a corner and turning there is not a deviation from the square
    assert loop.run.max_deviation == pytest.approx(measured, abs=1e-9)


def test_a_rotation_reports_its_heading_error():
    loop = Loop('rotate', SimpleNamespace(angle=1.0, speed=0.0), theta=0.2)
    poses = loop.drive()
    outcome = loop.run.outcome(poses[-1], now_s=len(poses) * STEP_S)
    assert outcome.final_heading_error == pytest.approx(poses[-1].theta - 1.2, abs=1e-12)
    assert outcome.final_error < 1e-9 and abs(outcome.final_heading_error) < 0.01


def test_a_move_pushed_sideways_reports_the_drift():
    loop = Loop('move', SimpleNamespace(distance=3.0, speed=0.0), 4.0, 5.0)

    def push(step, turtle):
        if step == 60:
            turtle.y += 0.004  # 4 mm sideways, mid-way
    poses = loop.drive(disturb=push)
    drift = np.abs(_xy(poses)[:, 1] - 5.0).max()
    assert drift >= 0.003
    assert loop.run.max_deviation == pytest.approx(drift, abs=1e-9)


def test_a_circle_stopped_by_request_reports_what_was_driven():
    loop = Loop('circle', shape(size=1.0, forever=True))

    def stop_later(step, turtle):
        if step == 500:  # 8 s: more than one lap
            loop.run.request_stop()
    poses = loop.drive(disturb=stop_later)
    outcome = loop.run.outcome(poses[-1], now_s=len(poses) * STEP_S)
    driven = np.hypot(*np.diff(_xy(poses), axis=0).T).sum()
    assert outcome.success and outcome.path_length == pytest.approx(driven, rel=1e-6)
    assert outcome.path_length > 2 * math.pi  # not one fixed lap
    radius = math.dist((poses[-1].x, poses[-1].y), (5.5, 6.5))
    assert outcome.final_error == pytest.approx(abs(radius - 1.0), abs=1e-4)  # off the path
    assert outcome.final_heading_error == 0.0


@pytest.mark.parametrize(('silent_s', 'jumped'), [(0.0, True), (STEP_S, True), (0.55, False)])
def test_a_gap_in_the_poses_is_driven_through_a_jump_at_one_step_is_not(silent_s, jumped):
    """0.55 m between two poses a step apart is a teleport (more than 0.5 m a step); after
    0.55 s without poses (a link cut for a moment, at 1 m/s) it is where the turtle drove."""
    loop = Loop('circle', shape(size=1.0, forever=True))
    run, start = loop.run, loop.control.pose  # the run starts from the loop's last pose
    run.observe(Pose2D(start.x + 0.55, start.y, start.theta), silent_s)
    assert (run.reason is Ending.POSE_JUMPED) == jumped
    assert (run.ending is None) == (not jumped)
