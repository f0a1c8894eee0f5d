"""A base with acceleration limits, end to end through ROS: our simulator with inertia, the node
with the base's limits, Odometry and TwistStamped through a relay, rounded corners, open space.

Every figure is checked against independent geometry: the ideal polygon, the commands the node
published (each within reach of the one before) and the stop-and-turn time bound computed here.
"""

import math

import numpy as np
import pytest
from action_msgs.msg import GoalStatus
from geometry_msgs.msg import Point, Twist
from rcl_interfaces.msg import Parameter as ParameterMsg
from rcl_interfaces.msg import ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from turtle_traj_interfaces.msg import Ending
from turtle_traj_interfaces.srv import DrawShape, DrawText, FollowPath, GoTo, Move

from turtle_traj.apps.in_process import InProcessSystem
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M, STEP_S
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon, xy

START = (SPAWN_XY_M, SPAWN_XY_M, 0.0)
# The DWPP paper's base: 0.5 m/s and 1 rad/s, 0.5 m/s² and 1 rad/s².
SPEED, TURN_RATE, ACCEL, TURN_ACCEL = 0.5, 1.0, 0.5, 1.0
LIMITS = dict(linear_speed=SPEED, angular_speed=TURN_RATE, max_linear_accel=ACCEL,
              max_angular_accel=TURN_ACCEL)
INERTIA = dict(max_linear_accel=ACCEL, max_angular_accel=TURN_ACCEL)


def _system(rclpy_context, tmp_path, sim=INERTIA, **node) -> InProcessSystem:
    system = InProcessSystem(context=rclpy_context, output_dir=tmp_path, sim_parameters=sim,
                             **{**LIMITS, **node})
    system.commands = []  # what the node sent, as the simulator received it
    system.client.create_subscription(Twist, 'turtle1/cmd_vel', system.commands.append,
                                      TURTLE_TOPIC_QOS)
    return system


@pytest.fixture
def base(rclpy_context, tmp_path):
    system = _system(rclpy_context, tmp_path)
    try:
        yield system
    finally:
        system.close()


def _trapezoid_s(distance: float, top: float, accel: float) -> float:
    """Fastest rest-to-rest time over `distance` at `top` speed and `accel` (both ways)."""
    if distance * accel < top * top:  # never reaches top speed
        return 2.0 * math.sqrt(distance / accel)
    return distance / top + top / accel


def _outside_reach(commands: list[Twist]) -> int:
    """Commands the base cannot take within one step of the one before."""
    outside, previous = 0, Twist()
    for command in commands:
        if (abs(command.linear.x - previous.linear.x) > ACCEL * STEP_S * (1 + 1e-6)
                or abs(command.angular.z - previous.angular.z) > TURN_ACCEL * STEP_S * (1 + 1e-6)):
            outside += 1
        previous = command
    return outside


def test_a_square_on_a_base_with_inertia_is_exact_within_its_limits_and_near_the_bound(base):
    response = base.call(DrawShape, 'draw_square', DrawShape.Request(size=2.0))
    assert response.success, response.message
    ideal = regular_polygon(*START, 4, 2.0, False)
    path = xy(base.poses)
    for vertex in ideal:
        assert np.min(np.linalg.norm(path - vertex, axis=1)) < 0.001
    assert distance_to_polyline(path, ideal).max() < 0.001
    assert response.max_deviation == pytest.approx(distance_to_polyline(path, ideal).max(),
                                                   abs=1e-4)
    assert response.final_error < 0.001
    assert _outside_reach(base.commands) == 0
    assert max(abs(c.linear.x) for c in base.commands) <= SPEED + 1e-9
    # stop and turn: four sides, three quarter turns, each from rest to rest
    bound = 4 * _trapezoid_s(2.0, SPEED, ACCEL) + 3 * _trapezoid_s(math.pi / 2, TURN_RATE,
                                                                    TURN_ACCEL)
    assert 0.98 * bound < response.elapsed <= 1.10 * bound


