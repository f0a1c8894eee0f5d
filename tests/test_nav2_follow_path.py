"""Nav2's FollowPath action on the trajectory node (`/follow_path`), lock-step in-process: the
type Nav2 Jazzy has, a planner's dense path followed with Nav2's feedback, Nav2's error codes,
a goal replaced by the next, a cancel, and a refusal while a drawing runs."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from action_msgs.msg import GoalStatus
from ament_index_python.packages import get_package_share_directory
from geometry_msgs.msg import PoseStamped
from nav2_msgs.action import FollowPath
from nav_msgs.msg import Path as PathMsg
from rclpy.parameter import Parameter
from turtle_traj_interfaces.action import Draw
from turtlesim.srv import TeleportAbsolute

from turtle_traj.apps.score.courses import planner_path
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M
from turtle_traj.testing.geometry import distance_to_polyline, xy

# RIHS01 hashes of Nav2 Jazzy's nav2_msgs/action/FollowPath, computed with rosidl's type
# description generator from navigation2's jazzy branch (commit f4108e5b1,
# nav2_msgs/action/FollowPath.action), against the Jazzy messages it uses.
JAZZY_HASHES = {
    'nav2_msgs/action/FollowPath':
        'RIHS01_9d95513552fb578cfb933d7e0160273911269cbdf4b348f1acb87d8a903b13cf',
    'nav2_msgs/action/FollowPath_FeedbackMessage':
        'RIHS01_3f4008700ba56ac4c82b01ef2b7fdd3fc18dc194399c48e5c43ebf8008b891d5',
}
ACTION = '/follow_path'
Result = FollowPath.Result


@pytest.fixture
def follow(turtle_system):
    client = turtle_system.action_client(FollowPath, ACTION)
    assert turtle_system.spin_until(client.server_is_ready, timeout_s=60.0)
    return client


def path_message(points, frame_id: str = '') -> PathMsg:
    path = PathMsg()
    path.header.frame_id = frame_id
    for x, y in points:
        stamped = PoseStamped()
        stamped.pose.position.x, stamped.pose.position.y = float(x), float(y)
        stamped.pose.orientation.w = 1.0
        path.poses.append(stamped)
    return path


def planner_like(radius: float = 1.0, spacing: float = 0.02,
                 start: tuple[float, float] = (SPAWN_XY_M, SPAWN_XY_M)) -> np.ndarray:
    """A quarter circle from `start` along x (the spawn pose), turning left, a pose every
    `spacing` metres (as a planner's path comes: dense poses)."""
    angles = np.linspace(0.0, math.pi / 2, round(radius * math.pi / 2 / spacing) + 1)
    return np.stack([start[0] + radius * np.sin(angles),
                     start[1] + radius * (1.0 - np.cos(angles))], axis=1)


def _length_left(points: np.ndarray, position) -> float:
    """The path's length from the point on it nearest to `position` to its end."""
    starts, along = points[:-1], np.diff(points, axis=0)
    t = np.clip(((np.asarray(position) - starts) * along).sum(axis=1) / (along ** 2).sum(axis=1),
                0.0, 1.0)
    gaps = np.hypot(*(starts + t[:, None] * along - position).T)
    nearest = int(np.argmin(gaps))
    lengths = np.hypot(*along.T)
    return float((1.0 - t[nearest]) * lengths[nearest] + lengths[nearest + 1:].sum())


def send_path(turtle_system, follow, points, feedback=None, **fields):
    future = follow.send_goal_async(FollowPath.Goal(path=path_message(points, fields.pop(
        'frame_id', '')), **fields), feedback_callback=feedback)
    assert turtle_system.spin_until(future.done, timeout_s=10.0)
    handle = future.result()
    assert handle.accepted
    return handle


def path_result(turtle_system, handle, timeout_s: float = 120.0):
    future = handle.get_result_async()
    assert turtle_system.spin_until(future.done, timeout_s=timeout_s)
    return future.result()


def test_the_action_is_nav2_jazzys_type(turtle_system, follow):
    share = Path(get_package_share_directory('nav2_msgs'))
    description = json.loads((share / 'action' / 'FollowPath.json').read_text())
    installed = {entry['type_name']: entry['hash_string'] for entry in description['type_hashes']}
    assert {name: installed[name] for name in JAZZY_HASHES} == JAZZY_HASHES
    # and on the wire: the feedback topic the node publishes carries Nav2's type
    client = turtle_system.client
    publishers = client.get_publishers_info_by_topic(f'{ACTION}/_action/feedback')
    assert [str(info.topic_type_hash) for info in publishers] == [
        JAZZY_HASHES['nav2_msgs/action/FollowPath_FeedbackMessage']]


def test_a_planners_path_is_followed_with_feedback_counting_down(turtle_system, follow):
    points = planner_like()
    length = float(np.hypot(*np.diff(points, axis=0).T).sum())
    feedback = []
    turtle_system.poses.clear()

    def on_feedback(message) -> None:
        pose = turtle_system.poses[-1]
        feedback.append((turtle_system.sim_time_s, message.feedback, (pose.x, pose.y)))
    handle = send_path(turtle_system, follow, points, on_feedback)
    outcome = path_result(turtle_system, handle)
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED
    assert outcome.result.error_code == Result.NONE
    driven = xy(turtle_system.poses)
    assert distance_to_polyline(driven, points).max() < 3e-3
    assert math.dist(driven[-1], points[-1]) < 0.01
    # the length left from the turtle's nearest point on the path, as measured here from the
    # pose it reported (within a step of driving of the node's)
    settings = turtle_system.node.settings.control
    step_m = settings.linear_speed * 0.016
    for _, message, position in feedback:
        assert message.distance_to_goal == pytest.approx(_length_left(points, position),
                                                         abs=step_m + 1e-3)
    left = [message.distance_to_goal for _, message, _ in feedback]
    assert left[0] > length - 0.2 and left[-1] < 0.05
    assert all(later <= earlier + 1e-3 for earlier, later in zip(left, left[1:], strict=False))
    speeds = [message.speed for _, message, _ in feedback]
    assert settings.linear_speed / 2 < max(speeds) <= settings.linear_speed + 1e-6
    elapsed = feedback[-1][0] - feedback[0][0]
    assert len(feedback) >= 10 * elapsed - 1  # 10 Hz, node clock


def test_a_path_planned_from_where_the_robot_stood_is_driven_on_from_where_it_stands(
        turtle_system, follow):
    """A planner's path begins at the robot's pose when it was planned: a hair behind it, or
    some way back along the path. The robot goes on from where it stands, with no turn back to
    the path's first pose; a path that comes back past the robot is driven all the same."""
    points = planner_like() - (6e-4, 0.0)  # its first pose 0.6 mm behind the turtle
    turtle_system.poses.clear()
    outcome = path_result(turtle_system, send_path(turtle_system, follow, points))
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED
    headings = [pose.theta for pose in turtle_system.poses]
    assert min(headings) > -0.01 and max(headings) < math.pi / 2 + 0.01  # never turned back
    assert distance_to_polyline(xy(turtle_system.poses), points).max() < 3e-3
    # a loop that starts 0.2 m back along its first side and returns past the turtle
    pose = turtle_system.poses[-1]
    x, y = pose.x, pose.y
    loop = np.array([(x, y - 0.2), (x, y + 1.0), (x - 1.0, y + 1.0), (x - 1.0, y), (x, y),
                     (x, y + 0.5)])
    turtle_system.poses.clear()
    outcome = path_result(turtle_system, send_path(turtle_system, follow, loop))
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED
    driven = xy(turtle_system.poses)
    assert min(math.dist(position, (x - 1.0, y + 1.0)) for position in driven) < 0.01
    assert math.dist(driven[-1], loop[-1]) < 0.01
    assert driven[:, 1].min() > y - 0.01  # the part behind it was not driven


def test_a_grid_planners_staircase_is_followed_exactly_to_its_goal(turtle_system, follow):
    points = planner_path()  # 5 cm cells, staircases of 45-degree steps, 18 m
    turtle_system.call(TeleportAbsolute, '/turtle1/teleport_absolute', TeleportAbsolute.Request(
        x=float(points[0, 0]), y=float(points[0, 1]), theta=math.pi / 4))
    turtle_system.spin_sim_seconds(0.1)
    turtle_system.poses.clear()
    outcome = path_result(turtle_system, send_path(turtle_system, follow, points))
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED, outcome.result.error_msg
    driven = xy(turtle_system.poses)
    assert distance_to_polyline(driven, points).max() < 3e-3
    assert math.dist(driven[-1], points[-1]) < 0.01


def test_with_a_path_tolerance_a_staircase_is_driven_as_the_way_it_sketches(turtle_system,
                                                                             follow):
    """A grid planner's 24 steps of 5 cm along a 0.85 m diagonal, its goal facing along it: with
    path_tolerance 5 cm, no turn in place at any cell, within the tolerance of the staircase,
    in at most 1.5 times the diagonal's own time."""
    tolerance = 0.05
    turtle_system.node.set_parameters([Parameter('path_tolerance', value=tolerance)])
    x, y = SPAWN_XY_M, SPAWN_XY_M
    turtle_system.call(TeleportAbsolute, '/turtle1/teleport_absolute', TeleportAbsolute.Request(
        x=x, y=y, theta=math.pi / 4))
    stairs = [(x, y)]
    for step in range(24):
        last = stairs[-1]
        stairs.append((last[0] + 0.05, last[1]) if step % 2 == 0 else (last[0], last[1] + 0.05))
    stairs = np.array(stairs)

    def drive(points) -> tuple[float, np.ndarray, list]:
        path = path_message(points)
        last = path.poses[-1].pose.orientation
        last.z, last.w = math.sin(math.pi / 8), math.cos(math.pi / 8)  # facing 45 degrees
        future = follow.send_goal_async(FollowPath.Goal(path=path))
        assert turtle_system.spin_until(future.done, timeout_s=10.0)
        turtle_system.poses.clear()
        outcome = path_result(turtle_system, future.result())
        assert outcome.status == GoalStatus.STATUS_SUCCEEDED, outcome.result.error_msg
        moving = [pose for pose in turtle_system.poses
                  if pose.linear_velocity or pose.angular_velocity]
        return 0.016 * len(moving), xy(turtle_system.poses), moving
    staircase_s, driven, moving = drive(stairs)
    turtle_system.call(TeleportAbsolute, '/turtle1/teleport_absolute', TeleportAbsolute.Request(
        x=x, y=y, theta=math.pi / 4))
    diagonal_s, _, _ = drive(stairs[[0, -1]])
    assert staircase_s <= 1.5 * diagonal_s, (staircase_s, diagonal_s)
    in_place = [pose for pose in moving if pose.linear_velocity == 0.0]
    assert in_place == []  # never turning in place
    assert distance_to_polyline(driven, stairs).max() < tolerance + 0.005
    assert math.dist(driven[-1], stairs[-1]) < 0.01


@pytest.mark.parametrize(('orientation', 'heading'), [
    ((0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4)), math.pi / 2),  # yaw 90 degrees
    ((0.0, 0.0, 0.0, 0.0), 0.0),  # unset: it ends facing along the last segment
])
def test_the_goal_is_a_pose_its_last_orientation_reached(turtle_system, follow, orientation,
                                                         heading):
    start = turtle_system.poses[-1]
    points = np.array([(start.x, start.y), (start.x + 1.0, start.y)])  # along +x
    path = path_message(points)
    last = path.poses[-1].pose.orientation
    last.x, last.y, last.z, last.w = orientation
    future = follow.send_goal_async(FollowPath.Goal(path=path))
    assert turtle_system.spin_until(future.done, timeout_s=10.0)
    outcome = path_result(turtle_system, future.result())
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED
    end = turtle_system.poses[-1]
    assert math.dist((end.x, end.y), points[-1]) < 0.002
    assert abs(wrap_angle(end.theta - heading)) < 0.002  # turtlesim's float32 heading


