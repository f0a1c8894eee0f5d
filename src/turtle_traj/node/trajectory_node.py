"""TrajectoryNode: one service per trajectory, the draw action, a control timer, live parameters.

Service handlers validate and plan, hand the path to the control timer and await its end; the
timer steps the pure PathFollower on the latest pose. A watchdog aborts a trajectory when poses
stop arriving (see `PoseSilence`).
"""

from __future__ import annotations

from functools import partial
from pathlib import Path

from nav_msgs.msg import Path as PathMsg
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.clock import Clock, ClockType
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from rclpy.task import Future
from std_msgs.msg import Header

from turtle_traj.core.control.commands import STOP, Command
from turtle_traj.core.control.loop import ControlLoop
from turtle_traj.core.control.supervisor import RunSupervisor
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.planning import planner as planning
from turtle_traj.core.planning.planner import PlanError
from turtle_traj.core.registry import TRAJECTORIES, TrajectoryKind
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.node import outcomes, parameters
from turtle_traj.node.base_topics import BaseTopics
from turtle_traj.node.commands import CommandServices
from turtle_traj.node.draw_action import DrawActionServer
from turtle_traj.node.pen_client import PenClient
from turtle_traj.node.pose_silence import PoseSilence
from turtle_traj.node.state_lock import StateLock, serialized
from turtle_traj.node.trajectory_services import TrajectoryServices

