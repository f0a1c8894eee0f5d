"""What the base's controller does with a velocity command before the motors get it, as ROS 2's
diff_drive_controller does: limit speed and acceleration of v and omega, then convert to wheel
speeds within the motors' top speed. Pure.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class DriveLimits:
    """The base controller's limits on commands (diff_drive_controller's linear.x and
    angular.z limits); 0 means none."""

    max_linear_speed: float = 0.22  # m/s: TurtleBot3 Burger
    max_angular_speed: float = 2.84  # rad/s: TurtleBot3 Burger
    max_linear_accel: float = 2.5  # m/s^2: Nav2's TurtleBot3 configuration
    max_angular_accel: float = 3.2  # rad/s^2: Nav2's TurtleBot3 configuration


def _clamp(value: float, bound: float) -> float:
    return value if bound <= 0.0 else max(-bound, min(bound, value))


class VelocityLimiter:
    """Takes commands and gives what the base will do, within `limits`, one period at a time."""

    def __init__(self, limits: DriveLimits) -> None:
        self.limits = limits
        self.linear = self.angular = 0.0  # the command in effect

    def limit(self, linear: float, angular: float, period_s: float) -> tuple[float, float]:
        """The command in effect after one more period of heading for (linear, angular)."""
        limits = self.limits
        linear = _clamp(linear, limits.max_linear_speed)
        angular = _clamp(angular, limits.max_angular_speed)
        self.linear += _clamp(linear - self.linear, limits.max_linear_accel * period_s)
        self.angular += _clamp(angular - self.angular, limits.max_angular_accel * period_s)
        return self.linear, self.angular


def wheel_speeds(linear: float, angular: float, *, wheel_radius: float,
                 wheel_separation: float, max_wheel_speed: float) -> tuple[float, float, bool]:
    """Left and right wheel speeds [rad/s] for a command, and whether they were scaled down.

    A command a wheel cannot reach is scaled as a whole, so the base keeps to the curvature
    asked for, only slower (where clipping each wheel would turn it off its path).
    """
    half = wheel_separation / 2
    left = (linear - angular * half) / wheel_radius
    right = (linear + angular * half) / wheel_radius
    fastest = max(abs(left), abs(right))
    if fastest <= max_wheel_speed:
        return left, right, False
    scale = max_wheel_speed / fastest
    return left * scale, right * scale, True