@pytest.mark.parametrize(('fields', 'code', 'said'), [
    ({'points': []}, Result.INVALID_PATH, 'no poses'),
    ({'points': [(6.0, 5.5), (math.nan, 5.5)]}, Result.INVALID_PATH, 'not finite'),
    ({'points': [(6.0, 5.5), (30.0, 5.5)]}, Result.INVALID_PATH, 'arena'),  # refused by the plan
    ({'frame_id': 'map'}, Result.TF_ERROR, "'world'"),
    ({'controller_id': 'no_such_controller'}, Result.INVALID_CONTROLLER, 'no_such_controller'),
])
def test_a_bad_goal_fails_with_nav2s_code_and_the_next_one_runs(turtle_system, follow, fields,
                                                                 code, said):
    points = fields.pop('points', planner_like(radius=0.5))
    outcome = path_result(turtle_system, send_path(turtle_system, follow, points, **fields))
    assert outcome.status == GoalStatus.STATUS_ABORTED
    assert outcome.result.error_code == code and said in outcome.result.error_msg
    # the node serves the next goal, with the controller it names
    good = planner_like(radius=0.5)
    handle = send_path(turtle_system, follow, good, controller_id='dwpp')
    outcome = path_result(turtle_system, handle)
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED, outcome.result.error_msg


