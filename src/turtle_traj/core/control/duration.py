"""How long a run will take at the least, as the controller drives it. Pure Python.

Each leg at its own limits: a turn in place speeds up and brakes at the angular acceleration
limit (a trapezoid, or a triangle when short); a curve on a base with acceleration limits takes
its time-optimal profile's time (`SpeedProfile.duration_s`, planned with the request); a straight
line there speeds up at `max_linear_accel` and brakes at the braking limit; without limits a
curve takes each segment at the speed its curvature allows at the whole turn rate (a rounded
curve's profile plans so, and an exact curve's follower drives so). The kinematic bound
(`Path.lower_bound_s`: length over top speed, turns over top turn rate) ignores all of these:
on a base it said 26.4 s for a text that took 77 s.
"""

from __future__ import annotations

import math

import numpy as np

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.profile import SpeedProfile
from turtle_traj.core.geometry.path import Path, Polyline, Turn


def ramp_s(distance: float, top: float, speeding_up: float, braking: float) -> float:
    """The least time to cover `distance` from rest to rest at most at `top`, changing speed at
    most at these rates (0: at once)."""
    if distance <= 0.0 or top <= 0.0:
        return 0.0
    up = top / (2.0 * speeding_up) if speeding_up else 0.0  # time/2 per unit of top
    down = top / (2.0 * braking) if braking else 0.0
    if distance >= top * (up + down):  # reaches the top speed: a trapezoid
        return distance / top + up + down
    # a triangle: the peak v with v²/2a + v²/2d = distance
    rates = [rate for rate in (speeding_up, braking) if rate]
    peak = math.sqrt(2.0 * distance / sum(1.0 / rate for rate in rates))
    return sum(peak / rate for rate in rates)


def _curve_s(polyline: Polyline, config: ControlConfig) -> float:
    """A curve without acceleration limits: each segment at the speed its curvature allows."""
    cap = config.angular_speed / np.maximum(np.abs(polyline.curvatures), 1e-9)
    return float(np.sum(polyline.segment_lengths / np.minimum(config.linear_speed, cap)))


def least_time_s(path: Path, config: ControlConfig,
                 profiles: tuple[SpeedProfile | None, ...] = ()) -> float:
    """The least time the controller can drive `path` in under `config` (see the module)."""
    total = 0.0
    for index, leg in enumerate(path.legs):
        if isinstance(leg, Turn):
            total += ramp_s(abs(leg.sweep_rad), config.angular_speed, config.max_angular_accel,
                            config.max_angular_accel)
            continue
        profile = profiles[index] if profiles else None
        if profile is not None and math.isfinite(profile.duration_s):
            total += profile.duration_s
        elif config.max_linear_accel:
            total += ramp_s(leg.length, config.linear_speed, config.max_linear_accel,
                            config.linear_braking)
        else:
            total += _curve_s(leg, config)
    return total
