"""Driving on while turning onto the path, within the tube a tolerance leaves. Pure Python.

A robot that faces away from its path by more than the turn-first angle turns in place first:
exactly, on the path. Given a tolerance (a path rounded within it), a base with acceleration
limits may instead drive on slowly while it turns, as the minimum-time limit does where it
joins a path from another heading. Held at speed v while it closes a heading error e in the
least time T its turn rate and angular acceleration allow from rest and to rest, it drifts
sideways by v times the integral of sin(error) over T: at most v * e * T / 2, as such a turn's
error averages e / 2 (it is symmetric: what is left at t and what is turned by T - t add up to
e) and sin(error) <= error. `drift_speed` is the speed that keeps that bound within the room
the tube has left where the robot stands: the tolerance less its distance from the path as
drawn, so that, drifting any way, it stays within the tube. Asked every control period, the
speed grows as the error closes.
"""

from __future__ import annotations

import math

import numpy as np

from turtle_traj.core.control.config import Limits
from turtle_traj.core.control.duration import ramp_s
from turtle_traj.core.geometry.projection import NearestOnPolyline


class Tube:
    """The room a tolerance leaves round the path as drawn (its points prepared on first use)."""

    def __init__(self, drawn: np.ndarray, tolerance: float) -> None:
        self.tolerance = tolerance
        self._drawn = drawn
        self._nearest: NearestOnPolyline | None = None

    def room(self, x: float, y: float) -> float:
        """How much farther than (x, y) is from the path as drawn the motion may stray, m
        (negative: outside the tube)."""
        if self._nearest is None:
            self._nearest = NearestOnPolyline(self._drawn)
        return self.tolerance - self._nearest.distance(x, y)


def closing_time_s(heading_error: float, limits: Limits) -> float:
    """The least time to turn through `heading_error` from rest and stop turning, s."""
    return ramp_s(abs(heading_error), limits.angular_speed, limits.angular_accel,
                  limits.angular_accel)


def drift_speed(room: float, heading_error: float, limits: Limits) -> float:
    """The speed at which the sideways drift while `heading_error` closes stays within `room`
    (m/s, 0 where there is no room or the robot faces a quarter turn or more away)."""
    error = abs(heading_error)
    if room <= 0.0 or error >= math.pi / 2:
        return 0.0
    return 2.0 * room / (closing_time_s(error, limits) * error)
