"""Dynamic Window Pure Pursuit (DWPP), written from the paper's description.

Ohnishi & Takahashi (2025), "Dynamic Window Pure Pursuit": regulated pure pursuit
(`pure_pursuit`: adaptive look-ahead, slower on tight curvature and towards the goal) chooses a
curvature k and a speed; DWPP then keeps every command inside the dynamic window, the
velocities the base can reach within one control period under its acceleration limits,
choosing on the line omega = k v the fastest point up to the regulated speed or, where the line
misses the window, the window's point nearest to it (the faster on a tie). No rotation in
place: the window turns the robot as fast as it can.
"""

from __future__ import annotations

import math

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.controllers.pure_pursuit import PurePursuit

_UNLIMITED = 1e6  # an acceleration limit of 0: no window (turtlesim)


class Dwpp(PurePursuit):
    """DWPP along one stroke (see the module's docstring)."""

    rotate_to_heading = False
    approach_scaling = False  # the paper's robot brakes at its limit, not on a ramp
    # the tuning of those two regulations does not apply
    rotate_to_heading_min_angle = approach_velocity_scaling_dist = None
    min_approach_linear_velocity = None

    def _window(self, velocity: Command) -> tuple[float, float, float, float]:
        """The velocities within reach in one period: v_low, v_high, w_low, w_high."""
        limits = self.limits
        a = (limits.linear_accel or _UNLIMITED) * limits.period_s
        braking = (limits.linear_braking or _UNLIMITED) * limits.period_s
        alpha = (limits.angular_accel or _UNLIMITED) * limits.period_s
        return (max(velocity.linear - braking, 0.0), min(velocity.linear + a, limits.linear_speed),
                max(velocity.angular - alpha, -limits.angular_speed),
                min(velocity.angular + alpha, limits.angular_speed))

    def stopping(self, velocity: Command) -> Command:
        """The window's point nearest to standing still."""
        v_low, v_high, w_low, w_high = self._window(velocity)
        return Command(min(max(0.0, v_low), v_high), min(max(0.0, w_low), w_high))

    def choose(self, speed: float, curvature: float, bearing: float,
               velocity: Command) -> Command:
        v_low, v_high, w_low, w_high = self._window(velocity)
        low, high = v_low, v_high
        if abs(curvature) > 1e-12:
            bounds = sorted((w_low / curvature, w_high / curvature))
            low, high = max(low, bounds[0]), min(high, bounds[1])
        elif not w_low <= 0.0 <= w_high:
            low, high = 1.0, 0.0  # the line omega = 0 misses the window
        if low <= high:
            v = min(max(speed, low), high)
            return Command(v, curvature * v)
        corners = [(v, w) for v in (v_low, v_high) for w in (w_low, w_high)]
        norm = math.sqrt(1.0 + curvature * curvature)
        v, w = min(corners, key=lambda c: (abs(c[1] - curvature * c[0]) / norm, -c[0]))
        return Command(v, w)
