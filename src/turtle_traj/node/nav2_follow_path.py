"""Nav2's FollowPath action on the trajectory node, as Nav2's controller server serves it.

`follow_path` in the node's namespace, of type nav2_msgs/action/FollowPath (Nav2 Jazzy's, or the
subset interfaces/nav2_msgs builds where Nav2 is not installed: the same type hash). A goal's
path is smoothed within the node's `path_tolerance` (a grid planner's staircase becomes a
line; 0, the default: followed exactly, turning in place at its corners, as `follow_path`
does), in the frame of the poses the node reads, from the robot: a planner's
path begins where the robot stood when it was planned, so the poses up to the end of the
segment nearest the robot (walking from the path's start) are behind it, and the robot drives
from where it stands to the next one.
`controller_id` picks a controller for the goal (empty: the node's `controller`). The goal is
a pose: the run ends turning in place to the last pose's orientation (none where it is a zero
quaternion). Feedback at
10 Hz: the path length left from the nearest point and the speed commanded. A new goal while
one runs replaces it, as Nav2's controller server does: the old run drives on while the new path
is planned, then the new one takes over from where the robot is, without a stop (on a base
with acceleration limits its first curve's profile starts at the speed driven), and the old
goal ends aborted with no error code (a new goal that cannot run leaves the old one running). A
goal that arrives while one of the node's own trajectories runs is refused. Failures carry
Nav2's error codes with `error_msg`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np
from geometry_msgs.msg import Point
from nav2_msgs.action import FollowPath
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.action.server import ServerGoalHandle
from rclpy.callback_groups import CallbackGroup
from rclpy.node import Node
from turtle_traj_interfaces.srv import FollowPath as FollowPathRequest

from turtle_traj.api.controllers import UnknownController
from turtle_traj.core.control.controllers.catalogue import ControllerChoice
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.goal_check import GoalChecker, checker_for
from turtle_traj.core.control.supervisor import Outcome, RunSupervisor
from turtle_traj.core.geometry.projection import LengthLeft, PolylineSegments
from turtle_traj.core.registry import BY_NAME
from turtle_traj.node.draw_action import FEEDBACK_PERIOD_S
from turtle_traj.node.outcomes import RunRefused
from turtle_traj.node.running import RunningNode
from turtle_traj.node.waiting import completion

ACTION = 'follow_path'
Result = FollowPath.Result
# Nav2's code for each way a run ends unsuccessfully or is refused (a cancel ends CANCELED,
# with none; a goal replaced by the next ends aborted with none, as Nav2's action server ends
# it); UNKNOWN for the rest (busy, no robot, a wall, a jump)
ERROR_CODES = {Ending.REPLACED: Result.NONE,
               Ending.INVALID_REQUEST: Result.INVALID_PATH,
               Ending.NO_PROGRESS: Result.FAILED_TO_MAKE_PROGRESS,
               Ending.TIMED_OUT: Result.PATIENCE_EXCEEDED,
               Ending.CONTROLLER_FAULT: Result.NO_VALID_CONTROL}


class GoalFailed(Exception):
    """A goal that cannot be driven: Nav2's error code and the message."""

    def __init__(self, code: int, message: str) -> None:
        super().__init__(message)
        self.code = code


