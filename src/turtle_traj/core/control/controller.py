"""The controller interface: what a path-following controller is given, and what it gives back.

Pure Python, no ROS. A `Controller` follows one *stroke* at a time: a polyline the robot drives
without lifting the pen (a square's four sides, a letter's outline, a step curve). The node
hands it the stroke and the base's limits when the stroke starts; then, once per control
period, a `State`: what the model of the robot predicts for the moment the command takes
effect (and how uncertain that moment is), the pose measured, and the limits in effect; the
controller answers with a velocity command, or None once it has arrived. Everything else is
the node's (`walker.PlanWalker`, the same for every controller, the node's exact follower
included): turns in place between strokes and at the end (`rotate`, a final heading), the pen,
progress and laps, whether an end the controller claims is reached (driven in order to within
`walker.ARRIVED_M`), the watchdogs, and keeping the robot safe from the controller (commands
clamped to the limits; NaN, exceptions and late answers end the run with the robot stopped).

A minimal controller (a proportional go-to-goal)::

    class GoToGoal:
        def start(self, stroke: Stroke, limits: Limits) -> None:
            self.goal, self.limits = stroke.points[-1], limits

        def command(self, state: State) -> Command | None:
            dx, dy = self.goal[0] - state.pose.x, self.goal[1] - state.pose.y
            if math.hypot(dx, dy) < 0.01:
                return None
            error = wrap_angle(math.atan2(dy, dx) - state.pose.theta)
            return Command(min(math.hypot(dx, dy), 1.0) * math.cos(error), 4.0 * error)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.config import Limits
from turtle_traj.core.control.drift import Tube
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.control.profile import SpeedProfile
from turtle_traj.core.geometry.path import Polyline, Pose2D

# How near a stroke's end, along it and straight, a controller's None counts as arrived where
# the stroke's tolerance is smaller (the node's goal checker, as Nav2's xy_goal_tolerance).
ARRIVED_M = 0.05


@dataclass(frozen=True)
class Stroke:
    """A polyline to drive from its first point to its last (N >= 2 points, metres)."""

    points: np.ndarray  # (N, 2)
    lap: int = 0  # an endless stroke (a circle until stopped) comes again, lap after lap
    # it ends where it starts and has no end: a controller may drive on round it, or answer
    # None at its last point, and the next lap starts
    endless: bool = False
    # m from its last point that count as arrived: the node's position_tolerance, or the
    # request's on the plan's last stroke
    tolerance: float = 0.0
    # on a base with acceleration limits, the time-optimal speed along the stroke as the node
    # planned it with the request (`profile.SpeedProfile.speed_at(arc length)`); without them,
    # on a path rounded within a tolerance, the speed its curvature allows at the whole turn
    # rate; None: none planned (an exact path without limits, a straight line on a base with
    # them, a stroke of several legs)
    profile: SpeedProfile | None = None
    # the same stroke as the node planned it, its headings, curvatures and segments computed
    # once for the node and the controller (its `reverse` is the node's: the pose is turned
    # round already); None: a controller makes one from `points` if it needs one
    polyline: Polyline | None = field(default=None, repr=False, compare=False)
    # the tolerance round the path as drawn, where the request gives one (`drift.Tube`: its
    # `room(x, y)`, how much farther the motion may stray from there); None: exact
    tube: Tube | None = field(default=None, repr=False, compare=False)


@dataclass(frozen=True)
class State:
    """What a controller is given each control period: the model of the robot's prediction
    for the moment this period's command takes effect, the pose last measured, and the limits
    in effect now.

    `robot` answers what a controller may ask of the model: `pose` and `velocity` there and
    then, how many steps late the command may act (`late_steps`) and how far that carries the
    robot (`overrun`, `braking_overrun`), whether it is `standing` (at rest, with nothing but
    stops on their way), and whether each of its steps `turns_first` (turtlesim) or drives an
    arc (a base).
    """

    robot: Prediction
    measured: Pose2D  # the last pose the robot reported
    elapsed_s: float  # control periods since the stroke started, in seconds
    # the limits in effect now: the node's parameters may change them during a stroke
    limits: Limits
    # where the measured pose is along the stroke, as the node measures progress: the index of
    # the nearest segment (points[i] to points[i + 1]) and the fraction along it (0 to 1)
    nearest: tuple[int, float] | None = None

    @property
    def pose(self) -> Pose2D:
        """Where the commands already on their way will have taken the robot."""
        return self.robot.pose

    @property
    def velocity(self) -> Command:
        """The velocity in effect until this period's command acts (the last command sent)."""
        return self.robot.velocity


@runtime_checkable
class Controller(Protocol):
    """A path-following controller: `start` once per stroke, then `command` every period.

    A controller may set the class attribute `turns_at_corners = True`: the node then turns in
    place at every corner of the path, and each stroke is the stretch between two corners
    (the exact follower's corners at 0.0 mm). By default it drives round corners up to
    `walker.MAX_CORNER_RAD` itself.
    """

    def start(self, stroke: Stroke, limits: Limits) -> None:
        """A new stroke begins (the robot stands at or near its first point)."""

    def command(self, state: State) -> Command | None:
        """This period's velocity command; None once the stroke's end is reached (the node
        checks the claim: an end claimed before the stroke is driven is a controller fault)."""


def interface_problem(candidate: object) -> str | None:
    """Why `candidate` (a class) does not implement `Controller`, or None."""
    if not isinstance(candidate, type):
        return f'{candidate!r} is not a class'
    missing = [name for name in ('start', 'command')
               if not callable(getattr(candidate, name, None))]
    if missing:
        return (f'{candidate.__module__}.{candidate.__qualname__} has no '
                f"{' and no '.join(missing)} method: a controller needs start(stroke, limits) "
                'and command(state)')
    return None
