"""The controller's tuning, one frozen value (the node builds it from its parameters)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class ControlConfig:
    """Controller tuning, built from the node's parameters (`parameter_table` has units and
    defaults)."""

    linear_speed: float  # top speed
    angular_speed: float  # top turn rate
    heading_gain: float  # turn rate per radian of heading error
    cross_track_gain: float  # how hard curves pull the turtle back onto the path
    deceleration: float  # braking towards the end of a curve
    angular_deceleration: float  # braking towards the end of a turn
    position_tolerance: float  # end of a curve reached (corners, line ends)
    heading_tolerance: float  # end of a turn reached
    turn_first_angle: float  # heading error beyond which the turtle turns in place
    period_s: float  # control period
