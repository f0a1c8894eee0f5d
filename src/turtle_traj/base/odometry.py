"""Wheel odometry as ROS 2's diff_drive_controller computes it: the pose integrated from the
wheel encoders' counts and the nominal wheel radius and separation. Pure.

It drifts, as a real base's does: the encoders count whole ticks, and tyres slip and roll on a
radius a little smaller than the nominal one under load.
"""

from __future__ import annotations

import math


class WheelOdometry:
    """The pose in the odom frame (starting at 0, 0, 0) and the twist, from encoder angles."""

    def __init__(self, *, wheel_radius: float, wheel_separation: float,
                 ticks_per_revolution: int) -> None:
        self._radius, self._separation = wheel_radius, wheel_separation
        self._radians_per_tick = 2.0 * math.pi / ticks_per_revolution
        self._ticks: tuple[int, int] | None = None
        self.x = self.y = self.yaw = 0.0
        self.linear = self.angular = 0.0

    def counts(self, angle_rad: float) -> int:
        """What an encoder reads at this wheel angle: whole ticks."""
        return math.floor(angle_rad / self._radians_per_tick)

    def update(self, left_rad: float, right_rad: float, period_s: float) -> None:
        """Integrate one period from the wheels' angles at its end."""
        ticks = self.counts(left_rad), self.counts(right_rad)
        previous, self._ticks = self._ticks, ticks
        if previous is None:
            return  # the first reading only sets where the counts start
        left = (ticks[0] - previous[0]) * self._radians_per_tick * self._radius
        right = (ticks[1] - previous[1]) * self._radians_per_tick * self._radius
        distance, turn = (left + right) / 2.0, (right - left) / self._separation
        self._integrate(distance, turn)
        self.linear, self.angular = distance / period_s, turn / period_s

    def _integrate(self, distance: float, turn: float) -> None:
        """Advance the pose along an arc (diff_drive_controller's integrateExact; the
        second-order Runge-Kutta step for a turn too small to divide by)."""
        if abs(turn) < 1e-6:
            heading = self.yaw + 0.5 * turn
            self.x += distance * math.cos(heading)
            self.y += distance * math.sin(heading)
        else:
            radius = distance / turn
            new_yaw = self.yaw + turn
            self.x += radius * (math.sin(new_yaw) - math.sin(self.yaw))
            self.y -= radius * (math.cos(new_yaw) - math.cos(self.yaw))
        self.yaw = math.remainder(self.yaw + turn, math.tau)
