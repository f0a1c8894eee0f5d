"""The controller's tuning, one frozen value (the node builds it from its parameters)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class ControlConfig:
    """Controller tuning, built from the node's parameters (`parameters.table` has units and
    defaults)."""

    linear_speed: float  # top speed
    angular_speed: float  # top turn rate
    angular_deceleration: float  # braking towards the end of a turn, without acceleration limits
    position_tolerance: float  # end of a curve reached (corners, line ends)
    heading_tolerance: float  # end of a turn reached
    period_s: float  # control period
    # A base's acceleration limits; 0: unlimited (turtlesim's instant response). With any of
    # them set, every command stays within reach of the one before (`dynamics`), and braking
    # follows the limits instead of `deceleration` and `angular_deceleration`.
    max_linear_accel: float = 0.0
    max_linear_decel: float = 0.0  # 0: the same as max_linear_accel
    max_angular_accel: float = 0.0
    progress_timeout_s: float = 3.0  # a run that makes no progress this long ends

    @property
    def limited(self) -> bool:
        """The base has acceleration limits, linear or angular."""
        return bool(self.max_linear_accel or self.max_angular_accel)

    @property
    def linear_braking(self) -> float:
        """The base's braking limit along a path, m/s²; 0: unlimited."""
        return self.max_linear_decel or self.max_linear_accel

    @property
    def angular_braking(self) -> float:
        """How hard the controller brakes a turn, rad/s²."""
        return self.max_angular_accel or self.angular_deceleration
