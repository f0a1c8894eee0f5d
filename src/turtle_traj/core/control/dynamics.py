"""What a base with acceleration limits can do in one control period. Pure Python.

A command is within reach when the base can take it in one period from the command before it:
each speed changes by at most its limit times the period. A controller that sends only such
commands sees the base respond as turtlesim does (at once, one period later), so its latency
model and its predictions stay exact. Limits of 0 mean unlimited.
"""

from __future__ import annotations

import math

from turtle_traj.core.control.commands import Command
from turtle_traj.core.control.config import Limits

# Commands stay this much inside the window, so that rounding never puts one outside it.
_INSIDE = 1.0 - 1e-9


def _reach(value: float, previous: float, limit: float, period_s: float) -> float:
    if not limit:
        return value
    step = limit * period_s * _INSIDE
    return min(max(value, previous - step), previous + step)


def _linear_step(previous: float, wanted: float, limits: Limits) -> float:
    """The linear change allowed: speeding up at the acceleration limit, slowing down at the
    braking limit (a change of sign is slowing down first)."""
    speeding_up = abs(wanted) > abs(previous) and wanted * previous >= 0.0
    return limits.linear_accel if speeding_up else limits.linear_braking


def within_reach(command: Command, previous: Command, limits: Limits,
                 keep_curvature: bool = True) -> Command:
    """`command`, limited to what the base can reach from `previous` in one period; with
    `keep_curvature`, slowed down where its turn rate is out of reach so that its curvature
    holds (a follower whose speed profile already keeps the path's own turn within reach
    leaves it off: only its steering is then clamped, and slowing for it costs time)."""
    if not limits.limited:
        return command
    angular = _reach(command.angular, previous.angular, limits.angular_accel, limits.period_s)
    linear = command.linear
    if keep_curvature and angular != command.angular and command.angular:
        # the turn rate cannot follow: slow down so that the curvature asked for holds
        # (on the line omega = k v, as Dynamic Window Pure Pursuit chooses)
        share = angular / command.angular
        if 0.0 <= share < 1.0:
            linear *= share
    linear = _reach(linear, previous.linear, _linear_step(previous.linear, linear, limits),
                    limits.period_s)
    return Command(linear, angular)


def can_stop(previous: Command, limits: Limits) -> bool:
    """A stop is within reach of `previous` (so a leg may end and the next begin)."""
    period = limits.period_s
    linear_ok = (not limits.linear_braking
                 or abs(previous.linear) <= limits.linear_braking * period)
    angular_ok = (not limits.angular_accel
                  or abs(previous.angular) <= limits.angular_accel * period)
    return linear_ok and angular_ok


def stopping_speed(distance: float, deceleration: float, period_s: float) -> float:
    """Fastest speed v from which commands v, v - dT, v - 2dT, ... (each acting one period T,
    the last positive one included) cover at most `distance`."""
    step = deceleration * period_s
    budget = max(distance, 0.0) / period_s  # the sum of the commands' speeds
    # with n full steps down, (n + 1) v - step n (n + 1) / 2 = budget, for n step <= v
    n = int((math.sqrt(0.25 * step * step + 2.0 * step * budget) - 0.5 * step) / step)
    while n > 0 and (budget + step * n * (n + 1) / 2) / (n + 1) < n * step:
        n -= 1
    return min((budget + step * n * (n + 1) / 2) / (n + 1), (n + 1) * step)
