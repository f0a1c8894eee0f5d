"""Turtlesim physics as plain Python: turtles, commands, teleports, rotation goals, walls.

Matches ROS 2 Jazzy's turtlesim (see shared turtlesim reference): a fixed 16 ms step, heading
integrated first, per-axis wall clamp without zeroing velocity, 1 s command timeout.

Time: turtlesim reads its velocity commands at the start of a tick, stamps them with the node
clock then, and drops a command older than 1 s at the start of a later tick. Callers pass that
clock as `now_s`; without it the world uses its own simulated time (step count times the step),
and a command given between steps is stamped with the coming step's time, as turtlesim would
stamp it. Either way a single command lasts 63 steps.

Inertia (a turtle_traj extension for testing controllers meant for real bases): with
`Inertia` limits, each step moves a turtle's velocity towards its command by at most the limit
times the step, and the pose reports the velocity in effect. A command within reach is taken
exactly, so a controller that respects the limits sees turtlesim's behaviour. Limits of 0 are
turtlesim's instant response.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

from turtle_traj.core.turtlesim_contract import COMMAND_TIMEOUT_S, SPAWN_XY_M, STEP_S, WORLD_SIZE_M
from turtle_traj.sim.state import (
    NonFiniteCommand,
    Pen,
    RotationEnd,
    RotationEvent,
    RotationGoal,
    Segment,
    SimulationError,
    StepReport,
    Turtle,
    normalize_angle,
    require_finite,
)

ROTATION_SPEED_RAD_S = 1.0
ROTATION_TOLERANCE_RAD = 0.02


@dataclass(frozen=True)
class Inertia:
    """How fast a turtle's velocity may change: m/s² and rad/s²; 0 is at once."""

    linear_accel: float = 0.0
    angular_accel: float = 0.0

    def __post_init__(self) -> None:
        for name, value in (('linear_accel', self.linear_accel),
                            ('angular_accel', self.angular_accel)):
            if not (math.isfinite(value) and value >= 0.0):
                raise SimulationError(f'{name} must be a finite number >= 0, got {value}')


def _towards(value: float, target: float, step: float) -> float:
    """`value` moved towards `target` by at most `step` (> 0); the target itself if within
    reach, so that a command in reach is taken exactly."""
    if abs(target - value) <= step:
        return target
    return value + math.copysign(step, target - value)