def test_rounded_corners_keep_moving_within_their_tolerance_and_report_the_cost(base):
    exact = base.call(DrawShape, 'draw_square', DrawShape.Request(size=2.0))
    assert exact.success, exact.message
    start = base.poses[-1]  # back at the first corner, facing along the last side
    rounded = base.call(DrawShape, 'draw_square', DrawShape.Request(size=2.0,
                                                                     corner_tolerance=0.05))
    assert rounded.success, rounded.message
    ideal = regular_polygon(start.x, start.y, start.theta, 4, 2.0, False)
    deviation = distance_to_polyline(xy(base.poses), ideal)
    assert 0.03 < deviation.max() <= 0.05 + 0.002  # it used the tolerance, and kept to it
    assert rounded.max_deviation == pytest.approx(deviation.max(), abs=1e-3)
    assert rounded.elapsed < exact.elapsed - 1.0  # three corners driven through, not turned
    assert rounded.final_error < 0.001
    assert _outside_reach(base.commands) == 0


def test_rotate_go_to_and_a_circle_brake_in_time(base):
    turned = base.call(Move, 'rotate', Move.Request(angle=math.pi))
    assert turned.success, turned.message
    assert abs(turned.final_heading_error) < 0.001
    gone = base.call(GoTo, 'go_to', GoTo.Request(x=8.0, y=4.0))
    assert gone.success, gone.message
    assert math.dist((base.poses[-1].x, base.poses[-1].y), (8.0, 4.0)) < 0.01
    circle = base.call(DrawShape, 'draw_circle', DrawShape.Request(size=1.0))
    assert circle.success, circle.message
    assert circle.max_deviation < 0.002
    assert _outside_reach(base.commands) == 0


@pytest.mark.parametrize('delay', [0.048])
def test_the_latency_model_keeps_working_with_inertia(rclpy_context, tmp_path, delay):
    system = _system(rclpy_context, tmp_path, sim={**INERTIA, 'command_delay': delay})
    try:
        response = system.call(DrawShape, 'draw_triangle', DrawShape.Request(size=2.0))
        assert response.success, response.message
        ideal = regular_polygon(*START, 3, 2.0, False)
        assert distance_to_polyline(xy(system.poses), ideal).max() < 0.001
        assert _outside_reach(system.commands) == 0
    finally:
        system.close()


def test_odometry_and_twist_stamped_through_a_relay(rclpy_context, tmp_path):
    system = InProcessSystem(context=rclpy_context, output_dir=tmp_path, sim_parameters=INERTIA,
                             base_adapter=True, pose_source='odometry', odom_topic='odom',
                             cmd_vel_type='TwistStamped', cmd_vel_topic='cmd_vel', **LIMITS)
    try:
        assert system.node.pose_topic == '/odom'
        response = system.call(FollowPath, 'follow_path', FollowPath.Request(points=[
            Point(x=7.5, y=5.5), Point(x=7.5, y=7.5)]))
        assert response.success, response.message
        ideal = np.array([START[:2], (7.5, 5.5), (7.5, 7.5)])
        assert distance_to_polyline(xy(system.poses), ideal).max() < 0.002
        assert math.dist((system.poses[-1].x, system.poses[-1].y), (7.5, 7.5)) < 0.002
    finally:
        system.close()


def test_a_base_slower_than_its_limits_ends_with_a_message(rclpy_context, tmp_path):
    system = _system(rclpy_context, tmp_path, sim=dict(max_linear_accel=0.1,
                                                    max_angular_accel=0.2))
    try:
        response = system.call(DrawShape, 'draw_square', DrawShape.Request(size=2.0),
                               timeout_s=120.0)
        assert not response.success and response.ending.code == Ending.NO_PROGRESS
        assert 'max_linear_accel' in response.message
        # the node still serves: the next request gets its verdict, and nothing is left running
        after = system.call(Move, 'rotate', Move.Request(angle=0.5), timeout_s=120.0)
        assert after.success or after.ending.code == Ending.NO_PROGRESS, after.message
        assert not system.node.busy
    finally:
        system.close()


def test_open_space_allows_what_the_walls_refuse(rclpy_context, tmp_path):
    system = _system(rclpy_context, tmp_path, sim={})
    try:
        near_wall = GoTo.Request(x=10.9, y=5.5)
        refused = system.call(GoTo, 'go_to', near_wall)
        assert not refused.success and refused.ending.code == Ending.INVALID_REQUEST
        assert 'outside the arena' in refused.message
        changed = system.call(SetParameters, '/turtle_traj/set_parameters',
                              SetParameters.Request(parameters=[ParameterMsg(
                                  name='arena', value=ParameterValue(
                                      type=ParameterType.PARAMETER_STRING,
                                      string_value='none'))]))
        assert changed.results[0].successful, changed.results[0].reason
        allowed = system.call(GoTo, 'go_to', near_wall)
        assert allowed.success, allowed.message
        wrong = system.call(SetParameters, '/turtle_traj/set_parameters',
                            SetParameters.Request(parameters=[ParameterMsg(
                                name='arena', value=ParameterValue(
                                    type=ParameterType.PARAMETER_STRING,
                                    string_value='walls'))]))
        assert not wrong.results[0].successful
        assert "one of 'rectangle', 'none'" in wrong.results[0].reason
    finally:
        system.close()


