"""The managed controller server driven as Nav2's lifecycle manager drives it: lifecycle_msgs
services, a Nav2 parameter file's controller_server section, FollowPath goals; lock-step,
in-process, our simulator seen as a base (Odometry on odom, TwistStamped on cmd_vel)."""

import math
from pathlib import Path

import numpy as np
import pytest
from action_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped, TwistStamped
from lifecycle_msgs.msg import State, Transition
from lifecycle_msgs.srv import ChangeState, GetState
from nav2_msgs.action import FollowPath
from nav_msgs.msg import Path as PathMsg
from rclpy.exceptions import InvalidHandle
from rclpy.parameter import Parameter, parameter_dict_from_yaml_file
from turtlesim.msg import Pose

from turtle_traj.apps.in_process import SIM_TIME, LockstepSim
from turtle_traj.node.controller_server import ControllerServer
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
from turtle_traj.sim.base_adapter import BaseAdapter
from turtle_traj.testing.geometry import distance_to_polyline

PARAMS_FILE = Path(__file__).parent / 'data' / 'nav2_controller_server.yaml'
SERVER = '/controller_server'


def file_parameters(**changes: object) -> list[Parameter]:
    """The section of the test's Nav2 parameter file, as rclpy reads it, with `changes`."""
    values = {name: Parameter.from_parameter_msg(message).value for name, message in
              parameter_dict_from_yaml_file(str(PARAMS_FILE),
                                            target_nodes=['controller_server']).items()}
    values.update(changes)
    return [Parameter(name, value=value) for name, value in values.items()]


class ServerSystem(LockstepSim):
    """Our simulator, the base adapter, the controller server and a client recording poses
    and the commands sent."""

    def __init__(self, context, tmp_path, **changes: object) -> None:
        super().__init__(context=context, output_dir=tmp_path)
        with self._closed_on_error():
            self.add_node(BaseAdapter(context=context, parameter_overrides=[SIM_TIME]))
            self.server = ControllerServer(
                context=context, parameter_overrides=[SIM_TIME, *file_parameters(**changes)])
            self.add_node(self.server)
            self.poses: list[Pose] = []
            self.commands: list[tuple[float, TwistStamped]] = []
            self.client.create_subscription(Pose, 'turtle1/pose', self.poses.append,
                                            TURTLE_TOPIC_QOS)
            self.client.create_subscription(
                TwistStamped, '/cmd_vel',
                lambda msg: self.commands.append((self.sim_time_s, msg)), TURTLE_TOPIC_QOS)

    def state(self) -> int:
        return self.call(GetState, f'{SERVER}/get_state').current_state.id

    def transition(self, transition: int) -> bool:
        return self.call(ChangeState, f'{SERVER}/change_state', ChangeState.Request(
            transition=Transition(id=transition))).success


@pytest.fixture
def system(rclpy_context, tmp_path):
    made = []

    def make(**changes):
        made.append(ServerSystem(rclpy_context, tmp_path, **changes))
        return made[-1]
    yield make
    for system_ in made:
        system_.close()


def destroyed(node) -> bool:
    try:
        node.get_name()
    except InvalidHandle:
        return True
    return False


def path_message(points) -> PathMsg:
    path = PathMsg()
    path.header.frame_id = 'odom'
    for x, y in points:
        stamped = PoseStamped()
        stamped.header.frame_id = 'odom'
        stamped.pose.position.x, stamped.pose.position.y = float(x), float(y)
        stamped.pose.orientation.w = 1.0
        path.poses.append(stamped)
    return path


def send(system_, points, **fields):
    client = system_.action_client(FollowPath, '/follow_path')
    assert system_.spin_until(client.server_is_ready, timeout_s=60.0)
    future = client.send_goal_async(FollowPath.Goal(path=path_message(points), **fields))
    assert system_.spin_until(future.done, timeout_s=10.0)
    return future.result()


def l_path(start: Pose) -> np.ndarray:
    """An L from the turtle: 1.5 m ahead (along x: it spawns facing +x), then 1 m left."""
    return np.array([(start.x, start.y), (start.x + 1.5, start.y),
                     (start.x + 1.5, start.y + 1.0)])