_WATCHDOG_PERIOD_S = 0.05


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
        try:
            parameters.declare(self)
        except Exception:  # a refused override: nothing is left behind for the collector
            self.destroy_node()
            raise
        self.settings = parameters.read_settings(self)
        self.add_post_set_parameters_callback(self._on_parameters_set)
        turtle = self.get_parameter('turtle_name').value

        self._silence = PoseSilence(self.get_clock(), _WATCHDOG_PERIOD_S)
        self._run_done: Future | None = None  # what the run's handler awaits
        # Held by every change of the run's state: the handlers are reentrant, and on a
        # MultiThreadedExecutor run beside the timers and each other (a pose can end its run).
        self._state_lock = StateLock(self.get_logger())

        self._base = BaseTopics(self, turtle, self._on_pose)
        self.pose_topic = self._base.pose_topic
        self._cmd_vel = self._base.publisher
        # an odometry reports measured velocities, not the command in effect
        self._loop.model.echoes = not self._base.odometry
        self._plan = self.create_publisher(
            PathMsg, '~/plan', QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))

        # Handlers await the end of a trajectory, so they must not block the timer's group.
        group = ReentrantCallbackGroup()
        TrajectoryServices(self, group)  # ~/draw_square, ...: one per registry entry
        self._draw_action = DrawActionServer(self, group)
        self._commands = CommandServices(self, group)  # ~/stop and ~/reset
        self.stop_service = self._commands.stop_service
        self._pen = PenClient(self, turtle, callback_group=group)  # drawings lift the pen
        self._recording = None  # each run a bag, when record_dir is set (rosbags loaded then)
        if record_dir := self.get_parameter('record_dir').value:
            from turtle_traj.node.run_recording import RunRecording
            self._recording = RunRecording(self, turtle, Path(record_dir))

        self.create_timer(1.0 / self.get_parameter('control_rate').value,
                          self._on_control_timer)
        self.create_timer(_WATCHDOG_PERIOD_S, self._on_watchdog,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        name = self.get_fully_qualified_name()
        self.get_logger().info(
            f'serving {len(TRAJECTORIES)} trajectories on {name}/<service> and the action '
            f'{self._draw_action.name}; driving {self._cmd_vel.topic_name} from '
            f'{self.pose_topic}')

    def _on_parameters_set(self, _parameters) -> None:
        self.settings = parameters.read_settings(self)

    @serialized
    def _on_pose(self, pose: Pose2D, linear_echo: float, angular_echo: float) -> None:
        self._loop.observe(pose, linear_echo, angular_echo)
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
        if (draw_action := getattr(self, '_draw_action', None)) is not None:
            draw_action.destroy()
        super().destroy_node()

    @property
    def ready(self) -> bool:
        """A fresh pose is in and nothing is running: a request would be accepted."""
        return self.refusal() is None

    @serialized
    def _on_control_timer(self) -> None:
        run = self._run
        if run is not None and self._aborted_for_silence():
            return
        command = self._loop.command(self.settings.control, self.settings.arena, self.now_s())
        if run is None:
            return
        if command is None:
            self._finish_if_ended()  # which sends the stop
            return
        self._publish(command)
        if run.pen_wanted is not None and not self._pen.busy:
            self._pen.set(run.plan.pen, down=run.pen_wanted,
                          then=partial(self._pen_answered, run, run.pen_wanted))

    @serialized
    def _pen_answered(self, run: RunSupervisor, down: bool, answered: bool) -> None:
        if answered and run is self._run:
            run.pen_is(down)

    @serialized
    def _on_watchdog(self) -> None:
        self._silence.beat()
        if self._pen.give_up_if_late():
            self.abort_run(f'{self._pen.service_name} did not answer within '
                           f'{self._pen.timeout_s:g} s; is the simulator still running?')
        if self._run is not None:
            self._aborted_for_silence()

    def _aborted_for_silence(self) -> bool:
        """End the run if the poses have been silent past pose_timeout; whether it did. Checked
        on each tick (node clock: in lock-step, simulated seconds pass between two wall-clock
        beats) and each beat of the watchdog (a vanished simulator stops the node clock too)."""
        silence, timeout_s = self._silence.seconds(), self.settings.pose_timeout_s
        if silence > timeout_s:
            self.abort_run(f'no pose on {self.pose_topic} for {silence:.2f} s (pose_timeout '
                           f'{timeout_s:g} s); is the simulator still running?')
        return silence > timeout_s

    @serialized
    def shutdown_turtle(self) -> None:
        """End any trajectory and leave the turtle standing (called on program exit)."""
        self.abort_run('the node is shutting down')
        self._publish(STOP)

    @serialized
    def abort_run(self, why: str) -> None:
        """End the run, if one runs, as failed: '<trajectory> aborted: <why>'."""
        if self._run is not None:
            self._finish(False, f'{self._run.name} aborted: {why}')

    @serialized
    def stop(self) -> str:
        """Stop the turtle, and the run if one runs; what was stopped."""
        run = self._run
        self._publish(STOP)
        if run is None:
            return 'nothing was running; turtle stopped'
        self.stop_run(run)
        return f'stopped {run.name}'

    def _publish(self, command: Command) -> None:
        self._loop.sent(command, self.now_s())
        self._base.publish(command)

    @serialized
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
        if outcome.success:
            self._state_lock.info(outcomes.summary(outcome))
        else:
            self._state_lock.warning(outcomes.summary(outcome))
        if run.plan.pen is None:
            done.set_result(outcome)
        else:  # a drawing answers once the pen is down again, as turtlesim starts it
            self._pen.set(self.settings.pen, down=True,
                          then=lambda _answered: done.set_result(outcome))

    def now_s(self) -> float:
        """The node clock, seconds."""
        return self.get_clock().now().nanoseconds * 1e-9

    def refusal(self) -> str | None:
        """Why a request would be refused now (None: it would be accepted)."""
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

    @serialized
    def refuse(self, reason: str) -> outcomes.RunRefused:
        """The refusal of a request, logged."""
        self._state_lock.warning(reason)
        return outcomes.RunRefused(reason)

    @serialized
    def start_run(self, kind: TrajectoryKind, request) -> tuple[RunSupervisor, Future]:
        """Plan `request` and drive it: the run, and the future of its Outcome.

        :raises RunRefused: busy, a request that cannot be planned, or no simulator (logged).
        """
        refusal = self.refusal()
        if refusal is not None:
            raise self.refuse(refusal)
        try:
            plan = planning.plan(kind.name, request, self._loop.pose, self.settings)
        except PlanError as error:
            raise self.refuse(f'{kind.name} refused: {error}') from None
        if plan.pen is not None and not self._pen.ready:
            raise self.refuse(f'{kind.name} refused: it lifts the pen between strokes, and the '
                              f'simulator service {self._pen.service_name} is not available')
        self._silence.was_busy()  # planning held the executor: the poses wait in its queue
        run = self._loop.start(plan, arena=self.settings.arena, now_s=self.now_s())
        self._run_done = done = Future()
        if self._recording is not None:
            self._recording.start(kind.name, self.settings.control)
        self._plan.publish(outcomes.plan_message(plan.path, Header(
            frame_id=outcomes.PLAN_FRAME_ID, stamp=self.get_clock().now().to_msg())))
        self._state_lock.info(f'{kind.name}: {outcomes.describe(plan, self.settings.control)}')
        return run, done

    @serialized
    def stop_run(self, run: RunSupervisor) -> None:
        """End `run` at once as stopped by request, if it is still the one running."""
        if run is self._run:
            run.request_stop()
            self._finish_if_ended()

    @serialized
    def forget_turtle(self) -> None:
        """The simulator made a new turtle: no pose until its first one (a reset)."""
        self._loop.forget_pose()
        self._silence.forget()

    @property
    def pen_ready(self) -> bool:
        """The simulator's set_pen is found (drawings need it)."""
        return self._pen.ready

    @serialized
    def commands_heard(self) -> bool:
        """The simulator acknowledged every command sent; a stop is sent (harmless while no
        trajectory runs) when not, for the next check."""
        if self._cmd_vel.wait_for_all_acked(Duration()):
            return True
        self._publish(STOP)
        return False