class Nav2FollowPath:
    """`follow_path` on `node`: each goal's path driven through `runs`.

    :param accepting: whether goals are accepted now (a managed server rejects them while it
        is inactive); None: always.
    :param controller_ids: a goal's `controller_id` -> our controller's name (a Nav2 parameter
        file's ids, the first for an empty one); None: the id is the name.
    :param goal_checkers: Nav2's goal checkers by id, one of which (`goal_checker_id`) judges
        the pose a goal's run ends at (`goal_check`); None: none.
    """

    def __init__(self, node: Node, runs: RunningNode, callback_group: CallbackGroup, *,
                 accepting: Callable[[], bool] | None = None,
                 controller_ids: Mapping[str, str] | None = None,
                 goal_checkers: Mapping[str, GoalChecker] | None = None) -> None:
        self._runs, self._ros = runs, node
        self._goal_checkers = goal_checkers
        self._accepting = accepting
        self._controller_ids = controller_ids
        self._running: tuple[ServerGoalHandle, RunSupervisor] | None = None
        self._server = ActionServer(node, FollowPath, ACTION, self._execute,
                                    goal_callback=self._on_goal,
                                    cancel_callback=self._on_cancel,
                                    callback_group=callback_group)

    @property
    def running(self) -> RunSupervisor | None:
        """The run of the goal being driven, if one is."""
        return self._running[1] if self._running is not None else None

    def _on_goal(self, _goal) -> GoalResponse:
        if self._accepting is not None and not self._accepting():
            self._ros.get_logger().warning(f'{ACTION}: a goal arrived while the server is '
                                           'inactive: rejected')
            return GoalResponse.REJECT
        return GoalResponse.ACCEPT

    def destroy(self) -> None:
        self._server.destroy()

    def _on_cancel(self, goal_handle: ServerGoalHandle) -> CancelResponse:
        """Stop this goal's run at once; the goal then ends CANCELED."""
        if self._running is not None and self._running[0] is goal_handle:
            self._runs.stop_run(self._running[1], Ending.CANCELLED)
        else:  # its plan may be being made
            self._runs.stop_planning(goal_handle.request, Ending.CANCELLED)
        return CancelResponse.ACCEPT

    async def _execute(self, goal_handle: ServerGoalHandle) -> FollowPath.Result:
        try:
            controller, request = self._checked(goal_handle.request)
            checker = self._goal_checker(goal_handle.request.goal_checker_id)
            replacing = self._running[1] if self._running is not None else None
            run, finished = await self._start(request, controller, replacing)
        except GoalFailed as failure:
            return self._end(goal_handle, failure.code, str(failure))
        self._running = (goal_handle, run)
        left = LengthLeft(run.plan.path.points())
        feedback = self._ros.create_timer(
            FEEDBACK_PERIOD_S, lambda: goal_handle.publish_feedback(self._feedback(left)))
        try:
            outcome: Outcome = await completion(self._ros, finished)
        finally:
            self._ros.destroy_timer(feedback)
            if self._running is not None and self._running[1] is run:
                self._running = None
        goal_handle.publish_feedback(self._feedback(left))  # the run as it ended
        if goal_handle.is_cancel_requested:
            goal_handle.canceled()
            return Result(error_code=Result.NONE, error_msg=outcome.message)
        if outcome.success:
            missed = self._missed(checker, goal_handle.request.path)
            if missed is not None:
                return self._end(goal_handle, Result.UNKNOWN, f'{outcome.message}, but {missed}')
            goal_handle.succeed()
            return Result(error_code=Result.NONE)
        return self._end(goal_handle, ERROR_CODES.get(outcome.reason, Result.UNKNOWN),
                         outcome.message)

    async def _start(self, request, controller: ControllerChoice | None,
                     replacing: RunSupervisor | None):
        try:
            return await self._runs.start_run(BY_NAME['follow_path'], request,
                                              controller=controller, replacing=replacing)
        except RunRefused as refusal:  # busy, no robot, a path too big, stopped meanwhile
            raise GoalFailed(ERROR_CODES.get(refusal.reason, Result.UNKNOWN), str(refusal)) \
                from None

    def _goal_checker(self, name: str) -> GoalChecker | None:
        """The goal checker `goal_checker_id` picks; GoalFailed for one not loaded."""
        if self._goal_checkers is None:
            return None
        try:
            return checker_for(self._goal_checkers, name)
        except KeyError as error:
            raise GoalFailed(Result.UNKNOWN, error.args[0]) from None

    def _missed(self, checker: GoalChecker | None, path) -> str | None:
        """Why `checker` says the goal is not reached where the run ended; None if it is."""
        pose = self._runs.pose
        if checker is None or pose is None:
            return None
        end = path.poses[-1].pose.position
        command = self._runs.last_command
        return checker.miss(pose, (command.linear, command.angular), (end.x, end.y),
                            _final_heading(path))

    def _checked(self, goal: FollowPath.Goal) -> tuple[ControllerChoice | None, object]:
        """The goal's controller and the request it makes; GoalFailed if it cannot run."""
        points = _points(goal.path)
        self._check_frames(goal.path)
        controller = None
        name = goal.controller_id
        if self._controller_ids is not None:
            name = self._controller_ids.get(name or next(iter(self._controller_ids)))
            if name is None:
                raise GoalFailed(Result.INVALID_CONTROLLER, f'controller_id '
                                 f'{goal.controller_id!r} is not one of this server\'s: '
                                 f"{', '.join(self._controller_ids)}")
        if name:
            try:
                controller = self._runs.choose_controller(name)
            except UnknownController as error:
                raise GoalFailed(Result.INVALID_CONTROLLER, str(error)) from None
        request = FollowPathRequest.Request(
            points=[Point(x=x, y=y) for x, y in self._ahead(points)],
            corner_tolerance=self._runs.settings.defaults.path_tolerance)
        heading = _final_heading(goal.path)
        if heading is not None:  # the goal is a pose: end facing its orientation
            request.use_theta, request.theta = True, heading
        return controller, request

    def _check_frames(self, path) -> None:
        """GoalFailed (TF_ERROR) unless the path is in the frame of the poses read."""
        expected = self._runs.frame_id
        frames = {path.header.frame_id, *(stamped.header.frame_id for stamped in path.poses)}
        if frames - {'', expected}:
            raise GoalFailed(Result.TF_ERROR, f"the path is in frame(s) {sorted(frames - {''})}; "
                             f"this node follows paths in '{expected}' (the frame of the poses "
                             "it reads), or with an empty frame_id")

    def _ahead(self, points: list[tuple[float, float]]) -> list[tuple[float, float]]:
        """The path from where the robot joins it on: the point a little ahead of the one
        nearest the robot (found walking from the start), then the poses after it. The joining
        stretch is at least a control period's drive at top speed, and meets the path at a
        quarter of `corner_angle` at most, however close the next pose: the robot steers onto
        the path, never turns in place to reach a pose beside it."""
        pose = self._runs.pose
        if pose is None or len(points) < 2:
            return points
        segments = PolylineSegments(np.array(points))
        nearest, _ = segments.walk(0, pose.x, pose.y)
        _, fraction, offset = segments.project(pose.x, pose.y, (nearest,))
        settings = self._runs.settings
        join = max(abs(offset) / math.tan(settings.defaults.corner_angle / 4.0),
                   settings.control.linear_speed * settings.control.period_s)
        index, x, y = segments.along(nearest, fraction, join)
        return [(x, y), *points[index + 1:]]

    def _feedback(self, left: LengthLeft) -> FollowPath.Feedback:
        pose = self._runs.pose
        distance = left(pose.x, pose.y) if pose is not None else math.nan
        return FollowPath.Feedback(distance_to_goal=distance,
                                   speed=abs(self._runs.last_command.linear))

    def _end(self, goal_handle: ServerGoalHandle, code: int, message: str) -> Result:
        """Abort the goal with Nav2's `code` (a warning in the log, unless it is NONE). rclpy
        ties a severity to each line that logs: each severity has its own."""
        if code == Result.NONE:
            self._ros.get_logger().info(f'{ACTION}: {message}')
        else:
            self._ros.get_logger().warning(f'{ACTION}: {message}')
        goal_handle.abort()
        return Result(error_code=code, error_msg=message)


def _final_heading(path) -> float | None:
    """The yaw of the path's last pose; None where its orientation is unset (a zero
    quaternion)."""
    q = path.poses[-1].pose.orientation
    norm = math.sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w)
    if not math.isfinite(norm) or norm < 1e-9:
        return None
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def _points(path) -> list[tuple[float, float]]:
    """The path's positions; GoalFailed (INVALID_PATH) for none, or one not finite."""
    if not path.poses:
        raise GoalFailed(Result.INVALID_PATH, 'the path has no poses')
    points = [(stamped.pose.position.x, stamped.pose.position.y) for stamped in path.poses]
    if not all(math.isfinite(value) for point in points for value in point):
        raise GoalFailed(Result.INVALID_PATH, 'the path has a pose that is not finite')
    return points
