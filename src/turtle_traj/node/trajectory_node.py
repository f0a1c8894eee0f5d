"""TrajectoryNode: one service per trajectory, the draw action, a control timer, live parameters.

Service handlers validate and plan, hand the path to the control timer and await its end; the
timer steps the pure PathFollower on the latest pose. A watchdog aborts a trajectory when poses
stop arriving: silence is measured on the node's clock (so simulated time gives the same verdict
under any load) and on the wall clock only while the node's clock stands still (a simulator that
published /clock has vanished).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from functools import partial

import numpy as np
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Path as PathMsg
from rclpy.action import ActionServer, CancelResponse
from rclpy.action.server import ServerGoalHandle
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.clock import Clock, ClockType
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from rclpy.task import Future
from rclpy.time import Time
from std_srvs.srv import Empty, Trigger
from turtle_traj_interfaces.action import Draw
from turtlesim.msg import Pose
from turtlesim.srv import SetPen

from turtle_traj import planning
from turtle_traj.control.commands import STOP, Command
from turtle_traj.control.loop import ControlLoop
from turtle_traj.control.plan import Plan
from turtle_traj.control.supervisor import Outcome, RunSupervisor
from turtle_traj.geometry.path import Path, Pose2D
from turtle_traj.node import parameters
from turtle_traj.node.async_service import create_async_service
from turtle_traj.planning import PlanError
from turtle_traj.services import DRAW_ACTION, service_type
from turtle_traj.trajectories import BY_NAME, TRAJECTORIES, Trajectory
from turtle_traj.turtlesim_contract import STEP_S, PenStyle
from turtle_traj.wire import TURTLE_TOPIC_QOS

PLAN_FRAME_ID = 'world'
_WATCHDOG_PERIOD_S = 0.05
_FEEDBACK_PERIOD_S = 0.1  # node clock: 10 Hz
_RESET_TIMEOUT_S = 5.0
_POLL_PERIOD_S = 0.005
_PLAN_POINTS = 20_000  # most points published on ~/plan
_SET_PEN_TIMEOUT_S = 2.0  # wall clock: a simulator that does not answer set_pen has vanished


def fill_response(response, outcome: Outcome):
    """Copy an outcome into any of our service responses (they share these fields)."""
    response.success = outcome.success
    response.message = outcome.message
    if outcome.pose is not None:
        response.final_x, response.final_y = outcome.pose.x, outcome.pose.y
        response.final_theta = outcome.pose.theta
    response.elapsed = outcome.elapsed_s
    response.path_length = outcome.path_length
    response.max_deviation = outcome.max_deviation
    response.final_error = outcome.final_error
    response.final_heading_error = outcome.final_heading_error
    if hasattr(response, 'pen_up_length'):  # drawings (text, svg) and the draw action
        response.pen_up_length = outcome.pen_up_length
        response.pen_up_unordered = outcome.pen_up_unordered
    return response


class TrajectoryNode(Node):
    """Drives one turtle along trajectories on request (node name `turtle_traj`)."""

    def __init__(self, node_name: str = 'turtle_traj', **kwargs) -> None:
        super().__init__(node_name, **kwargs)
        # Pose in, command out: the run, the last pose and the commands still on their way.
        self._loop = ControlLoop(STEP_S)
        # The validator goes first so that overrides given at start-up are checked too; a new
        # arena must contain the turtle.
        self.add_on_set_parameters_callback(
            lambda params: parameters.validate(self, params, self._loop.pose))
        parameters.declare(self)
        self.settings = parameters.read_settings(self)
        self.add_post_set_parameters_callback(self._on_parameters_set)
        turtle = self.get_parameter('turtle_name').value

        self._pose_wall_s = -math.inf
        self._pose_time: Time | None = None
        # The future the run's service handler awaits. One executor thread calls everything
        # here, and a handler checks `_run` and claims it without an `await` in between, so
        # two requests can never both start a run.
        self._run_done: Future | None = None
        self._goal_runs: dict[bytes, RunSupervisor] = {}  # draw goals running, by goal id

        self.pose_topic = self.resolve_topic_name(f'{turtle}/pose')
        self.create_subscription(Pose, f'{turtle}/pose', self._on_pose, TURTLE_TOPIC_QOS)
        self._cmd_vel = self.create_publisher(Twist, f'{turtle}/cmd_vel', TURTLE_TOPIC_QOS)
        self._twist = Twist()
        self._plan = self.create_publisher(
            PathMsg, '~/plan', QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))

        # Handlers await the end of a trajectory, so they must not block the timer's group.
        group = ReentrantCallbackGroup()
        for trajectory in TRAJECTORIES:
            create_async_service(self, service_type(trajectory), f'~/{trajectory.service}',
                                 partial(self._execute, trajectory), callback_group=group)
        # Every goal is accepted (rclpy's default goal callback): one that cannot run ends
        # ABORTED with the reason in its result, which any action client can read; a goal id
        # the server already knows is rejected by rclpy, which makes a client's repeat of an
        # unanswered request harmless (client.py).
        ActionServer(self, Draw, f'~/{DRAW_ACTION}', self._execute_goal,
                     cancel_callback=self._on_cancel,
                     callback_group=group)
        self.create_service(Trigger, '~/stop', self._handle_stop, callback_group=group)
        create_async_service(self, Trigger, '~/reset', self._handle_reset, callback_group=group)
        self.stop_service = self.resolve_service_name('~/stop')
        self._sim_reset = self.create_client(Empty, 'reset', callback_group=group)
        # Drawings lift the pen between strokes; the pen call on its way, and when it went.
        self._set_pen = self.create_client(SetPen, f'{turtle}/set_pen', callback_group=group)
        self._pen_call: Future | None = None
        self._pen_call_wall_s = 0.0

        self.create_timer(1.0 / self.get_parameter('control_rate').value,
                          self._on_control_timer)
        self.create_timer(_WATCHDOG_PERIOD_S, self._on_watchdog,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        name = self.get_fully_qualified_name()
        self.get_logger().info(
            f'serving {len(TRAJECTORIES)} trajectories on {name}/<service> and the action '
            f'{name}/{DRAW_ACTION}; driving {self.pose_topic.removesuffix("/pose")}')

    # -- inputs ------------------------------------------------------------------------------

    def _on_parameters_set(self, _parameters) -> None:
        self.settings = parameters.read_settings(self)

    def _on_pose(self, msg: Pose) -> None:
        self._loop.observe(Pose2D(msg.x, msg.y, msg.theta), msg.linear_velocity,
                           msg.angular_velocity)
        self._finish_if_ended()  # a jump ends the run
        self._pose_wall_s = time.monotonic()
        self._pose_time = self.get_clock().now()

    def _pose_silence_s(self) -> float:
        """Time since the last pose, on the node clock (wall clock while that one stands still)."""
        if self._pose_time is None:
            return math.inf
        silence = (self.get_clock().now() - self._pose_time).nanoseconds * 1e-9
        if silence > 0.0:
            return silence
        return time.monotonic() - self._pose_wall_s

    @property
    def pose(self) -> Pose2D | None:
        """The driven turtle's latest pose (None before the first, or after a reset)."""
        return self._loop.pose

    @property
    def _run(self) -> RunSupervisor | None:
        return self._loop.run

    @property
    def busy(self) -> bool:
        return self._run is not None

    @property
    def ready(self) -> bool:
        """A fresh pose is in and nothing is running: a request would be accepted."""
        return self._refusal() is None

    # -- control -----------------------------------------------------------------------------

    def _on_control_timer(self) -> None:
        run = self._run
        if run is None:
            return
        command = self._loop.command(self.settings.control, self.settings.arena, self._now_s())
        if command is not None:
            self._publish(command)
            if run.follower.pen_wanted is not None and self._pen_call is None:
                self._call_set_pen(run.plan.pen, down=run.follower.pen_wanted, run=run)
        else:
            self._finish_if_ended()  # which sends the stop

    def _call_set_pen(self, pen: PenStyle, *, down: bool, run: RunSupervisor | None = None,
                      then: Callable[[], None] | None = None) -> None:
        """Ask turtlesim for this pen. Once it answers, tell `run`'s follower (if that run is
        still on); answered or given up (the watchdog), call `then`."""
        request = SetPen.Request(r=pen.r, g=pen.g, b=pen.b, width=pen.width, off=not down)
        self._pen_call, self._pen_call_wall_s = self._set_pen.call_async(request), time.monotonic()

        def answered(future: Future) -> None:
            if future is self._pen_call:
                self._pen_call = None
            if run is not None and run is self._run and not future.cancelled():
                run.follower.pen_down = down
            if then is not None:
                then()
        self._pen_call.add_done_callback(answered)

    def _on_watchdog(self) -> None:
        if (self._pen_call is not None
                and time.monotonic() - self._pen_call_wall_s > _SET_PEN_TIMEOUT_S):
            self._pen_call.cancel()
            self._pen_call = None
            if self._run is not None:
                self._finish(False, f'{self._run.name} aborted: {self._set_pen.srv_name} did '
                                    f'not answer within {_SET_PEN_TIMEOUT_S:g} s; is the '
                                    'simulator still running?')
        if self._run is None:
            return
        silence = self._pose_silence_s()
        if silence > self.settings.pose_timeout_s:
            self._finish(False, f'{self._run.name} aborted: no pose on {self.pose_topic} for '
                                f'{silence:.2f} s (pose_timeout {self.settings.pose_timeout_s:g} '
                                's); is the simulator still running?')

    def shutdown_turtle(self) -> None:
        """End any trajectory and leave the turtle standing (called on program exit)."""
        if self._run is not None:
            self._finish(False, f'{self._run.name} aborted: the node is shutting down')
        self._publish(STOP)

    def _publish(self, command: Command) -> None:
        self._loop.sent(command)
        twist = self._twist  # refilled: publish() serializes at once
        twist.linear.x, twist.angular.z = command.linear, command.angular
        self._cmd_vel.publish(twist)

    def _finish(self, success: bool, message: str) -> None:
        """End the run now with this verdict (unless it already had one)."""
        if self._run is not None:
            self._run.end(success, message)
            self._finish_if_ended()

    def _finish_if_ended(self) -> None:
        run, done = self._run, self._run_done
        if run is None or run.ending is None:
            return
        self._loop.take_run()
        self._run_done = None
        self._publish(STOP)
        outcome = run.outcome(self._loop.pose, self._now_s())
        summary = (f'{outcome.message} (elapsed {outcome.elapsed_s:.2f} s, max deviation '
                   f'{outcome.max_deviation:.4f} m, final error {outcome.final_error:.4f} m, '
                   f'heading error {outcome.final_heading_error:.4f} rad)')
        # Two call sites: rclpy refuses one call site logging at two severities.
        if outcome.success:
            self.get_logger().info(summary)
        else:
            self.get_logger().warning(summary)
        if run.plan.pen is None:
            done.set_result(outcome)
        else:  # a drawing answers once the pen is down again, as turtlesim starts it
            self._call_set_pen(self.settings.pen, down=True, then=lambda: done.set_result(outcome))

    def _now_s(self) -> float:
        return self.get_clock().now().nanoseconds * 1e-9

    # -- running a trajectory ----------------------------------------------------------------

    def _refusal(self) -> str | None:
        if self._run is not None:
            return (f'busy: {self._run.name} is running; wait for it or call '
                    f'{self.stop_service} (std_srvs/srv/Trigger) to stop it')
        silence = self._pose_silence_s()
        if self._loop.pose is None or silence > self.settings.pose_timeout_s:
            heard = 'never' if self._loop.pose is None else f'not for {silence:.1f} s'
            return (f'no pose on {self.pose_topic} ({heard}): is the simulator running and '
                    f'turtle_name right?')
        if self._cmd_vel.get_subscription_count() == 0:
            return (f'nothing subscribes to {self._cmd_vel.topic_name} yet: is the simulator '
                    f'running and turtle_name right?')
        return None

    def _pen_refusal(self, trajectory: Trajectory, plan: Plan) -> str | None:
        """Why a drawing cannot run here: turtlesim's set_pen is not there to lift the pen."""
        if plan.pen is not None and not self._set_pen.service_is_ready():
            return (f'{trajectory.name} refused: it lifts the pen between strokes, and the '
                    f'simulator service {self._set_pen.srv_name} is not available')
        return None

    def _begin(self, trajectory: Trajectory, request) -> Future | str:
        """Start a run: the future of its Outcome, or why it is refused (logged)."""
        refusal = self._refusal()
        if refusal is None:
            try:
                plan = planning.plan(trajectory.name, request, self._loop.pose, self.settings)
                refusal = self._pen_refusal(trajectory, plan)
            except PlanError as error:
                refusal = f'{trajectory.name} refused: {error}'
        if refusal is not None:
            self.get_logger().warning(refusal)
            return refusal
        self._loop.start(plan, arena=self.settings.arena, now_s=self._now_s())
        self._run_done = done = Future()
        path = plan.path
        self._publish_plan(path)
        self.get_logger().info(
            f'{trajectory.name}: {path.length:.2f} m of path, {math.degrees(path.turning):.0f} '
            f'deg of turns in place, at least {plan.lower_bound_s(self.settings.control):.1f} s')
        return done

    async def _execute(self, trajectory: Trajectory, request, response):
        """A trajectory service: refuse, or drive to the end; the response is filled either way."""
        started = self._begin(trajectory, request)
        if isinstance(started, str):
            return fill_response(response, Outcome(False, started, self._loop.pose))
        return fill_response(response, await started)

    # -- the draw action ---------------------------------------------------------------------

    def _on_cancel(self, goal_handle: ServerGoalHandle) -> CancelResponse:
        """Stop this goal's run at once (not another's); the goal then ends CANCELED."""
        run = self._goal_runs.get(bytes(goal_handle.goal_id.uuid))
        if run is not None and run is self._run:
            run.request_stop()
            self._finish_if_ended()
        return CancelResponse.ACCEPT

    async def _execute_goal(self, goal_handle: ServerGoalHandle) -> Draw.Result:
        goal = goal_handle.request
        if goal_handle.is_cancel_requested:  # cancelled before it started
            goal_handle.canceled()
            return fill_response(Draw.Result(), Outcome(False, 'cancelled before it started',
                                                         self._loop.pose))
        trajectory = BY_NAME.get(goal.trajectory)
        if trajectory is None:
            started = f'unknown trajectory {goal.trajectory!r}; known: {", ".join(BY_NAME)}'
            self.get_logger().warning(started)  # as `_begin` logs the other refusals
        else:
            started = self._begin(trajectory, goal)
        if isinstance(started, str):  # refused: busy, bad numbers, no simulator
            goal_handle.abort()
            return fill_response(Draw.Result(), Outcome(False, started, self._loop.pose))
        run, goal_id = self._run, bytes(goal_handle.goal_id.uuid)
        self._goal_runs[goal_id] = run
        feedback = self.create_timer(_FEEDBACK_PERIOD_S,
                                     lambda: goal_handle.publish_feedback(self._feedback(run)))
        try:
            outcome = await started
        finally:
            self.destroy_timer(feedback)
            del self._goal_runs[goal_id]
        if goal_handle.is_cancel_requested:
            goal_handle.canceled()
        elif outcome.success:
            goal_handle.succeed()
        else:
            goal_handle.abort()
        return fill_response(Draw.Result(), outcome)

    def _feedback(self, run: RunSupervisor) -> Draw.Feedback:
        pose = self._loop.pose or Pose2D(math.nan, math.nan, math.nan)
        return Draw.Feedback(
            progress=run.follower.progress(run.plan.control(self.settings.control)),
            distance=run.distance, elapsed=self._now_s() - run.started_s,
            deviation=run.deviation, x=pose.x, y=pose.y, theta=pose.theta)

    def _publish_plan(self, path: Path) -> None:
        msg = PathMsg()
        msg.header.frame_id = PLAN_FRAME_ID
        msg.header.stamp = self.get_clock().now().to_msg()
        points = path.points()
        # Every point up to _PLAN_POINTS (a Lissajous curve has 12 000); beyond, evenly
        # thinned, its last point kept.
        stride = math.ceil(len(points) / _PLAN_POINTS)
        for x, y in points[np.unique(np.r_[np.arange(0, len(points), stride), len(points) - 1])]:
            stamped = PoseStamped()
            stamped.header = msg.header
            stamped.pose.position.x, stamped.pose.position.y = float(x), float(y)
            msg.poses.append(stamped)
        self._plan.publish(msg)

    # -- services ----------------------------------------------------------------------------

    def _handle_stop(self, request: Trigger.Request, response: Trigger.Response):
        run = self._run
        self._publish(STOP)
        if run is None:
            response.success, response.message = True, 'nothing was running; turtle stopped'
        else:
            run.request_stop()
            self._finish_if_ended()
            response.success, response.message = True, f'stopped {run.name}'
        return response

    async def _handle_reset(self, request: Trigger.Request, response: Trigger.Response):
        if self._run is not None:
            self._finish(False, f'{self._run.name} aborted: reset requested')
        if not self._sim_reset.service_is_ready():
            response.message = (f'the simulator service {self._sim_reset.srv_name} is not '
                                 'available')
            return response
        future = self._sim_reset.call_async(Empty.Request())
        if not await self._wait_until(future.done, _RESET_TIMEOUT_S):
            future.cancel()
            response.message = (f'{self._sim_reset.srv_name} did not answer in '
                                f'{_RESET_TIMEOUT_S:g} s')
            return response
        # The simulator made a new turtle: forget the old one's pose and wait until the new
        # one's topics are connected, so that a trajectory requested next starts at once.
        self._loop.forget_pose()
        self._pose_time = None
        if await self._wait_until(self._connected, _RESET_TIMEOUT_S):
            response.success, response.message = True, 'simulator reset; ready'
        else:
            response.message = f'simulator reset, but not ready: {self._refusal()}'
        return response

    def _connected(self) -> bool:
        """A fresh pose is in, the simulator acknowledged a stop command (it hears us) and its
        set_pen is found (drawings need it).

        Sends that stop (harmless: no trajectory runs) while no acknowledgement is in.
        """
        if self._refusal() is not None or not self._set_pen.service_is_ready():
            return False
        if self._cmd_vel.wait_for_all_acked(Duration()):
            return True
        self._publish(STOP)
        return False

    async def _wait_until(self, condition, timeout_s: float) -> bool:
        """Await `condition()` for at most `timeout_s` of wall time.

        Polled on the node clock, so that on simulated time it is seen at the step it comes
        true, and on the steady clock, so that a clock that stands still (a vanished /clock
        source) still times out.
        """
        waited = Future()
        deadline = time.monotonic() + timeout_s

        def poll() -> None:
            if waited.done():
                return
            met = condition()
            if met or time.monotonic() > deadline:
                waited.set_result(met)

        timers = [self.create_timer(_POLL_PERIOD_S, poll),
                  self.create_timer(_POLL_PERIOD_S, poll,
                                    clock=Clock(clock_type=ClockType.STEADY_TIME))]
        try:
            poll()
            return await waited
        finally:
            for timer in timers:
                self.destroy_timer(timer)
