"""TrajectoryNode: one service per trajectory, the draw action, a control timer, live parameters.

Service handlers validate and plan, hand the path to the control timer and await its end; the
timer steps the pure PathFollower on the latest pose. A watchdog aborts a trajectory when poses
stop arriving (see `PoseSilence`).
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable
from functools import partial, wraps
from pathlib import Path
from typing import Any, TypeVar

from geometry_msgs.msg import Twist
from nav_msgs.msg import Path as PathMsg
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.clock import Clock, ClockType
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from rclpy.task import Future
from std_msgs.msg import Header
from std_srvs.srv import Empty, Trigger
from turtlesim.msg import Pose

from turtle_traj.api.ros_interface import service_type
from turtle_traj.core.control.commands import STOP, Command
from turtle_traj.core.control.loop import ControlLoop
from turtle_traj.core.control.supervisor import Outcome, RunSupervisor
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.planning.planner import PlanError
from turtle_traj.core.registry import TRAJECTORIES, TrajectoryKind
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.node import parameters
from turtle_traj.node.async_service import create_async_service
from turtle_traj.node.draw_action import DrawActionServer
from turtle_traj.node.outcomes import PLAN_FRAME_ID, RunRefused, fill_response, plan_message
from turtle_traj.node.pen_client import PenClient
from turtle_traj.node.pose_silence import PoseSilence
from turtle_traj.node.waiting import completion, wait_until
from turtle_traj.rosutils.qos import POSE_READER_QOS, TURTLE_TOPIC_QOS

_WATCHDOG_PERIOD_S = 0.05
_RESET_TIMEOUT_S = 5.0
_Method = TypeVar('_Method', bound=Callable[..., Any])


def _serialized(method: _Method) -> _Method:
    """Run `method` holding the node's state lock (see TrajectoryNode.__init__)."""
    @wraps(method)
    def locked(self: TrajectoryNode, *args: Any, **kwargs: Any) -> Any:
        with self._state_lock:
            return method(self, *args, **kwargs)
    return locked  # type: ignore[return-value]


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

        self._silence = PoseSilence(self.get_clock(), _WATCHDOG_PERIOD_S)
        # The future the run's service handler awaits.
        self._run_done: Future | None = None
        # Every change of the run's state (a pose, a tick, a request's check-and-claim, a stop,
        # a reset, the pen's answer) holds this lock: the handlers are reentrant, and on a
        # MultiThreadedExecutor they run beside the timers and each other. Uncontended on the
        # single-threaded executors. Reentrant: a pose can end the run it updates.
        self._state_lock = threading.RLock()

        self.pose_topic = self.resolve_topic_name(f'{turtle}/pose')
        self.create_subscription(Pose, f'{turtle}/pose', self._on_pose, POSE_READER_QOS)
        self._cmd_vel = self.create_publisher(Twist, f'{turtle}/cmd_vel', TURTLE_TOPIC_QOS)
        self._twist = Twist()
        self._plan = self.create_publisher(
            PathMsg, '~/plan', QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))

        # Handlers await the end of a trajectory, so they must not block the timer's group.
        group = ReentrantCallbackGroup()
        for kind in TRAJECTORIES:
            create_async_service(self, service_type(kind), f'~/{kind.service}',
                                 partial(self._execute, kind), callback_group=group)
        self._draw_action = DrawActionServer(self, group)
        self.create_service(Trigger, '~/stop', self._handle_stop, callback_group=group)
        create_async_service(self, Trigger, '~/reset', self._handle_reset, callback_group=group)
        self.stop_service = self.resolve_service_name('~/stop')
        self._sim_reset = self.create_client(Empty, 'reset', callback_group=group)
        self._pen = PenClient(self, turtle, callback_group=group)  # drawings lift the pen
        self._recording = None  # each run a bag, when record_dir is set (rosbags loaded then)
        if self.get_parameter('record_dir').value:
            from turtle_traj.node.run_recording import RunRecording
            self._recording = RunRecording(self, turtle,
                                           Path(self.get_parameter('record_dir').value))

        self.create_timer(1.0 / self.get_parameter('control_rate').value,
                          self._on_control_timer)
        self.create_timer(_WATCHDOG_PERIOD_S, self._on_watchdog,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        name = self.get_fully_qualified_name()
        self.get_logger().info(
            f'serving {len(TRAJECTORIES)} trajectories on {name}/<service> and the action '
            f'{self._draw_action.name}; driving {self.pose_topic.removesuffix("/pose")}')

    # -- inputs ------------------------------------------------------------------------------

    def _on_parameters_set(self, _parameters) -> None:
        self.settings = parameters.read_settings(self)

    @_serialized
    def _on_pose(self, msg: Pose) -> None:
        self._loop.observe(Pose2D(msg.x, msg.y, msg.theta), msg.linear_velocity,
                           msg.angular_velocity)
        self._finish_if_ended()  # a jump ends the run
        self._silence.heard()

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

    def destroy_node(self) -> None:
        self._draw_action.destroy()
        super().destroy_node()

    @property
    def ready(self) -> bool:
        """A fresh pose is in and nothing is running: a request would be accepted."""
        return self._refusal() is None

    # -- control -----------------------------------------------------------------------------

    @_serialized
    def _on_control_timer(self) -> None:
        run = self._run
        if run is None or self._aborted_for_silence():
            return
        command = self._loop.command(self.settings.control, self.settings.arena, self.now_s())
        if command is None:
            self._finish_if_ended()  # which sends the stop
            return
        self._publish(command)
        wanted = run.pen_wanted
        if wanted is not None and not self._pen.busy:
            def answered(ok: bool) -> None:
                with self._state_lock:
                    if ok and run is self._run:
                        run.pen_is(wanted)
            self._pen.set(run.plan.pen, down=wanted, then=answered)

    @_serialized
    def _on_watchdog(self) -> None:
        self._silence.beat()
        if self._pen.give_up_if_late() and self._run is not None:
            self._finish(False, f'{self._run.name} aborted: {self._pen.service_name} did not '
                                f'answer within {self._pen.timeout_s:g} s; is the simulator '
                                'still running?')
        if self._run is not None:
            self._aborted_for_silence()

    def _aborted_for_silence(self) -> bool:
        """End the run if the poses have been silent past pose_timeout; whether it did.

        Checked on each control tick, on the node clock: in lock-step, simulated seconds can
        pass between two beats of the wall-clock watchdog (a step with no turtle to drive takes
        microseconds). And on the watchdog's beat, which catches a vanished simulator that also
        stopped the node clock.
        """
        silence = self._silence.seconds()
        if silence <= self.settings.pose_timeout_s:
            return False
        self._finish(False, f'{self._run.name} aborted: no pose on {self.pose_topic} for '
                            f'{silence:.2f} s (pose_timeout {self.settings.pose_timeout_s:g} '
                            's); is the simulator still running?')
        return True

    @_serialized
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

    @_serialized
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
        if self._recording is not None:
            self._recording.stop()
        outcome = run.outcome(self._loop.pose, self.now_s())
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
            self._pen.set(self.settings.pen, down=True,
                          then=lambda _answered: done.set_result(outcome))

    def now_s(self) -> float:
        """The node clock, seconds."""
        return self.get_clock().now().nanoseconds * 1e-9

    # -- running a trajectory ----------------------------------------------------------------

    def _refusal(self) -> str | None:
        if self._run is not None:
            return (f'busy: {self._run.name} is running; wait for it or call '
                    f'{self.stop_service} (std_srvs/srv/Trigger) to stop it')
        silence = self._silence.seconds()
        if self._loop.pose is None or silence > self.settings.pose_timeout_s:
            heard = 'never' if self._loop.pose is None else f'not for {silence:.1f} s'
            return (f'no pose on {self.pose_topic} ({heard}): is the simulator running and '
                    f'turtle_name right?')
        if self._cmd_vel.get_subscription_count() == 0:
            return (f'nothing subscribes to {self._cmd_vel.topic_name} yet: is the simulator '
                    f'running and turtle_name right?')
        return None

    def refuse(self, reason: str) -> RunRefused:
        """The refusal of a request, logged."""
        self.get_logger().warning(reason)
        return RunRefused(reason)

    @_serialized
    def start_run(self, kind: TrajectoryKind, request) -> tuple[RunSupervisor, Future]:
        """Plan `request` and drive it: the run, and the future of its Outcome.

        :raises RunRefused: busy, a request that cannot be planned, or no simulator (logged).
        """
        refusal = self._refusal()
        if refusal is not None:
            raise self.refuse(refusal)
        try:
            plan = planning.plan(kind.name, request, self._loop.pose, self.settings)
        except PlanError as error:
            raise self.refuse(f'{kind.name} refused: {error}') from None
        if plan.pen is not None and not self._pen.ready:
            raise self.refuse(f'{kind.name} refused: it lifts the pen between strokes, and the '
                              f'simulator service {self._pen.service_name} is not available')
        run = self._loop.start(plan, arena=self.settings.arena, now_s=self.now_s())
        self._run_done = done = Future()
        path = plan.path
        if self._recording is not None:
            self._recording.start(kind.name, self.settings.control)
        self._plan.publish(plan_message(path, Header(frame_id=PLAN_FRAME_ID,
                                                     stamp=self.get_clock().now().to_msg())))
        self.get_logger().info(
            f'{kind.name}: {path.length:.2f} m of path, {math.degrees(path.turning):.0f} '
            f'deg of turns in place, at least {plan.lower_bound_s(self.settings.control):.1f} s')
        return run, done

    @_serialized
    def stop_run(self, run: RunSupervisor) -> None:
        """End `run` at once as stopped by request, if it is still the one running."""
        if run is self._run:
            run.request_stop()
            self._finish_if_ended()

    async def _execute(self, kind: TrajectoryKind, request, response):
        """A trajectory service: refuse, or drive to the end; the response is filled either way."""
        try:
            _run, finished = self.start_run(kind, request)
        except RunRefused as refusal:
            return fill_response(response, Outcome(False, str(refusal), self._loop.pose))
        return fill_response(response, await completion(self, finished))

    # -- services ----------------------------------------------------------------------------

    @_serialized
    def _handle_stop(self, request: Trigger.Request, response: Trigger.Response):
        run = self._run
        self._publish(STOP)
        if run is None:
            response.success, response.message = True, 'nothing was running; turtle stopped'
        else:
            self.stop_run(run)
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
        if not await wait_until(self, future.done, _RESET_TIMEOUT_S):
            future.cancel()
            response.message = (f'{self._sim_reset.srv_name} did not answer in '
                                f'{_RESET_TIMEOUT_S:g} s')
            return response
        # The simulator made a new turtle: forget the old one's pose and wait until the new
        # one's topics are connected, so that a trajectory requested next starts at once.
        with self._state_lock:
            self._loop.forget_pose()
            self._silence.forget()
        if await wait_until(self, self._connected, _RESET_TIMEOUT_S):
            response.success, response.message = True, 'simulator reset; ready'
        else:
            response.message = f'simulator reset, but not ready: {self._refusal()}'
        return response

    @_serialized
    def _connected(self) -> bool:
        """A fresh pose is in, the simulator acknowledged a stop command (it hears us) and its
        set_pen is found (drawings need it).

        Sends that stop (harmless: no trajectory runs) while no acknowledgement is in.
        """
        if self._refusal() is not None or not self._pen.ready:
            return False
        if self._cmd_vel.wait_for_all_acked(Duration()):
            return True
        self._publish(STOP)
        return False
