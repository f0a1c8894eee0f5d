"""What the base can do (`Limits`) and the node's control settings (`ControlConfig`, built from
its parameters): frozen values."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property


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
    def limited(self) -> bool:
        """The base has acceleration limits, linear or angular."""
        return bool(self.linear_accel or self.angular_accel)

    @property
    def linear_braking(self) -> float:
        """The deceleration the node clamps braking with [m/s^2]; 0: unlimited."""
        return self.linear_decel or self.linear_accel


@dataclass(frozen=True)
class ControlConfig:
    """The node's control settings, built from its parameters (`parameters.table` has units
    and defaults); `limits` is what they say of the base."""

    linear_speed: float  # top speed
    angular_speed: float  # top turn rate
    angular_deceleration: float  # braking towards the end of a turn, without acceleration limits
    position_tolerance: float  # end of a curve reached (corners, line ends)
    heading_tolerance: float  # end of a turn reached
    period_s: float  # control period
    # A base's acceleration limits; 0: unlimited (turtlesim's instant response). With any of
    # them set, every command stays within reach of the one before (`dynamics`), and braking
    # follows the limits instead of a follower's deceleration and `angular_deceleration`.
    max_linear_accel: float = 0.0
    max_linear_decel: float = 0.0  # 0: the same as max_linear_accel
    max_angular_accel: float = 0.0
    progress_timeout_s: float = 3.0  # a run that makes no progress this long ends

    @cached_property
    def limits(self) -> Limits:
        """What the base can do, as controllers, the dynamics and the profiles read it."""
        return Limits(self.linear_speed, self.angular_speed, self.max_linear_accel,
                      self.max_angular_accel, self.period_s, self.max_linear_decel)

    @property
    def limited(self) -> bool:
        """The base has acceleration limits, linear or angular."""
        return self.limits.limited

    @property
    def linear_braking(self) -> float:
        """The base's braking limit along a path, m/s²; 0: unlimited."""
        return self.limits.linear_braking

    @property
    def angular_braking(self) -> float:
        """How hard the controller brakes a turn, rad/s²."""
        return self.max_angular_accel or self.angular_deceleration
