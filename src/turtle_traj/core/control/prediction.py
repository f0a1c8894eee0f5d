"""What the model of the robot says for one control period: one immutable value. Pure Python.

`RobotModel.predict` makes it; the follower steers from it.
"""

from __future__ import annotations

from dataclasses import dataclass

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
    # the robot stands: its last pose shows it at rest, and every command on its way is a stop
    standing: bool = True
    # turtlesim's step turns first and then moves along the new heading; a base reporting
    # odometry drives arcs
    turns_first: bool = True
    # m, rad: as `overrun`, for a braking at the deceleration limit, whose every command is
    # its approach (a base with inertia: `robot_model.BRAKING_WINDOW`)
    braking_overrun: tuple[float, float] = (0.0, 0.0)

    def overrun_when(self, limited: bool) -> tuple[float, float]:
        """What an approach allows for: `braking_overrun` on a base with acceleration limits,
        `overrun` on one that takes each command at once."""
        return self.braking_overrun if limited else self.overrun

    @classmethod
    def immediate(cls, pose: Pose2D, velocity: Command = STOP) -> Prediction:
        """A robot that takes each command at once (no model: the follower used alone)."""
        return cls(pose, velocity)
