"""The physics base (MuJoCo) end to end through ROS: the trajectory node drives it by odom and
TwistStamped cmd_vel, exactly as it would a real base, and every figure is checked against
independent geometry and the base's ground truth.
"""

import math
import os
import subprocess
import sys

import numpy as np
import pytest
from geometry_msgs.msg import Twist, TwistStamped
from rclpy.parameter import Parameter
from turtle_traj_interfaces.srv import DrawShape, Move

from turtle_traj.apps.base_system import BaseSystem
from turtle_traj.base.drive import DriveLimits
from turtle_traj.base.node import BaseNode
from turtle_traj.base.parameters import BaseConfigError
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon

LIMITS = DriveLimits()  # TurtleBot3 Burger: 0.22 m/s, 2.84 rad/s; 2.5 m/s², 3.2 rad/s²
PERIOD_S = 0.016


def _xy(samples) -> np.ndarray:
    return np.array([(x, y) for _t, x, y, _yaw in samples])


def _outside_limits(commands: list[TwistStamped]) -> list[str]:
    """Commands beyond the limits the node was given, or a step the limits do not allow."""
    found, previous = [], Twist()
    for msg in commands:
        twist = msg.twist
        if (abs(twist.linear.x) > LIMITS.max_linear_speed + 1e-9
                or abs(twist.angular.z) > LIMITS.max_angular_speed + 1e-9
                or abs(twist.linear.x - previous.linear.x)
                > LIMITS.max_linear_accel * PERIOD_S * (1 + 1e-6)
                or abs(twist.angular.z - previous.angular.z)
                > LIMITS.max_angular_accel * PERIOD_S * (1 + 1e-6)):
            found.append(f'{twist.linear.x:.4f} m/s {twist.angular.z:.4f} rad/s')
        previous = twist
    return found


@pytest.fixture
def base(rclpy_context, tmp_path):
    system = BaseSystem(context=rclpy_context, output_dir=tmp_path)
    try:
        yield system
    finally:
        system.close()


def test_the_node_draws_a_square_on_the_physics_base_within_its_limits(base):
    commands: list[TwistStamped] = []
    base.client.create_subscription(TwistStamped, 'cmd_vel', commands.append, TURTLE_TOPIC_QOS)
    response = base.call(DrawShape, 'draw_square', DrawShape.Request(size=0.5))
    assert response.success, response.message
    ideal = regular_polygon(0.0, 0.0, 0.0, 4, 0.5, False)
    odometry, truth = _xy(base.odometry), _xy(base.truth)
    # What the controller sees (odometry) is exact; the true path is off by the odometry's drift.
    seen = distance_to_polyline(odometry, ideal).max()
    assert seen < 0.005
    assert response.max_deviation == pytest.approx(seen, abs=2e-4)
    assert distance_to_polyline(truth, ideal).max() < 0.015
    for vertex in ideal:
        assert np.min(np.linalg.norm(odometry - vertex, axis=1)) < 0.005
    assert commands and _outside_limits(commands) == []
    assert base.sim.clipped_commands == 0
    # the odometry drifts from the truth, as a real base's does, but little
    drift = np.linalg.norm(odometry[-1] - truth[-1])
    assert 0.0 < drift < 0.015


def test_the_command_timeout_stops_the_wheels(base):
    publisher = base.client.create_publisher(TwistStamped, 'cmd_vel', TURTLE_TOPIC_QOS)
    command = TwistStamped()
    command.twist.linear.x = 0.2
    assert base.spin_until(lambda: publisher.get_subscription_count() > 0, timeout_s=5.0)
    publisher.publish(command)  # once: then silence
    sent_s = base.sim_time_s
    base.spin_sim_seconds(0.4)
    moving = base.truth[-1]
    assert base.sim.limiter.linear == pytest.approx(0.2)
    # 0.5 s after the command the base brakes at its limit: 0.2 m/s stops in 0.08 s
    base.spin_until(lambda: base.sim_time_s > sent_s + 0.5 + 0.2, timeout_s=2.0)
    stopped = base.truth[-1]
    base.spin_sim_seconds(0.5)
    assert base.sim.timed_out == 1
    assert base.sim.limiter.linear == 0.0
    assert math.dist(stopped[1:3], base.truth[-1][1:3]) < 0.0005  # standing
    # from the origin it drove at 0.2 m/s for the timeout (less what reaching that speed
    # cost), braked at its limit, and went no further
    ramp_m = 0.2**2 / (2 * 2.5)
    assert moving[1] < stopped[1]
    assert 0.2 * 0.5 - ramp_m - 0.005 < stopped[1] < 0.2 * (0.5 + 0.016) + ramp_m + 0.005


