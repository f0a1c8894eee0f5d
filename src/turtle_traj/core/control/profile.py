"""The fastest speed along a curve under a base's four limits: v, omega, a and alpha.

On a curve of curvature k(s), the turn rate is omega = v k and its rate of change
d(omega)/dt = a k + v² dk/ds: speed is bounded by the curvature and by its rate of change. The
path is handed to TOPP-RA (`toppra`, time-optimal path parameterisation by reachability
analysis) as a two-joint path q(s) = (s, heading(s)), whose joint velocity and acceleration
limits are exactly (v, omega) and (a, alpha). Pure Python; toppra (and SciPy under it) load
only when a base has acceleration limits.
"""

from __future__ import annotations

import math
import sys

import numpy as np

from turtle_traj.core.control.config import Limits
from turtle_traj.core.geometry.path import Polyline

# Shares of the limits an exact path's profile plans with: the rest is the steering's, to pull
# the base back onto the path. Speed itself is planned at its full limit. A path rounded within
# a tolerance plans with FULL_LIMITS: the tolerance's reserve (`corners.shape_width`) covers the
# steering's error there.
ANGULAR_SHARE = 0.95
ACCEL_SHARE = 1.0
ANGULAR_ACCEL_SHARE = 0.9
PLANNING_SHARES = (ANGULAR_SHARE, ACCEL_SHARE, ANGULAR_ACCEL_SHARE)
FULL_LIMITS = (1.0, 1.0, 1.0)  # the time-optimal bound itself
_GRID_STEP_M = 0.02  # profile resolution along the path
_STRAIGHT_M = 0.2  # a segment this long is a straight stretch, not a chord of a curve
_GRID_POINTS = (50, 2000)