def test_the_server_comes_up_as_nav2s_manager_brings_it_and_drives_a_goal(system):
    server = system()
    assert server.state() == State.PRIMARY_STATE_UNCONFIGURED
    assert server.server.follower is None  # nothing but the lifecycle services yet
    assert server.transition(Transition.TRANSITION_CONFIGURE)
    assert server.state() == State.PRIMARY_STATE_INACTIVE
    follower = server.server.follower
    # the file's limits are the follower's: vx_max, wz_max, ax_max, -ax_min, az_max
    assert [follower.get_parameter(name).value for name in (
        'linear_speed', 'angular_speed', 'max_linear_accel', 'max_linear_decel',
        'max_angular_accel', 'control_rate', 'progress_timeout', 'controller',
        'cmd_vel_type')] == [0.5, 1.9, 3.0, 3.0, 3.5, 20.0, 10.0, 'dwpp', 'TwistStamped']
    ignored = ' '.join(server.server.config.ignored)
    assert 'FollowPath.time_steps' in ignored and 'FollowPath.GoalCritic.cost_weight' in ignored
    assert 'FollowPath.vx_max' not in ignored  # used
    assert server.spin_until(lambda: bool(server.poses), timeout_s=10.0)

    inactive = send(server, l_path(server.poses[-1]))
    assert not inactive.accepted  # goals are rejected while inactive

    assert server.transition(Transition.TRANSITION_ACTIVATE)
    assert server.state() == State.PRIMARY_STATE_ACTIVE
    start = server.poses[-1]
    points = l_path(start)
    handle = send(server, points)
    assert handle.accepted
    result = handle.get_result_async()
    assert server.spin_until(result.done, timeout_s=60.0)
    assert result.result().status == GoalStatus.STATUS_SUCCEEDED
    driven = np.array([(pose.x, pose.y) for pose in server.poses])
    end = server.poses[-1]
    assert math.dist((end.x, end.y), points[-1]) < 0.05  # DWPP: within its goal tolerance
    assert distance_to_polyline(driven[-50:], points).max() < 0.1
    # every command within the file's limits
    assert max(abs(msg.twist.linear.x) for _, msg in server.commands) <= 0.5 + 1e-9
    assert max(abs(msg.twist.angular.z) for _, msg in server.commands) <= 1.9 + 1e-9


def driving(server: ServerSystem):
    """Bring the server up, send it an L and wait until the robot drives: the goal's handle
    and its result's future (asked for at once, as Nav2's clients do)."""
    assert server.transition(Transition.TRANSITION_CONFIGURE)
    assert server.transition(Transition.TRANSITION_ACTIVATE)
    assert server.spin_until(lambda: bool(server.poses), timeout_s=10.0)
    handle = send(server, l_path(server.poses[-1]))
    assert handle.accepted
    result = handle.get_result_async()
    assert server.spin_until(lambda: server.poses[-1].linear_velocity > 0.3, timeout_s=10.0)
    return handle, result


def test_deactivating_mid_goal_stops_the_robot_within_a_control_period(system):
    server = system()
    handle, result = driving(server)
    server.commands.clear()
    deactivated_at = server.sim_time_s
    assert server.transition(Transition.TRANSITION_DEACTIVATE)
    assert server.state() == State.PRIMARY_STATE_INACTIVE
    assert server.spin_until(result.done, timeout_s=5.0)
    assert result.result().status == GoalStatus.STATUS_ABORTED
    assert 'deactivated' in result.result().result.error_msg
    period = 1.0 / 20.0
    first = server.commands[0]
    assert first[1].twist.linear.x == 0.0 and first[1].twist.angular.z == 0.0
    assert first[0] - deactivated_at <= period
    server.spin_sim_seconds(0.5)
    assert all(msg.twist.linear.x == 0.0 for _, msg in server.commands)  # nothing more sent
    assert server.poses[-1].linear_velocity == 0.0
    assert not send(server, l_path(server.poses[-1])).accepted  # inactive again: rejected