def test_a_command_delay_holds_each_command_that_long(rclpy_context, tmp_path):
    """`command_delay`: a latency for tests. A command takes effect that much later in
    simulated time (the base's speed then starts to follow it), and a run still ends where
    it should, its commands in flight counted from the odometry."""
    system = BaseSystem(context=rclpy_context, output_dir=tmp_path,
                        base_parameters={'command_delay': 0.048})
    try:
        publisher = system.client.create_publisher(TwistStamped, 'cmd_vel', TURTLE_TOPIC_QOS)
        assert system.spin_until(lambda: publisher.get_subscription_count() > 0, timeout_s=5.0)
        command = TwistStamped()
        command.twist.linear.x = 0.1
        publisher.publish(command)
        sent_s = system.sim_time_s
        system.spin_until(lambda: system.sim.limiter.linear > 0.0, timeout_s=5.0)
        assert system.sim_time_s - sent_s == pytest.approx(0.048, abs=0.017)
        publisher.publish(TwistStamped())
        system.spin_sim_seconds(0.3)
        response = system.call(Move, 'move', Move.Request(distance=0.2))
        assert response.success, response.message
        moved = system.odometry[-1][1] - system.odometry[0][1]
        assert moved == pytest.approx(0.2, abs=0.002)
    finally:
        system.close()


def test_a_twist_only_base_is_driven_with_twist(rclpy_context, tmp_path):
    system = BaseSystem(context=rclpy_context, output_dir=tmp_path,
                        base_parameters={'cmd_vel_type': 'Twist'})
    try:
        assert system.node.get_parameter('cmd_vel_type').value == 'Twist'
        response = system.call(Move, 'move', Move.Request(distance=0.3))
        assert response.success, response.message
        assert system.truth[-1][1] == pytest.approx(0.3, abs=0.01)
        assert system.odometry[-1][1] == pytest.approx(0.3, abs=0.001)
    finally:
        system.close()


def test_lock_step_on_the_base_is_bit_identical(rclpy_context, tmp_path):
    runs = []
    for _ in range(2):
        system = BaseSystem(context=rclpy_context, output_dir=tmp_path)
        try:
            assert system.call(Move, 'move', Move.Request(distance=0.2)).success
            runs.append(list(system.truth))
        finally:
            system.close()
    assert runs[0] == runs[1]


@pytest.mark.parametrize(('overrides', 'said'), [
    ({'mass': -1.0}, 'mass must be within 0.05 and 500, got -1.0'),
    ({'wheel_radius': 0.0}, 'wheel_radius must be within 0.011 and 0.5, got 0.0'),
    ({'max_linear_accel': math.nan, 'max_angular_speed': math.nan},
     'max_linear_accel must be within 0 and 100, got nan'),
    ({'mass': 2}, 'mass must be a number with a decimal point'),
    ({'cmd_vel_type': 'Foo'}, "cmd_vel_type must be one of TwistStamped, Twist, got 'Foo'"),
    ({'update_rate': 70.0}, 'a whole number of physics steps'),
])
def test_bad_parameters_are_refused_with_what_is_wrong(rclpy_context, overrides, said):
    with pytest.raises(BaseConfigError) as refused:
        BaseNode(context=rclpy_context, lockstep=True, parameter_overrides=[
            Parameter(name, value=value) for name, value in overrides.items()])
    assert said in str(refused.value)
    if len(overrides) == 2:  # every refusal is named at once
        assert 'max_angular_speed must be within' in str(refused.value)


