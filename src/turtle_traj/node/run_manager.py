"""The trajectory node's runs: one driven at a time, from the request to its outcome.

`RunManager` is not a Node: it owns the control loop, the lock over the run's state, the plan
being made (`PlanDesk`), the pose watchdog, the pen and the recording, and uses its node's
topics, clock and logger. The
services, the draw action and the commands reach it through `RunningNode` (`node.running`).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any

from nav_msgs.msg import Path as PathMsg
from rclpy.callback_groups import CallbackGroup
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from rclpy.task import Future

from turtle_traj.core.control.commands import STOP, Command
from turtle_traj.core.control.controllers.catalogue import ControllerChoice
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.loop import ControlLoop
from turtle_traj.core.control.observers import ODOMETRY_BASE, TURTLESIM
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.robot_model import COLD_START_LATE_STEPS
from turtle_traj.core.control.supervisor import Outcome, RunSupervisor
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import Settings
from turtle_traj.core.planning.planner import PlanError
from turtle_traj.core.registry import TrajectoryKind
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.node import outcomes
from turtle_traj.node.base_topics import BaseTopics
from turtle_traj.node.controller_tuning import ControllerTuning
from turtle_traj.node.pen_client import PenClient
from turtle_traj.node.plan_desk import PlanDesk, Planning
from turtle_traj.node.pose_silence import PoseSilence
from turtle_traj.node.state_lock import StateLock, serialized
from turtle_traj.node.waiting import completion
from turtle_traj.rosutils import offload
from turtle_traj.rosutils.clock_read import now_ns

WATCHDOG_PERIOD_S = 0.05
_STOPPED_EARLY = 'stopped by request before it started'


class RunManager:
    """Runs of one turtle on `node`: its pose in, its commands out, one run at a time.

    :param settings: the node's settings now (they change with its parameters).
    :param record_dir: a folder for a bag of each run, or None.
    """

    def __init__(self, node: Node, turtle: str, settings: Callable[[], Settings], *,
                 callback_group: CallbackGroup, record_dir: str | None = None) -> None:
        self._node = node
        self._settings = settings
        self.last_outcome: Outcome | None = None  # of the last run that ended
        self._silence = PoseSilence(node.get_clock(), WATCHDOG_PERIOD_S,
                                    held=lambda: offload.beside(node))
        self._run_done: Future | None = None  # what the run's handler awaits
        self._plans = PlanDesk(node)  # made beside the executor
        # Held by every change of the run's state: the handlers are reentrant, and on a
        # MultiThreadedExecutor run beside the timers and each other (a pose can end its run).
        self._state_lock = StateLock(node.get_logger())
        self._base = BaseTopics(node, turtle, self._on_pose)  # poses come once it spins
        self.pose_topic = self._base.pose_topic
        # on the wall clock the robot steps on its own timer, and a command can act late
        self._loop = ControlLoop(
            STEP_S, robot=ODOMETRY_BASE if self._base.odometry else TURTLESIM,
            late_prior=0.0 if node.get_clock().ros_time_is_active else COLD_START_LATE_STEPS)
        name = node.get_parameter('controller').value  # checked as it was declared
        self._tuning = ControllerTuning(node, name)
        self._controller = self._tuning.choose(name)
        self._plan = node.create_publisher(
            PathMsg, '~/plan', QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL))
        self._pen = PenClient(node, turtle, callback_group=callback_group)
        self._recording = None  # rosbags is loaded only when runs are recorded
        if record_dir:
            from turtle_traj.node.run_recording import RunRecording
            self._recording = RunRecording(node, self._base, Path(record_dir))

    @property
    def settings(self) -> Settings:
        return self._settings()

    def watch_arrivals(self, on_arrival: Callable[[], None]) -> None:
        """Call `on_arrival` as each pose is delivered (not for those a tick reads)."""
        self._base.on_arrival = on_arrival

    @property
    def command_topic(self) -> str:
        return self._base.publisher.topic_name

    @property
    def pose(self) -> Pose2D | None:
        """The driven turtle's latest pose (None before the first, or after a reset)."""
        return self._loop.pose

    @property
    def run(self) -> RunSupervisor | None:
        return self._loop.run

    @property
    def last_command(self) -> Command:
        """The command in effect once those sent have arrived: the last one sent."""
        return self._loop.model.last_sent

    @property
    def frame_id(self) -> str:
        """The frame of the poses read: the odometry's, or turtlesim's world."""
        return self._base.frame_id or outcomes.PLAN_FRAME_ID

    @property
    def pen_ready(self) -> bool:
        """The simulator's set_pen is found (drawings need it)."""
        return self._pen.ready

    def choose_controller(self, name: str) -> ControllerChoice:
        """The controller `name` stands for, tuned by the node's parameters.

        :raises UnknownController: with the reason.
        """
        return self._tuning.choose(name)

    def now_s(self) -> float:
        """The node clock, seconds."""
        return now_ns(self._node.get_clock()) * 1e-9

    @serialized
    def _on_pose(self, pose: Pose2D, linear_echo: float, angular_echo: float) -> None:
        self._loop.observe(pose, linear_echo, angular_echo, self._silence.seconds())
        self._finish_if_ended()  # a jump ends the run
        self._silence.heard()

    @serialized
    def on_control_timer(self) -> None:
        """The control timer's tick: this period's command for the run, if one runs."""
        self._base.read_waiting()
        run = self.run
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
        if answered and run is self.run:
            run.pen_is(down)

    @serialized
    def on_watchdog(self) -> None:
        """The watchdog's beat (steady clock): the pen's answer and the poses, in time. The
        poses waiting are read first, as the control tick reads them: after this process was
        starved, its executor can run the clock's update and then this timer before the poses
        that wait in their queue, and the node clock would show a silence that was not there."""
        self._silence.beat()
        if self._pen.give_up_if_late():
            self.abort_run(f'{self._pen.service_name} did not answer within '
                           f'{self._pen.timeout_s:g} s; is the simulator still running?',
                           Ending.NO_SIMULATOR)
        if self.run is not None:
            self._base.read_waiting()
            self._aborted_for_silence()

    def _aborted_for_silence(self) -> bool:
        """End the run if the poses have been silent past pose_timeout; whether it did. Checked
        on each tick (node clock: in lock-step, simulated seconds pass between two wall-clock
        beats) and each beat of the watchdog (a vanished simulator stops the node clock too)."""
        silence, timeout_s = self._silence.seconds(), self.settings.pose_timeout_s
        if silence > timeout_s:
            self.abort_run(f'no pose on {self.pose_topic} for {silence:.2f} s (pose_timeout '
                           f'{timeout_s:g} s); is the simulator still running?', Ending.POSE_LOST)
        return silence > timeout_s

    @serialized
    def shutdown_turtle(self) -> Future | None:
        """End any run and leave the turtle standing (on program exit). The run's end, if one
        ran: it completes once a drawing's pen is down again (a call to the simulator), which
        a program must wait for before its node goes, or the call may never leave it."""
        done = self._run_done
        self.abort_run('the node is shutting down', Ending.SHUTTING_DOWN)
        self._publish(STOP)
        return done

    @serialized
    def abort_run(self, why: str, reason: Ending) -> None:
        """End the run, or the plan being made, as failed for `reason`: '<trajectory> aborted:
        <why>'."""
        self._plans.drop(f'aborted: {why}', reason)
        if self.run is not None:
            self.run.end(False, f'{self.run.name} aborted: {why}', reason)
            self._finish_if_ended()

    @serialized
    def stop(self) -> str:
        """Stop the turtle, and the run if one runs; what was stopped."""
        run = self.run
        self._publish(STOP)
        if run is None:
            name = self._plans.drop(_STOPPED_EARLY, Ending.STOPPED)
            if name is not None:
                return f'stopped {name} while it was being planned'
            return 'nothing was running; turtle stopped'
        self.stop_run(run)
        return f'stopped {run.name}'

    @serialized
    def send_stop(self) -> None:
        """Publish a stop (harmless while no run is driven)."""
        self._publish(STOP)

    def _publish(self, command: Command) -> None:
        self._loop.sent(command, self.now_s())
        self._base.publish(command)

    def _finish_if_ended(self, *, stop: bool = True) -> None:
        """Report the run if it has ended, and stop the turtle (unless a new run takes over)."""
        run, done = self.run, self._run_done
        if run is None or run.ending is None:
            return
        self._loop.take_run()
        self._run_done = None
        if stop:
            self._publish(STOP)
        if self._recording is not None:
            self._recording.stop()
        self.last_outcome = outcome = run.outcome(self._loop.pose, self.now_s())
        if outcome.success:
            self._state_lock.info(outcomes.summary(outcome))
        else:
            self._state_lock.warning(outcomes.summary(outcome))
        if run.plan.pen is None:
            done.set_result(outcome)
        else:  # a drawing answers once the pen is down again, as turtlesim starts it
            self._pen.set(self.settings.pen, down=True,
                          then=lambda _answered: done.set_result(outcome))

    def refusal(self, replacing: RunSupervisor | None = None) -> outcomes.RunRefused | None:
        """Why a request would be refused now (None: it would be accepted), one that replaces
        the run `replacing` if it still runs."""
        busy = None
        if self.run is not None and self.run is not replacing:
            busy = f'{self.run.name} is running'
        elif self._plans.current is not None:
            busy = f'{self._plans.current.name} is being planned'
        if busy is not None:
            return outcomes.RunRefused(
                f'busy: {busy}; wait for it or call '
                f'{self._node.resolve_service_name("~/stop")} (std_srvs/srv/Trigger) to stop it',
                Ending.BUSY)
        silence = self._silence.seconds()
        if self._loop.pose is None or silence > self.settings.pose_timeout_s:
            heard = 'never' if self._loop.pose is None else f'not for {silence:.1f} s'
            return outcomes.RunRefused(f'no pose on {self.pose_topic} ({heard}): is the '
                                       'simulator running and turtle_name right?',
                                       Ending.POSE_LOST)
        if self._base.publisher.get_subscription_count() == 0:
            return outcomes.RunRefused(f'nothing subscribes to {self.command_topic} yet: is the '
                                       'simulator running and turtle_name right?',
                                       Ending.NO_SIMULATOR)
        return None

    @serialized
    def refuse(self, message: str, reason: Ending) -> outcomes.RunRefused:
        """The refusal of a request for `reason`, logged."""
        self._state_lock.warning(message)
        return outcomes.RunRefused(message, reason)

    async def start_run(self, kind: TrajectoryKind, request, *,
                        controller: ControllerChoice | None = None,
                        replacing: RunSupervisor | None = None) -> tuple[RunSupervisor, Future]:
        """Plan `request` and drive it (with `controller`, or the node's): the run, and the
        future of its Outcome.

        The plan is made beside the executor (a text with rounded corners takes seconds), which
        meanwhile answers parameters and hears poses. The node is busy from the request on. A
        request `replacing` a run lets that run drive on while it is planned, then takes over
        from it without a stop (the run ends REPLACED); if it no longer runs, it starts anew.

        :raises RunRefused: busy, a request that cannot be planned, no simulator, or stopped
            while it was being planned (logged).
        """
        planning = self._begin_planning(kind, request, replacing)
        try:
            plan = await completion(self._node, planning.plan)
        except PlanError as error:
            raise self.refuse(f'{kind.name} refused: {error}', Ending.INVALID_REQUEST) from None
        finally:
            self._done_planning(planning)
        return self._start_planned(kind, planning, plan, controller or self._controller,
                                   replacing)

    @serialized
    def _begin_planning(self, kind: TrajectoryKind, request,
                        replacing: RunSupervisor | None) -> Planning:
        refusal = self.refusal(replacing)
        if refusal is not None:
            raise self.refuse(str(refusal), refusal.reason)
        # a path that takes over from a run starts at the speed the robot drives
        moving = replacing is not None and replacing is self.run
        speed = abs(self.last_command.linear) if moving else 0.0
        return self._plans.begin(kind.name, request, self._loop.pose, self.settings, speed)

    @serialized
    def _done_planning(self, planning: Planning) -> None:
        self._plans.done(planning)

    @serialized
    def _start_planned(self, kind: TrajectoryKind, planning: Planning, plan: Plan | None,
                       controller: ControllerChoice,
                       replacing: RunSupervisor | None) -> tuple[RunSupervisor, Future]:
        if plan is None:  # its future was cancelled: stopped or aborted
            raise self.refuse(f'{kind.name} {planning.ended}', planning.reason)
        if plan.pen is not None and not self._pen.ready:
            raise self.refuse(f'{kind.name} refused: it lifts the pen between strokes, and the '
                              f'simulator service {self._pen.service_name} is not available',
                              Ending.NO_SIMULATOR)
        settings = planning.settings
        if replacing is not None and replacing is self.run:  # it hands over, moving
            replacing.end(False, f'{replacing.name} replaced by {kind.name}', Ending.REPLACED)
            self._finish_if_ended(stop=False)
        self._silence.was_busy()  # the plan's wall time is not the simulator's silence
        run = self._loop.start(plan, arena=settings.arena, now_s=self.now_s(),
                               controller=controller)
        self._run_done = done = Future()
        if self._recording is not None:
            self._recording.start(kind.name, settings.control)
        message = planning.message  # made with the plan (`plan_desk`)
        assert message is not None
        message.header.stamp = self._node.get_clock().now().to_msg()  # its poses' header too
        self._plan.publish(message)
        self._state_lock.info(f'{kind.name}: {outcomes.describe(plan, settings.control)}')
        return run, done

    @serialized
    def stop_run(self, run: RunSupervisor, reason: Ending = Ending.STOPPED) -> None:
        """End `run` at once as stopped by request (`reason`: a stop or a cancel), if it is
        still the one running."""
        if run is self.run:
            run.request_stop(reason)
            self._finish_if_ended()

    @serialized
    def stop_planning(self, request: Any, reason: Ending = Ending.STOPPED) -> None:
        """End the plan being made for `request`, if it still is, as stopped by request."""
        self._plans.drop(_STOPPED_EARLY, reason, request)

    @serialized
    def forget_turtle(self) -> None:
        """The simulator made a new turtle: no pose until its first one (a reset)."""
        self._loop.forget_pose()
        self._silence.forget()

    def commands_heard(self) -> bool:
        """The simulator acknowledged every command sent (a question: it sends nothing)."""
        return self._base.publisher.wait_for_all_acked(Duration())