class World:
    """All turtles of one simulator, stepped in lexicographic name order."""

    def __init__(self, *, holonomic: bool = False, inertia: Inertia | None = None) -> None:
        self.holonomic = holonomic
        self.inertia = inertia if inertia is not None else Inertia()
        self.time_s = 0.0
        self.turtles: dict[str, Turtle] = {}
        self._name_counter = 0
        # By turtle name: the share of its velocity its motors deliver (1 unless given), as a
        # worn motor would; its pose still reports the velocity, as turtlesim's reports the
        # command.
        self.motor_gains: dict[str, float] = {}

    def __iter__(self) -> Iterator[Turtle]:
        return (self.turtles[name] for name in sorted(self.turtles))

    def turtle(self, name: str) -> Turtle:
        try:
            return self.turtles[name]
        except KeyError:
            raise SimulationError(f'no turtle named {name!r}') from None

    def spawn(self, x: float, y: float, theta: float, name: str = '',
              now_s: float | None = None) -> Turtle:
        """Add a turtle; an empty name gets the next free `turtleN`.

        :param now_s: the clock (see the module); its command timestamp starts there.
        """
        require_finite(x=x, y=y, theta=theta)
        if name in self.turtles:
            raise SimulationError(f'A turtle named [{name}] already exists')
        if not name:
            while not name or name in self.turtles:
                self._name_counter += 1
                name = f'turtle{self._name_counter}'
        turtle = Turtle(name, x, y, theta, command_time_s=self._now(now_s))
        self.turtles[name] = turtle
        return turtle

    def kill(self, name: str) -> Turtle:
        """Remove a turtle; its trail stays."""
        turtle = self.turtle(name)
        del self.turtles[name]
        return turtle

    def remove_all(self) -> None:
        """Remove every turtle and restart automatic naming at turtle1."""
        self.turtles.clear()
        self._name_counter = 0

    def reset(self) -> Turtle:
        """Remove every turtle and spawn a fresh turtle1 in the middle."""
        self.remove_all()
        return self.spawn(SPAWN_XY_M, SPAWN_XY_M, 0.0)

    def command(self, name: str, linear_x: float, linear_y: float, angular_z: float,
                now_s: float | None = None) -> RotationGoal | None:
        """Apply a cmd_vel message; return the rotation goal it aborts, if any.

        :param now_s: the clock at the tick that reads the command (see the module).
        :raises NonFiniteCommand: NaN or infinity; the turtle is stopped instead (turtlesim
            would write NaN into its pose).
        """
        turtle = self.turtle(name)
        turtle.command_time_s = self._now(now_s, coming=True)
        aborted, turtle.rotation = turtle.rotation, None
        values = {'linear.x': linear_x, 'linear.y': linear_y, 'angular.z': angular_z}
        if not all(math.isfinite(value) for value in values.values()):
            turtle.stop()
            shown = ', '.join(f'{key}={value}' for key, value in values.items())
            raise NonFiniteCommand(f'non-finite velocity ({shown}): the turtle stops', aborted)
        turtle.want_vx = linear_x
        turtle.want_vy = linear_y if self.holonomic else 0.0
        turtle.want_omega = angular_z  # in effect from the next step (`_accelerate`)
        return aborted

    def _now(self, now_s: float | None, coming: bool = False) -> float:
        """The given clock, else simulated time (of the coming step, for a command)."""
        if now_s is not None:
            return now_s
        return self.time_s + STEP_S if coming else self.time_s

    def teleport_absolute(self, name: str, x: float, y: float, theta: float) -> None:
        require_finite(x=x, y=y, theta=theta)
        self.turtle(name).teleports.append(('absolute', x, y, theta))

    def teleport_relative(self, name: str, linear: float, angular: float) -> None:
        require_finite(linear=linear, angular=angular)
        self.turtle(name).teleports.append(('relative', linear, angular, 0.0))

    def set_pen(self, name: str, r: int, g: int, b: int, width_px: int, off: int) -> None:
        """turtlesim's SetPen: any non-zero `off` only lifts the pen; width 0 means 1 px."""
        turtle = self.turtle(name)
        if off:
            turtle.pen = Pen(turtle.pen.r, turtle.pen.g, turtle.pen.b, turtle.pen.width_px, False)
        else:
            turtle.pen = Pen(r, g, b, width_px or 1, True)

    def start_rotation(self, name: str, token: object, target_rad: float) -> RotationGoal | None:
        """Start a rotate_absolute goal; return the goal it replaces (to be aborted)."""
        require_finite(theta=target_rad)
        turtle = self.turtle(name)
        replaced = turtle.rotation
        turtle.rotation = RotationGoal(token, target_rad, start_rad=turtle.theta)
        return replaced

    def cancel_rotation(self, name: str, token: object) -> None:
        rotation = self.turtles.get(name) and self.turtles[name].rotation
        if rotation and rotation.token is token:
            rotation.cancel_requested = True

    def step(self, now_s: float | None = None) -> StepReport:
        """Advance every turtle by one 16 ms step.

        :param now_s: the clock at this tick (see the module), for the command timeout.
        """
        self.time_s += STEP_S
        now = self._now(now_s)
        report = StepReport()
        for turtle in self:
            self._update(turtle, report, now)
        return report

    def _update(self, turtle: Turtle, report: StepReport, now_s: float) -> None:
        for kind, a, b, c in turtle.teleports:
            old = (turtle.x, turtle.y)
            if kind == 'absolute':
                turtle.x, turtle.y, turtle.theta = a, min(b, WORLD_SIZE_M), c
            else:
                turtle.theta += b
                turtle.x += a * math.cos(turtle.theta)
                turtle.y += a * math.sin(turtle.theta)
            if turtle.pen.on:
                report.segments.append(Segment(old, (turtle.x, turtle.y), turtle.pen))
        turtle.teleports.clear()

        if turtle.rotation is not None:
            self._rotate(turtle, report, now_s)

        if now_s - turtle.command_time_s > COMMAND_TIMEOUT_S:
            turtle.want_vx = turtle.want_vy = turtle.want_omega = 0.0  # with inertia: slows
        self._accelerate(turtle)

        old = (turtle.x, turtle.y)
        moved_s = self.motor_gains.get(turtle.name, 1.0) * STEP_S
        turtle.theta = normalize_angle(turtle.theta + turtle.omega * moved_s)
        cos_t, sin_t = math.cos(turtle.theta), math.sin(turtle.theta)
        turtle.x += (turtle.vx * cos_t - turtle.vy * sin_t) * moved_s
        turtle.y += (turtle.vx * sin_t + turtle.vy * cos_t) * moved_s
        if not (0.0 <= turtle.x <= WORLD_SIZE_M and 0.0 <= turtle.y <= WORLD_SIZE_M):
            report.wall_hits.append((turtle.name, turtle.x, WORLD_SIZE_M - turtle.y))
            turtle.x = min(max(turtle.x, 0.0), WORLD_SIZE_M)
            turtle.y = min(max(turtle.y, 0.0), WORLD_SIZE_M)
        if turtle.pen.on and (turtle.x, turtle.y) != old:
            report.segments.append(Segment(old, (turtle.x, turtle.y), turtle.pen))

    def _accelerate(self, turtle: Turtle) -> None:
        """With inertia, move the velocity towards the command by one step's worth."""
        linear, angular = self.inertia.linear_accel, self.inertia.angular_accel
        if linear:
            turtle.vx = _towards(turtle.vx, turtle.want_vx, linear * STEP_S)
            turtle.vy = _towards(turtle.vy, turtle.want_vy, linear * STEP_S)
        else:
            turtle.vx, turtle.vy = turtle.want_vx, turtle.want_vy
        turtle.omega = (_towards(turtle.omega, turtle.want_omega, angular * STEP_S) if angular
                        else turtle.want_omega)

    def _rotate(self, turtle: Turtle, report: StepReport, now_s: float) -> None:
        goal = turtle.rotation
        assert goal is not None
        if goal.cancel_requested:
            turtle.rotation = None
            turtle.stop()
            report.rotation_events.append(
                RotationEvent(turtle.name, goal.token, 0.0, goal.delta_rad, RotationEnd.CANCELED))
            return
        target = normalize_angle(goal.target_rad)
        remaining = normalize_angle(target - turtle.theta)
        goal.delta_rad = normalize_angle(goal.start_rad - turtle.theta)
        report.rotation_events.append(
            RotationEvent(turtle.name, goal.token, remaining, goal.delta_rad))
        if abs(normalize_angle(turtle.theta - target)) < ROTATION_TOLERANCE_RAD:
            turtle.rotation = None
            turtle.stop()
            report.rotation_events.append(
                RotationEvent(turtle.name, goal.token, remaining, goal.delta_rad,
                              RotationEnd.SUCCEEDED))
            return
        turtle.want_vx = turtle.want_vy = 0.0
        turtle.want_omega = -ROTATION_SPEED_RAD_S if remaining < 0 else ROTATION_SPEED_RAD_S
        turtle.command_time_s = now_s
