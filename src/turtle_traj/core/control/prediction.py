"""What the model of the robot says for one control period: one immutable value. Pure Python.

`RobotModel.predict` makes it; the follower steers from it (`Prediction.then` looks a step
further, for a command queued behind the last one sent).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from turtle_traj.core.control.commands import STOP, Command
from turtle_traj.core.geometry.path import Pose2D


@dataclass(frozen=True)
class Prediction:
    """What the model says of the robot for this control period (immutable)."""

    pose: Pose2D  # where the robot will be when the next command takes effect
    velocity: Command  # the command in effect until then: the last one sent
    late_steps: int = 0  # how many steps longer than one the next command may act
    # m, rad the robot may move beyond `pose`: the last command sent, acting `late_steps` longer
    overrun: tuple[float, float] = (0.0, 0.0)
    still: bool = True  # it stands, and every command on its way is a stop
    # turtlesim's step turns first and then moves along the new heading; a base reporting
    # odometry drives arcs
    turns_first: bool = True
    in_flight: int = 0  # commands sent and not yet taken
    # how many more commands its queue takes now, one acting each step (`step_s`): 0 without a
    # queue, or where a command's step is not exactly known (a base's odometry)
    room: int = 0
    step_s: float = 0.0
    # a command sent now would wait behind the last one sent (sent with others, it holds the
    # robot's next step)
    queued: bool = False
    dropped: int = 0  # commands dropped on the way so far (in flight past their lifespan)

    @classmethod
    def immediate(cls, pose: Pose2D, velocity: Command = STOP) -> Prediction:
        """A robot that takes each command at once (no model: the follower used alone)."""
        return cls(pose, velocity)

    def then(self, command: Command) -> Prediction:
        """The prediction one step on, with `command` sent now behind the others: it acts
        exactly one step (the next one queued behind it takes over), and then acts on."""
        return replace(self, pose=advance(self.pose, command, self.step_s), velocity=command,
                       overrun=_overrun(command, self.late_steps, self.step_s),
                       still=self.still and command == STOP, in_flight=self.in_flight + 1,
                       room=self.room - 1, queued=True)


def _overrun(command: Command, late_steps: int, step_s: float) -> tuple[float, float]:
    """How far `command` carries the robot acting `late_steps` longer: m, rad."""
    return abs(command.linear) * late_steps * step_s, abs(command.angular) * late_steps * step_s


def advance(pose: Pose2D, command: Command, seconds: float) -> Pose2D:
    """`pose` after `command` acted `seconds`, as turtlesim integrates a step: heading first,
    then position along the new heading (unwrapped: steps add up)."""
    theta = pose.theta + command.angular * seconds
    return Pose2D(pose.x + command.linear * math.cos(theta) * seconds,
                  pose.y + command.linear * math.sin(theta) * seconds, theta)
