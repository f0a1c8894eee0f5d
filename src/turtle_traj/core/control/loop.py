"""The control loop of one turtle: a pose in, a command out, the model of the robot inside.

Pure Python. The trajectory node feeds it from its pose subscription and control timer; the pure
tests and the benchmarks feed it from `sim.physics.World`, thousands of times faster than ROS.
The model of the robot (`RobotModel`) lives across runs: how late commands take effect is a
property of the link, known before the next trajectory starts.
"""

from __future__ import annotations

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.controllers.catalogue import ControllerChoice
from turtle_traj.core.control.echo import alike
from turtle_traj.core.control.ending import Ending
from turtle_traj.core.control.observers import TURTLESIM, Robot
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.robot_model import RobotModel
from turtle_traj.core.control.supervisor import RunSupervisor
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.shapes import Arena


class ControlLoop:
    """One turtle's poses, the commands sent to it, and the run being driven (if any).

    :param step_s: how long each command acts at least: the robot's step (turtlesim's 16 ms),
        not the control period, which may differ.
    :param robot: what the robot is (`observers.Robot`): turtlesim, or a base seen through
        its odometry.
    :param late_prior: steps a command may act late at a leg's end before the link's timing
        is seen (`RobotModel`).
    """

    def __init__(self, step_s: float, *, robot: Robot = TURTLESIM,
                 late_prior: float = 0.0) -> None:
        self.model = RobotModel(step_s, robot=robot, late_prior=late_prior)
        self.run: RunSupervisor | None = None
        self.pose: Pose2D | None = None

    def observe(self, pose: Pose2D, linear_echo: float, angular_echo: float,
                silent_s: float = 0.0) -> None:
        """A pose as turtlesim reports it, with the velocities in effect at its step, `silent_s`
        after the pose before (0: the next step's; see `RunSupervisor.observe`)."""
        self.pose = pose
        if self.run is not None:
            self.run.observe(pose, silent_s)
        self.model.observe(linear_echo, angular_echo, pose)

    def forget_pose(self) -> None:
        """The turtle is gone (a reset): no pose until the next one is observed."""
        self.pose = None

    def start(self, plan: Plan, *, arena: Arena, now_s: float,
              controller: ControllerChoice | None = None) -> RunSupervisor:
        """Begin driving `plan` from the last pose observed (with `controller`, a name and a
        class, instead of the exact follower). A controller that cannot be made ends the run at
        once, the exact follower's walker standing in."""
        if self.pose is None:
            raise RuntimeError('no pose observed yet')
        chosen, manage_pen = controller or ControllerChoice(), plan.pen is not None
        try:
            walker, fault = chosen.driver(plan, manage_pen=manage_pen), None
        except Exception as error:  # the controller's constructor
            walker, fault = ControllerChoice().driver(plan, manage_pen=manage_pen), error
        self.run = RunSupervisor(plan, walker, start=self.pose, arena=arena, started_s=now_s)
        if fault is not None:
            self.run.end(False, f"{plan.trajectory} aborted: controller '{chosen.name}' could "
                                f'not be made: {type(fault).__name__}: {fault}',
                         Ending.CONTROLLER_FAULT)
        return self.run

    @property
    def at_rest(self) -> bool:
        """The last pose shows the robot at rest, as the model of the robot judges it."""
        return self.model.at_rest

    def take_run(self) -> RunSupervisor | None:
        """Detach the run (it has ended) and return it."""
        run, self.run = self.run, None
        return run

    def command(self, config: ControlConfig, arena: Arena, now_s: float) -> Command | None:
        """This period's command for the run (call it on every tick of the control timer, with
        a run or without); None when there is nothing to send: no run, no pose yet, commands
        overdue at the robot (`RobotModel.excess`: more than one, or one where the command
        held in place of this one drives alike), or the run has just ended (whoever ends it
        sends the stop)."""
        self.model.ticked(now_s)
        run = self.run
        if run is None or self.pose is None:
            return None
        excess = self.model.excess
        if excess > 1:
            run.watch(self.pose, config, arena, now_s)  # a wall, or no progress, all the same
            return None
        prediction = self.model.predict(self.pose, now_s)
        command = run.command(self.pose, self.at_rest, config, arena, now_s, prediction)
        if run.ending is not None or (excess and alike(command, self.model.last_sent)):
            return None
        return self.model.distinct(command)

    def sent(self, command: Command, now_s: float) -> None:
        """Record a command as it is published (every one, the stops included; node clock)."""
        self.model.sent(command, now_s)
