"""TrajectoryNode: one service per trajectory, the draw action, a control timer, live parameters.

The node declares its parameters and wires its topics, services, action and timers to a
`RunManager`, which drives one run at a time: service handlers plan and await a run's end, the
control timer steps the pure control loop on the latest pose, and a watchdog aborts a run when
poses stop arriving (see `PoseSilence`).
"""

from __future__ import annotations

import threading

from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.task import Future

from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.profile import load_solver, solver_loaded
from turtle_traj.core.control.supervisor import Outcome
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.registry import TRAJECTORIES
from turtle_traj.node import parameters
from turtle_traj.node.commands import CommandServices
from turtle_traj.node.control_timer import ControlTimer
from turtle_traj.node.draw_action import DrawActionServer
from turtle_traj.node.lease import LeaseWatch
from turtle_traj.node.run_manager import WATCHDOG_PERIOD_S, RunManager
from turtle_traj.node.trajectory_services import TrajectoryServices


class TrajectoryNode(Node):
    """Drives one turtle along trajectories on request (node name `turtle_traj`)."""

    def __init__(self, node_name: str = 'turtle_traj', *, follow_path: bool = True,
                 **kwargs) -> None:
        """:param follow_path: serve Nav2's FollowPath action (`nav2_follow_path`); a managed
        controller server serves it on its own node instead."""
        super().__init__(node_name, **kwargs)
        self._runs: RunManager | None = None
        # The validator goes first so that overrides given at start-up are checked too; a new
        # arena must contain the turtle.
        self.add_on_set_parameters_callback(
            lambda params: parameters.validate(self, params, self.pose))
        try:
            parameters.declare(self)
        except Exception:  # a refused override: nothing is left behind for the collector
            self.destroy_node()
            raise
        self.settings = parameters.read_settings(self)
        self.add_post_set_parameters_callback(self._on_parameters_set)
        self._solver_loader: threading.Thread | None = None
        if self.settings.control.limited:
            load_solver()  # before the node serves: no run can meet the import (see below)

        # Handlers await the end of a trajectory, so they must not block the timer's group.
        group = ReentrantCallbackGroup()
        self._runs = runs = RunManager(
            self, self.get_parameter('turtle_name').value, lambda: self.settings,
            callback_group=group, record_dir=self.get_parameter('record_dir').value or None)
        self.pose_topic = runs.pose_topic
        TrajectoryServices(self, runs, group)  # ~/draw_square, ...: one per registry entry
        self._draw_action = DrawActionServer(self, runs, group)
        self._nav2 = _nav2_follow_path(self, runs, group) if follow_path else None
        self._commands = CommandServices(self, runs, group)  # ~/stop and ~/reset
        self._lease = LeaseWatch(self, lambda why: self.abort_run(why))  # ~/lease
        self.stop_service = self._commands.stop_service

        self._control = ControlTimer(self, 1.0 / self.get_parameter('control_rate').value,
                                     runs.on_control_timer, lambda: self.busy)
        runs.watch_arrivals(self._control.pose_arrived)
        self.create_timer(WATCHDOG_PERIOD_S, runs.on_watchdog,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        name = self.get_fully_qualified_name()
        self.get_logger().info(
            f'serving {len(TRAJECTORIES)} trajectories on {name}/<service> and the action '
            f'{self._draw_action.name}; driving {runs.command_topic} from {self.pose_topic}')

    def _on_parameters_set(self, _parameters) -> None:
        self.settings = parameters.read_settings(self)
        self._load_solver_if_limited()

    def _load_solver_if_limited(self) -> None:
        """On a base with acceleration limits, runs are planned with TOPP-RA, whose import
        takes 2.4-2.7 s: a node given limits at start-up imports it before it serves, and one
        given them live imports it beside the executor. In a first run, its time went by with
        the turtle standing (a simulator on its own clock at 5x counted 12 s without progress,
        and the watchdog aborted the run); beside a run, the import's long steps in C held
        Python's lock from the node's callbacks (poses unread for 0.2 s of wall time, 1.2 s
        at 5x: the run aborted for pose silence, 2 runs in 3 as two programs at 5x)."""
        if (self.settings.control.limited and self._solver_loader is None
                and not solver_loaded()):
            self._solver_loader = threading.Thread(target=load_solver, name='load_solver')
            self._solver_loader.start()

    @property
    def runs(self) -> RunManager:
        """What drives the runs, for a server that serves requests on a node of its own."""
        return self._runs

    @property
    def pose(self) -> Pose2D | None:
        """The driven turtle's latest pose (None before the first, or after a reset)."""
        return self._runs.pose if self._runs is not None else None

    @property
    def last_outcome(self) -> Outcome | None:
        """How the last run that ended ended, figures included (for in-process callers)."""
        return self._runs.last_outcome

    @property
    def busy(self) -> bool:
        return self._runs.run is not None

    @property
    def ready(self) -> bool:
        """A fresh pose is in and nothing is running: a request would be accepted."""
        return self._runs.refusal() is None

    def stop(self) -> str:
        """Stop the turtle, and the run if one runs; what was stopped."""
        return self._runs.stop()

    def abort_run(self, why: str, reason: Ending = Ending.STOPPED) -> None:
        """End the run, if one runs, as failed for `reason` (by default: stopped by the
        program holding the node): '<trajectory> aborted: <why>'."""
        self._runs.abort_run(why, reason)

    def shutdown_turtle(self) -> Future | None:
        """End any trajectory and leave the turtle standing (called on program exit); what to
        wait for before the node goes (`RunManager.shutdown_turtle`)."""
        return self._runs.shutdown_turtle()

    def now_s(self) -> float:
        """The node clock, seconds."""
        return self._runs.now_s()

    def destroy_node(self) -> None:
        for server in (getattr(self, '_draw_action', None), getattr(self, '_nav2', None)):
            if server is not None:
                server.destroy()
        super().destroy_node()


def _nav2_follow_path(node: Node, runs: RunManager, group) -> object | None:
    """Nav2's FollowPath action, where nav2_msgs is installed (ours or Nav2's)."""
    try:
        from turtle_traj.node.nav2_follow_path import Nav2FollowPath
    except ImportError as error:  # a colcon build without Nav2 or our interfaces/nav2_msgs
        node.get_logger().info(f'no Nav2 FollowPath action: {error}')
        return None
    return Nav2FollowPath(node, runs, group)