@pytest.mark.parametrize(('value', 'reason'), [
    (math.nan, 'corner_tolerance must be a finite number'),
    (-0.1, 'corner_tolerance must be 0'),
    (5.0, 'corner_tolerance must be 0'),
])
def test_bad_corner_tolerances_are_refused(base, value, reason):
    response = base.call(DrawText, 'draw_text', DrawText.Request(text='L',
                                                                   corner_tolerance=value))
    assert not response.success and response.ending.code == Ending.INVALID_REQUEST
    assert reason in response.message
    assert not base.node.busy


def test_a_bad_pose_source_is_refused_at_start(rclpy_context):
    from rclpy.exceptions import InvalidParameterValueException
    from rclpy.parameter import Parameter

    from turtle_traj.node.trajectory_node import TrajectoryNode
    with pytest.raises(InvalidParameterValueException, match="one of 'turtlesim', 'odometry'"):
        TrajectoryNode(context=rclpy_context,
                       parameter_overrides=[Parameter('pose_source', value='gps')])


def test_nav2s_follow_path_on_a_base_with_inertia_is_exact_and_counts_down(base):
    from nav2_msgs.action import FollowPath

    from tests.test_nav2_follow_path import path_result, planner_like, send_path

    follow = base.action_client(FollowPath, '/follow_path')
    assert base.spin_until(follow.server_is_ready, timeout_s=60.0)
    points = planner_like(radius=1.5)
    left: list[float] = []
    handle = send_path(base, follow, points,
                       feedback=lambda message: left.append(message.feedback.distance_to_goal))
    outcome = path_result(base, handle)
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED, outcome.result.error_msg
    driven = xy(base.poses)
    assert distance_to_polyline(driven, points).max() < 3e-3
    assert math.dist(driven[-1], points[-1]) < 0.01
    assert left[0] > 2.0 and left[-1] < 0.01 and all(np.diff(left) <= 1e-6)
    assert _outside_reach(base.commands) == 0


def test_a_path_taking_over_on_a_base_with_inertia_starts_at_the_speed_it_drives(base):
    """A new FollowPath goal replaces the running one on a base with inertia: its first curve's
    speed profile starts at the speed the base drives, so a path that goes on as the base does
    is taken over at full speed (a profile from rest would brake it to about 0.41 m/s within
    the first 0.1 m)."""
    from nav2_msgs.action import FollowPath

    from tests.test_nav2_follow_path import path_result, send_path

    follow = base.action_client(FollowPath, '/follow_path')
    assert base.spin_until(follow.server_is_ready, timeout_s=60.0)
    x, y = base.poses[-1].x, base.poses[-1].y
    first = send_path(base, follow, [(x + 0.02 * step, y) for step in range(201)])
    base.spin_sim_seconds(3.0)
    pose = base.poses[-1]
    assert pose.linear_velocity == pytest.approx(SPEED, abs=1e-3)  # cruising
    angles = np.linspace(0.0, 0.5, 51)[1:]  # on 0.4 m, then along an arc of 2 m radius
    path = np.vstack(([(pose.x + 0.02 * step, pose.y) for step in range(21)],
                      np.stack([pose.x + 0.4 + 2.0 * np.sin(angles),
                                pose.y + 2.0 * (1.0 - np.cos(angles))], axis=1)))
    base.poses.clear()
    second = send_path(base, follow, path)
    assert path_result(base, first).result.error_code == FollowPath.Result.NONE
    assert path_result(base, second).status == GoalStatus.STATUS_SUCCEEDED
    driven = xy(base.poses)
    handover = [p.linear_velocity for p, position in zip(base.poses, driven, strict=True)
                if math.dist(position, path[0]) < 0.1]
    assert min(handover) > 0.99 * SPEED
    assert distance_to_polyline(driven, path).max() < 3e-3
