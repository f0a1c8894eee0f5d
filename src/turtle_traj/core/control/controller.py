"""The controller interfaces: what a path-following controller is given, and what it gives back.

Pure Python, no ROS. Two levels. `PlanController` drives a whole plan (its legs, turns in
place and pen) and is what the node asks for a command every control period: the exact follower
(`follower.PathFollower`) is one, and `strokes.StrokeDriver` makes one of any `Controller`.

`Controller`, the one to write, follows one *stroke* at a time: a polyline the robot drives
without lifting the pen (a square's four sides, a letter's outline, a step curve). The node
hands it the stroke and the base's limits when the stroke starts; then, once per control
period, the robot's state as the model of the robot predicts it for the moment the command
takes effect; the controller answers with a velocity command, or None once it has arrived.
Everything else is the node's: turns in place between strokes and at the end (`rotate`, a
final heading), the pen, the watchdogs, and keeping the robot safe from the controller
(`strokes.StrokeDriver`: commands clamped to the limits, NaN, exceptions and late answers end
the run with the robot stopped).

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

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.prediction import Prediction
from turtle_traj.core.geometry.path import Pose2D


@dataclass(frozen=True)
class Limits:
    """What the base can do. A command beyond them is clamped by the node (and counted)."""

    linear_speed: float  # top forward speed [m/s]
    angular_speed: float  # top turn rate [rad/s]
    linear_accel: float  # [m/s^2] per period from the command before; 0: unlimited (turtlesim)
    angular_accel: float  # [rad/s^2]; 0: unlimited
    period_s: float  # the control period: one command each, acting for this long
    linear_decel: float = 0.0  # [m/s^2] braking; 0: linear_accel (the node's max_linear_decel)

    @property
    def linear_braking(self) -> float:
        """The deceleration the node clamps braking with [m/s^2]; 0: unlimited."""
        return self.linear_decel or self.linear_accel


@dataclass(frozen=True)
class Stroke:
    """A polyline to drive from its first point to its last (N >= 2 points, metres)."""

    points: np.ndarray  # (N, 2)
    lap: int = 0  # an endless stroke (a circle until stopped) comes again, lap after lap


@dataclass(frozen=True)
class State:
    """The robot as the model predicts it when this period's command takes effect."""

    pose: Pose2D  # predicted: where the commands already on their way will have taken it
    velocity: Command  # the velocity in effect until then (the last command sent)
    measured: Pose2D  # the last pose the robot reported
    elapsed_s: float  # control periods since the stroke started, in seconds


@runtime_checkable
class Controller(Protocol):
    """A path-following controller: `start` once per stroke, then `command` every period."""

    def start(self, stroke: Stroke, limits: Limits) -> None:
        """A new stroke begins (the robot stands at or near its first point)."""

    def command(self, state: State) -> Command | None:
        """This period's velocity command; None once the stroke's end is reached."""


@runtime_checkable
class PlanController(Protocol):
    """A controller of a whole plan, made for one run: every control period the node hands it
    the last pose and the model of the robot's prediction, and sends the command it returns.

    It reports how far it got (`mark`, `progress`: the run's watchdog and feedback) and when it
    is `done`; with the pen managed, it names the pen state it waits for (`pen_wanted`) and the
    node tells it the state the simulator confirmed (`pen_down`).
    """

    pen_down: bool | None
    pen_wanted: bool | None

    @property
    def done(self) -> bool:
        """The plan's last leg is finished."""

    @property
    def mark(self) -> tuple[int, float]:
        """Where it is: the index of its current step, and how much of that step is done."""

    def progress(self, config: ControlConfig) -> float:
        """How much of the plan is driven, 0 to 1."""

    @property
    def clamped_percent(self) -> float:
        """The share of its commands the node had to clamp to the limits, in percent."""

    def report(self) -> str:
        """What the run's message says of it once done ('' for nothing)."""

    def update(self, pose: Pose2D, config: ControlConfig,
               prediction: Prediction | None = None) -> Command:
        """This period's command (a stop once done)."""


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