def test_the_limits_are_live_and_refuse_nan(base):
    base.sim.set_parameters([Parameter('max_linear_accel', value=1.0)])
    assert base.sim.limiter.limits.max_linear_accel == 1.0
    result = base.sim.set_parameters([Parameter('max_linear_accel', value=math.nan)])[0]
    assert not result.successful
    assert base.sim.limiter.limits.max_linear_accel == 1.0


def test_a_non_finite_command_is_ignored(base):
    publisher = base.client.create_publisher(TwistStamped, 'cmd_vel', TURTLE_TOPIC_QOS)
    assert base.spin_until(lambda: publisher.get_subscription_count() > 0, timeout_s=5.0)
    command = TwistStamped()
    command.twist.linear.x = math.nan
    publisher.publish(command)
    base.spin_sim_seconds(0.2)
    assert base.sim.limiter.linear == 0.0
    assert math.dist(base.truth[0][1:3], base.truth[-1][1:3]) < 1e-4


@pytest.mark.system
def test_the_base_without_mujoco_says_how_to_get_it(tmp_path):
    hidden = tmp_path / 'mujoco'
    hidden.mkdir()
    (hidden / '__init__.py').write_text("raise ImportError('No module named mujoco')\n")
    env = {**os.environ, 'PYTHONPATH': f'{tmp_path}{os.pathsep}{os.environ.get("PYTHONPATH", "")}'}
    result = subprocess.run([sys.executable, '-m', 'turtle_traj.base'], env=env,
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 2
    assert "pip install 'turtle_traj[physics]'" in result.stderr
    assert 'Traceback' not in result.stderr


def test_the_live_view_shows_the_ground_truth_trail(base):
    from turtle_traj.apps.base_view import TRAIL, BaseScene
    from turtle_traj.core.turtlesim_contract import SPAWN_XY_M
    from turtle_traj.testing.geometry import ink_at

    scene = BaseScene(base.sim)
    frames = []
    scene.step_listeners.append(lambda: frames.append(scene.world.time_s))
    try:
        assert base.call(DrawShape, 'draw_square', DrawShape.Request(size=1.0)).success
    finally:
        scene.close()
    assert frames and frames[-1] == base.sim_time_s
    truth = _xy(base.truth)
    # the trail lies where the base truly went (the world's origin at the canvas's centre)
    on_canvas = truth[::10] + SPAWN_XY_M
    assert ink_at(scene.canvas, on_canvas, (TRAIL.r, TRAIL.g, TRAIL.b)).mean() > 0.95
    x, y, yaw = base.sim.physics.pose()
    assert (scene.turtle.x, scene.turtle.y, scene.turtle.theta) == (
        x + SPAWN_XY_M, y + SPAWN_XY_M, yaw)


def test_nav2s_follow_path_drives_the_physics_base_in_its_odometry_frame(base):
    from action_msgs.msg import GoalStatus
    from nav2_msgs.action import FollowPath

    from tests.test_nav2_follow_path import path_result, planner_like, send_path

    follow = base.action_client(FollowPath, '/follow_path')
    assert base.spin_until(follow.server_is_ready, timeout_s=60.0)
    points = planner_like(radius=0.5, start=(0.0, 0.0))  # where the base stands
    wrong = path_result(base, send_path(base, follow, points, frame_id='map'))
    assert wrong.result.error_code == FollowPath.Result.TF_ERROR
    assert "'odom'" in wrong.result.error_msg  # the frame it follows paths in
    outcome = path_result(base, send_path(base, follow, points, frame_id='odom'))
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED, outcome.result.error_msg
    odometry = _xy(base.odometry)
    assert distance_to_polyline(odometry, points).max() < 3e-3
    assert math.dist(odometry[-1], points[-1]) < 0.01