def test_a_new_goal_replaces_the_one_running_and_a_cancel_stops_the_robot(turtle_system,
                                                                         follow):
    first = send_path(turtle_system, follow, planner_like(radius=2.0))
    turtle_system.spin_sim_seconds(1.0)
    pose = turtle_system.poses[-1]
    second_path = [(pose.x, pose.y), (pose.x, pose.y - 1.0)]
    second = send_path(turtle_system, follow, second_path)
    assert path_result(turtle_system, first).status == GoalStatus.STATUS_ABORTED
    outcome = path_result(turtle_system, second)
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED
    assert math.dist(xy(turtle_system.poses)[-1], second_path[-1]) < 0.01
    # a cancel stops the robot within a few steps
    third = send_path(turtle_system, follow, planner_like(radius=2.0) - (0.0, 1.5))
    turtle_system.spin_sim_seconds(1.0)
    cancel = third.cancel_goal_async()
    cancelled_at = turtle_system.sim_time_s
    assert turtle_system.spin_until(cancel.done)
    assert path_result(turtle_system, third).status == GoalStatus.STATUS_CANCELED
    assert turtle_system.spin_until(
        lambda: turtle_system.poses[-1].linear_velocity == 0.0, timeout_s=1.0)
    assert turtle_system.sim_time_s - cancelled_at < 0.1