def test_cleanup_and_shutdown_release_everything(system):
    server = system()
    assert server.transition(Transition.TRANSITION_CONFIGURE)
    follower = server.server.follower
    assert server.transition(Transition.TRANSITION_CLEANUP)
    assert server.state() == State.PRIMARY_STATE_UNCONFIGURED
    assert server.server.follower is None
    assert server.spin_until(lambda: destroyed(follower), timeout_s=1.0)
    assert server.transition(Transition.TRANSITION_CONFIGURE)  # and configures again
    assert not server.transition(Transition.TRANSITION_UNCONFIGURED_SHUTDOWN)  # not inactive's
    assert server.transition(Transition.TRANSITION_INACTIVE_SHUTDOWN)
    assert server.state() == State.PRIMARY_STATE_FINALIZED
    assert server.server.follower is None


def test_shutting_down_mid_goal_stops_the_robot_and_releases_everything(system):
    server = system()
    _, result = driving(server)
    follower = server.server.follower
    assert server.transition(Transition.TRANSITION_ACTIVE_SHUTDOWN)
    assert server.state() == State.PRIMARY_STATE_FINALIZED
    assert server.spin_until(result.done, timeout_s=5.0)  # its result goes out before it goes
    assert result.result().status == GoalStatus.STATUS_ABORTED
    server.spin_sim_seconds(0.2)
    assert server.poses[-1].linear_velocity == 0.0 and server.server.follower is None
    assert destroyed(follower)
    assert not server.transition(Transition.TRANSITION_CONFIGURE)  # finalized is final


@pytest.mark.parametrize(('changes', 'said'), [
    ({'FollowPath.plugin': 'nav2_mppi_controller::MPPIController'},
     "FollowPath.plugin: 'nav2_mppi_controller::MPPIController' is a Nav2 C++ plugin, which "
     'this server cannot load: name one of turtle_traj::ExactFollower, turtle_traj::Dwpp, '
     'turtle_traj::PurePursuit, or your own as package.module:Class'),
    ({'FollowPath.vx_max': -0.5}, 'FollowPath.vx_max is -0.5: it must be within [0.01, 10]'),
    ({'general_goal_checker.plugin': 'nav2_controller::PoseGoalChecker'},
     "general_goal_checker.plugin 'nav2_controller::PoseGoalChecker' is not a checker"),
    ({'controller_frequency': 0.0}, 'controller_frequency is 0.0: it must be within [1, 500]'),
])
def test_a_file_this_server_cannot_honour_fails_configure_saying_why(system, changes, said):
    server = system(**changes)
    assert not server.transition(Transition.TRANSITION_CONFIGURE)
    assert server.state() == State.PRIMARY_STATE_UNCONFIGURED
    assert said in server.server.configure_error
    assert server.server.follower is None


def test_the_program_refuses_a_parameter_file_it_cannot_read(tmp_path, capsys):
    from turtle_traj.apps.controller_server import main
    assert main(['--params-file', str(tmp_path / 'missing.yaml')]) == 2
    assert 'error: --params-file: No such file or directory' in capsys.readouterr().err


def test_a_goal_picks_its_controller_by_the_files_id(system):
    server = system(**{'controller_plugins': ['FollowPath', 'Precise'],
                       'Precise.plugin': 'turtle_traj::ExactFollower',
                       'Precise.heading_gain': 6.0})
    assert server.transition(Transition.TRANSITION_CONFIGURE)
    assert server.transition(Transition.TRANSITION_ACTIVATE)
    follower = server.server.follower
    assert follower.get_parameter('exact.heading_gain').value == 6.0
    assert server.spin_until(lambda: bool(server.poses), timeout_s=10.0)
    unknown = send(server, l_path(server.poses[-1]), controller_id='MPPI')
    result = unknown.get_result_async()
    assert server.spin_until(result.done, timeout_s=10.0)
    assert result.result().result.error_code == FollowPath.Result.INVALID_CONTROLLER
    assert "'MPPI' is not one of this server's: FollowPath, Precise" in (
        result.result().result.error_msg)
    start = server.poses[-1]
    points = l_path(start)
    handle = send(server, points, controller_id='Precise')
    result = handle.get_result_async()
    assert server.spin_until(result.done, timeout_s=60.0)
    assert result.result().status == GoalStatus.STATUS_SUCCEEDED
    driven = np.array([(pose.x, pose.y) for pose in server.poses])
    # the exact follower: on the L to the millimetre, corners turned in place
    assert distance_to_polyline(driven, points).max() < 0.002