def heading_knots(polyline: Polyline) -> tuple[np.ndarray, np.ndarray]:
    """Arc lengths and headings (unwrapped) to interpolate the heading along `polyline` by:
    each segment's direction at its middle (a chord's direction is the curve's tangent
    there), along a straight stretch longer than _STRAIGHT_M every grid step (a spline
    through sparse knots rings), and at both ends the tangent the nearest chords give."""
    headings = np.unwrap(polyline.headings)
    arc = polyline.cumulative_length
    knots, values = [arc[:1]], [headings[:1]]
    for index, length in enumerate(polyline.segment_lengths.tolist()):
        inner = int(length // _GRID_STEP_M) if length > _STRAIGHT_M else 1
        knots.append(arc[index] + length * np.arange(1, inner + 1) / (inner + 1))
        values.append(np.full(inner, headings[index]))
    knots.append(arc[-1:])
    values.append(headings[-1:])
    knots, values = np.concatenate(knots), np.concatenate(values)
    if len(knots) > 3:  # the tangent at either end, extrapolated from the nearest chords
        values[0] = values[1] - (values[2] - values[1]) * (knots[1] - knots[0]) / (
            knots[2] - knots[1])
        values[-1] = values[-2] + (values[-2] - values[-3]) * (knots[-1] - knots[-2]) / (
            knots[-2] - knots[-3])
    return knots, values


class SpeedProfile:
    """Top speed by arc length along one polyline that starts and ends at rest.

    :param duration_s: the time of the profile TOPP-RA computed (its time-optimal bound under
        the shares of the limits planned with), or of the motion planned in time.
    :param times: for a motion planned in time (`Polyline.speeds`), the instant it passes each
        point of `arc`, s: its clock, which the follower keeps to (`timed_tracker`); else None.
    """

    def __init__(self, arc: np.ndarray, speed: np.ndarray, duration_s: float,
                 times: np.ndarray | None = None) -> None:
        self.arc = arc
        self.speed = speed
        self.duration_s = duration_s
        self.times = times

    @classmethod
    def timed(cls, polyline: Polyline) -> SpeedProfile:
        """The profile of a polyline planned in time: its own speeds, each segment at a
        constant acceleration (it takes twice its length over the sum of its end speeds)."""
        assert polyline.speeds is not None
        speeds = np.maximum(np.asarray(polyline.speeds, dtype=float), 0.0)
        mean = np.maximum(0.5 * (speeds[:-1] + speeds[1:]), 1e-9)
        times = np.concatenate(([0.0], np.cumsum(polyline.segment_lengths / mean)))
        return cls(polyline.cumulative_length, speeds, float(times[-1]), times)

    def speed_at(self, arc_length: float) -> float:
        """The speed at `arc_length`: v² is linear in s under constant acceleration."""
        return math.sqrt(float(np.interp(arc_length, self.arc, self.speed ** 2)))

    @classmethod
    def plan(cls, polyline: Polyline, limits: Limits,
             shares: tuple[float, float, float] = PLANNING_SHARES,
             start_speed: float = 0.0) -> SpeedProfile:
        """The time-optimal profile of `polyline` under `limits` (a limit of 0 is
        unlimited: it is left out), taking these `shares` of the turn rate, the acceleration
        and the angular acceleration, from `start_speed` (from rest, if the limits cannot
        take that speed where the polyline begins)."""
        angular_share, accel_share, angular_accel_share = shares
        import toppra
        import toppra.algorithm
        import toppra.constraint

        toppra.setup_logging('WARNING')
        arc = polyline.cumulative_length
        length = float(arc[-1])
        knots, headings = heading_knots(polyline)
        path = toppra.SplineInterpolator(knots, np.stack([knots, headings], axis=1))
        inf = 1e6  # "unlimited", finite for the solver
        accel = (limits.linear_accel or inf) * accel_share
        decel = (limits.linear_braking or inf) * accel_share
        alpha = (limits.angular_accel or inf) * angular_accel_share
        constraints = [
            toppra.constraint.JointVelocityConstraint(
                np.array([limits.linear_speed, limits.angular_speed * angular_share])),
            toppra.constraint.JointAccelerationConstraint(
                np.array([[-decel, accel], [-alpha, alpha]]))]
        count = int(min(max(length / _GRID_STEP_M, _GRID_POINTS[0]), _GRID_POINTS[1]))
        grid = np.linspace(0.0, length, count + 1)
        instance = toppra.algorithm.TOPPRA(constraints, path, gridpoints=grid,
                                           parametrizer='ParametrizeConstAccel')
        speed = instance.compute_parameterization(start_speed, 0.0)[1]  # (sdd, sd, v): ds/dt
        if speed is None and start_speed:
            speed = instance.compute_parameterization(0.0, 0.0)[1]
        if speed is None:  # infeasible by the solver: fall back to the curvature's bound
            return cls.curvature_bound(polyline, limits)
        speed = np.maximum(np.asarray(speed, dtype=float), 0.0)
        gaps = np.diff(grid)
        mean = np.maximum(0.5 * (speed[:-1] + speed[1:]), 1e-9)
        return cls(grid, speed, float(np.sum(gaps / mean)))

    @classmethod
    def curvature_bound(cls, polyline: Polyline, limits: Limits,
                        angular_share: float = ANGULAR_SHARE) -> SpeedProfile:
        """The speed the curvature allows at each vertex under this share of the top turn
        rate, with no braking: an endless loop's, or a curve's on a base that changes speed at
        once (turtlesim), where its time is each segment's length at its own speed."""
        curvature = np.abs(polyline.curvatures)
        per_segment = np.minimum(limits.linear_speed, limits.angular_speed * angular_share
                                 / np.maximum(curvature, 1e-9))
        speed = np.concatenate((per_segment, [per_segment[-1]]))
        speed[1:-1] = np.minimum(per_segment[:-1], per_segment[1:])
        duration = math.nan if polyline.repeat else float(np.sum(polyline.segment_lengths
                                                                  / per_segment))
        return cls(polyline.cumulative_length, speed, duration)


def solver_loaded() -> bool:
    """TOPP-RA is imported (`load_solver` has run)."""
    return 'toppra.algorithm' in sys.modules


def load_solver() -> None:
    """Import TOPP-RA, and SciPy under it: 2.4-2.7 s here the first time, which a node should
    spend at start-up rather than in its first run on a base with acceleration limits (a
    simulator on its own clock counts it as time without progress)."""
    import toppra.algorithm  # noqa: F401
    import toppra.constraint  # noqa: F401


def profile_for(polyline: Polyline, limits: Limits, start_speed: float = 0.0,
                shares: tuple[float, float, float] = PLANNING_SHARES) -> SpeedProfile | None:
    """The profile a base follows on `polyline` (from `start_speed`, under these `shares` of
    its limits): the curvature's bound on an endless loop or without acceleration limits, the
    polyline's own timing where it was planned in time (from rest), the time-optimal profile
    on a curve, and None on a straight line (the window and braking alone bound it there)."""
    if polyline.speeds is not None and limits.limited and not start_speed:
        return SpeedProfile.timed(polyline)
    if polyline.repeat or not limits.limited:
        return SpeedProfile.curvature_bound(polyline, limits, shares[0])
    if not np.any(np.abs(polyline.curvatures) > 1e-9):
        return None
    return SpeedProfile.plan(polyline, limits, shares, start_speed)