def test_a_new_path_takes_over_from_the_running_one_without_a_stop(turtle_system, follow):
    """As a Nav2 planner replans: the second path starts where the robot was as it was planned
    (a step behind it by the time it arrives), goes on straight, then bends left on an arc. The
    robot never slows below half its speed until it brakes for the end, follows both paths, and
    the first goal ends aborted with no error code, as Nav2's action server ends a preempted
    one."""
    x, y = SPAWN_XY_M - 2.0, SPAWN_XY_M
    first_path = np.array([(x + 0.02 * step, y) for step in range(201)])  # 4 m along x
    turtle_system.call(TeleportAbsolute, '/turtle1/teleport_absolute',
                       TeleportAbsolute.Request(x=x, y=y, theta=0.0))
    turtle_system.spin_sim_seconds(0.1)
    first = send_path(turtle_system, follow, first_path)
    turtle_system.spin_sim_seconds(1.5)
    pose = turtle_system.poses[-1]
    assert pose.linear_velocity > 0.99  # cruising
    straight = [(pose.x + 0.02 * step, pose.y) for step in range(21)]
    angles = np.linspace(0.0, 0.5, 51)[1:]  # radius 2 m, 2 cm apart
    arc = np.stack([straight[-1][0] + 2.0 * np.sin(angles),
                    pose.y + 2.0 * (1.0 - np.cos(angles))], axis=1)
    second_path = np.vstack((straight, arc))
    turtle_system.poses.clear()
    second = send_path(turtle_system, follow, second_path)
    replaced = path_result(turtle_system, first)
    assert replaced.status == GoalStatus.STATUS_ABORTED
    assert replaced.result.error_code == Result.NONE
    outcome = path_result(turtle_system, second)
    assert outcome.status == GoalStatus.STATUS_SUCCEEDED, outcome.result.error_msg
    driven = xy(turtle_system.poses)
    on_the_way = [p.linear_velocity for p, position in zip(turtle_system.poses, driven,
                                                             strict=True)
                  if math.dist(position, second_path[-1]) > 0.5]
    assert min(on_the_way) > 0.5  # never stopped, nor nearly
    gaps = np.minimum(distance_to_polyline(driven, first_path),
                      distance_to_polyline(driven, second_path))
    assert gaps.max() < 3e-3
    assert math.dist(driven[-1], second_path[-1]) < 0.01
    # a bad goal after a replaced one still fails with its code: the two end at two log
    # severities, and rclpy allows one severity per logging line
    empty = path_result(turtle_system, send_path(turtle_system, follow, np.empty((0, 2))))
    assert empty.result.error_code == Result.INVALID_PATH and empty.result.error_msg


def test_a_goal_while_a_drawing_runs_is_refused_with_the_reason(turtle_system, follow):
    draw = turtle_system.action_client(Draw, '/turtle_traj/draw')
    assert turtle_system.spin_until(draw.server_is_ready, timeout_s=60.0)
    future = draw.send_goal_async(Draw.Goal(trajectory='circle', size=1.0, forever=True))
    assert turtle_system.spin_until(future.done)
    turtle_system.spin_sim_seconds(0.5)
    outcome = path_result(turtle_system, send_path(turtle_system, follow, planner_like()))
    assert outcome.status == GoalStatus.STATUS_ABORTED
    assert outcome.result.error_code == Result.UNKNOWN
    assert 'busy: circle is running' in outcome.result.error_msg
    assert turtle_system.node.busy  # the drawing goes on