def test_a_speed_limit_caps_the_speed_from_the_next_control_period_and_lifts(system):
    """Nav2's speed filter publishes SpeedLimit on speed_limit: 50 % of the top speed (0.5 m/s
    in the file), then 0 (no limit). Braking at 10 m/s² (ax_min), half the speed is within
    reach of one 50 ms period."""
    from nav2_msgs.msg import SpeedLimit
    server = system(**{'FollowPath.ax_min': -10.0,
                       'FollowPath.plugin': 'turtle_traj::ExactFollower'})
    limits = server.client.create_publisher(SpeedLimit, '/speed_limit', 10)
    assert server.transition(Transition.TRANSITION_CONFIGURE)
    assert server.transition(Transition.TRANSITION_ACTIVATE)
    assert server.spin_until(lambda: bool(server.poses), timeout_s=10.0)
    start = server.poses[-1]
    handle = send(server, [(start.x, start.y), (start.x + 4.0, start.y)])
    assert handle.accepted
    assert server.spin_until(lambda: server.poses[-1].linear_velocity > 0.499, timeout_s=10.0)
    limits.publish(SpeedLimit(percentage=True, speed_limit=50.0))
    assert server.spin_until(
        lambda: server.server.follower.get_parameter('linear_speed').value == 0.25,
        timeout_s=1.0)
    limited_at, period = server.sim_time_s, 1.0 / 20.0
    server.commands.clear()
    poses_from = len(server.poses)
    server.spin_sim_seconds(1.0)
    later = [msg.twist.linear.x for stamp, msg in server.commands if stamp > limited_at + period]
    assert later and max(later) <= 0.25 + 1e-9  # commanded
    measured = [pose.linear_velocity for pose in server.poses[poses_from:]]
    assert max(measured[4:]) <= 0.25 + 1e-6  # and measured, a control period on (3 steps)
    limits.publish(SpeedLimit(percentage=False, speed_limit=0.0))  # lifted
    assert server.spin_until(lambda: server.poses[-1].linear_velocity > 0.499, timeout_s=2.0)
    result = handle.get_result_async()
    assert server.spin_until(result.done, timeout_s=30.0)
    assert result.result().status == GoalStatus.STATUS_SUCCEEDED


@pytest.mark.parametrize(('percentage', 'value', 'speed'), [
    (True, 50.0, 0.25), (False, 0.1, 0.1), (False, 2.0, 0.5), (True, 0.0, 0.5), (False, 0.0, 0.5),
    (True, 150.0, None), (False, -1.0, None), (False, math.nan, None), (True, 1e-6, 0.01)])
def test_speed_limits_as_nav2_states_them(percentage, value, speed):
    from nav2_msgs.msg import SpeedLimit

    from turtle_traj.node.speed_limit import limited_speed
    assert limited_speed(SpeedLimit(percentage=percentage, speed_limit=value), 0.5) == speed


def test_the_goal_checker_a_goal_names_judges_where_it_ended(system):
    """DWPP ends within its own 1 cm: a checker with no tolerance says the goal is not
    reached; an unknown checker id fails the goal as Nav2 fails it."""
    server = system(**{'goal_checker_plugins': ['general_goal_checker', 'exact_checker'],
                       'exact_checker.plugin': 'nav2_controller::SimpleGoalChecker',
                       'exact_checker.xy_goal_tolerance': 0.0})
    assert server.transition(Transition.TRANSITION_CONFIGURE)
    assert server.transition(Transition.TRANSITION_ACTIVATE)
    assert server.spin_until(lambda: bool(server.poses), timeout_s=10.0)

    def ended(**fields):
        handle = send(server, l_path(server.poses[-1]), **fields)
        result = handle.get_result_async()
        assert server.spin_until(result.done, timeout_s=60.0)
        return result.result()
    unknown = ended(goal_checker_id='precise')
    assert unknown.result.error_code == FollowPath.Result.UNKNOWN
    assert "goal_checker_id 'precise' is not one of this server's" in unknown.result.error_msg
    strict = ended(goal_checker_id='exact_checker')
    assert strict.status == GoalStatus.STATUS_ABORTED
    assert 'beyond xy_goal_tolerance 0 m' in strict.result.error_msg
    loose = ended(goal_checker_id='general_goal_checker')
    assert loose.status == GoalStatus.STATUS_SUCCEEDED
