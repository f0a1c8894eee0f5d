"""What the simulated world holds and reports: turtles, pens, trail segments, rotation goals,
and the errors it refuses requests with. Plain data, as turtlesim keeps it."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum

from turtle_traj.core.turtlesim_contract import DEFAULT_PEN

_PI = 3.14159265  # turtlesim's own value of pi in its angle normalisation


def normalize_angle(angle_rad: float) -> float:
    """Wrap an angle into [-pi, pi) exactly as turtlesim does, with its pi (the controller's
    `geometry.angles.wrap_angle` uses math.pi: the two differ by 4e-9 rad)."""
    return angle_rad - 2.0 * _PI * math.floor((angle_rad + _PI) / (2.0 * _PI))


class SimulationError(ValueError):
    """A request the world refuses; the message says why."""


class NonFiniteCommand(SimulationError):
    """A velocity command with NaN or infinity: refused, and the turtle stopped instead.

    :ivar aborted: the rotation goal the command aborted, if any (any cmd_vel aborts one).
    """

    def __init__(self, message: str, aborted: RotationGoal | None) -> None:
        super().__init__(message)
        self.aborted = aborted


@dataclass
class Pen:
    """Trail pen: opaque colour, width in pixels, on or off."""

    r: int = DEFAULT_PEN.r
    g: int = DEFAULT_PEN.g
    b: int = DEFAULT_PEN.b
    width_px: int = DEFAULT_PEN.width
    on: bool = True


class RotationEnd(Enum):
    """How a rotation goal ended."""

    SUCCEEDED = 'succeeded'
    ABORTED = 'aborted'
    CANCELED = 'canceled'


@dataclass
class RotationGoal:
    """An active rotate_absolute goal; `token` lets the ROS layer match it to its handle."""

    token: object
    target_rad: float
    start_rad: float
    delta_rad: float = 0.0
    cancel_requested: bool = False


@dataclass
class RotationEvent:
    """Feedback (status None) or the end of a rotation goal."""

    turtle: str
    token: object
    remaining_rad: float
    delta_rad: float
    status: RotationEnd | None = None


@dataclass
class Segment:
    """A pen stroke from one position to the next, in world metres."""

    start: tuple[float, float]
    end: tuple[float, float]
    pen: Pen


@dataclass
class Turtle:
    """State of one turtle."""

    name: str
    x: float
    y: float
    theta: float
    vx: float = 0.0
    vy: float = 0.0
    omega: float = 0.0
    # The velocity last commanded; with inertia (`World.inertia`) the velocity above moves
    # towards it step by step, without it the two are the same.
    want_vx: float = 0.0
    want_vy: float = 0.0
    want_omega: float = 0.0
    command_time_s: float = 0.0
    pen: Pen = field(default_factory=Pen)
    teleports: list[tuple[str, float, float, float]] = field(default_factory=list)
    rotation: RotationGoal | None = None

    @property
    def linear_speed(self) -> float:
        """Magnitude of the commanded velocity, as turtlesim's Pose reports it."""
        return math.hypot(self.vx, self.vy)

    def stop(self) -> None:
        """Stand still at once (and want to)."""
        self.vx = self.vy = self.omega = 0.0
        self.want_vx = self.want_vy = self.want_omega = 0.0


@dataclass
class StepReport:
    """What one step produced, for the ROS layer to publish."""

    segments: list[Segment] = field(default_factory=list)
    wall_hits: list[tuple[str, float, float]] = field(default_factory=list)
    rotation_events: list[RotationEvent] = field(default_factory=list)


def require_finite(**values: float) -> None:
    """Refuse NaN and infinities, naming the value."""
    for name, value in values.items():
        if not math.isfinite(value):
            raise SimulationError(f'{name} must be a finite number, got {value}')
