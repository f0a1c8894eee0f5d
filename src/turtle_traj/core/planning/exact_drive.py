"""The path driven exactly, as a timed trajectory: a start the minimum-time solver can improve.

Turn in place to each stretch's heading, then drive the stretch at a speed that its curvature's
turn rate and the acceleration allow, from rest to rest. It stays on the path, so it lies in any
tube around it; on a base with inertia it is feasible but for the angular acceleration along
curves, which it does not plan. Plain numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from turtle_traj.core.control.config import Limits
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Polyline
from turtle_traj.core.geometry.tube import resampled

CORNER_DEG = 10.0  # a vertex turning more than this ends a stretch: the robot stops and turns
_SPACING_M = 0.01  # between the samples of a stretch's speed profile
_UNLIMITED = 1e9  # an acceleration "at once", finite for the arithmetic


@dataclass(frozen=True)
class Timeline:
    """Samples of a motion: time (s), pose (x, y, heading) and velocities (speed, turn rate)
    at each, and the arc length of the path reached."""

    time: np.ndarray
    poses: np.ndarray  # (n, 3)
    velocities: np.ndarray  # (n, 2)
    progress: np.ndarray

    def at(self, instants: np.ndarray) -> Timeline:
        """The timeline interpolated at `instants` (s)."""
        def each(values: np.ndarray) -> np.ndarray:
            return np.column_stack([np.interp(instants, self.time, column)
                                    for column in values.T])
        return Timeline(instants, each(self.poses), each(self.velocities),
                        np.interp(instants, self.time, self.progress))


def exact_drive(points: np.ndarray, start_heading: float, limits: Limits) -> Timeline:
    """The motion along the polyline `points` that turns in place at its corners (see the
    module), from rest facing `start_heading` to rest at its last point, under `limits` (an
    acceleration of 0: at once)."""
    legs = np.diff(points, axis=0)
    headings = np.unwrap(np.arctan2(legs[:, 1], legs[:, 0]))
    turns = np.abs(np.diff(headings))
    cuts = [0, *(np.flatnonzero(turns > math.radians(CORNER_DEG)) + 1).tolist(), len(legs)]
    parts: list[Timeline] = []
    heading, clock, along = start_heading, 0.0, 0.0
    for first, last in zip(cuts[:-1], cuts[1:], strict=True):
        goal = heading + wrap_angle(headings[first] - heading)
        turn = _turn(points[first], heading, goal, limits.angular_speed,
                     limits.angular_accel or _UNLIMITED)
        stretch = _stretch(points[first:last + 1], goal, limits.linear_speed,
                           limits.angular_speed, limits.linear_accel or _UNLIMITED)
        for part in (turn, stretch):
            parts.append(Timeline(part.time + clock, part.poses, part.velocities,
                                  part.progress + along))
            clock = float(parts[-1].time[-1])
        along = float(parts[-1].progress[-1])
        heading = float(parts[-1].poses[-1, 2])
    return Timeline(*(np.concatenate([getattr(part, name) for part in parts])
                      for name in ('time', 'poses', 'velocities', 'progress')))


def rounded_corners(points: np.ndarray, tolerance_m: float, *, swing: bool) -> np.ndarray:
    """`points` with each corner (a vertex turning more than CORNER_DEG) replaced by an arc
    whose middle passes `tolerance_m` inside the vertex: tangent to both segments, or with
    `swing` tangent to the tube's outer edges (a larger arc: out, in across the corner, out),
    as large as half the shorter segment allows; sampled every degree."""
    rounded = [points[0]]
    for index in range(1, len(points) - 1):
        before, after = points[index] - points[index - 1], points[index + 1] - points[index]
        into, out_of = before / np.hypot(*before), after / np.hypot(*after)
        turn = math.atan2(into[0] * out_of[1] - into[1] * out_of[0], float(into @ out_of))
        if abs(turn) <= math.radians(CORNER_DEG):
            rounded.append(points[index])
            continue
        half = abs(turn) / 2.0
        outward = tolerance_m if swing else 0.0
        radius = (2.0 * tolerance_m if swing else tolerance_m * math.cos(half)) / (
            1.0 - math.cos(half))
        # the centre's distance along either segment from the vertex, at most half of it
        reach = min((radius - outward) * math.tan(half),
                    0.5 * min(np.hypot(*before), np.hypot(*after)))
        radius = outward + reach / math.tan(half)
        side = math.copysign(1.0, turn)
        inward = side * np.array([-into[1], into[0]])
        centre = points[index] - reach * into + (radius - outward) * inward
        begin = math.atan2(*(-inward)[::-1])
        angles = begin + np.linspace(0.0, turn, max(int(abs(math.degrees(turn))), 2) + 1)
        rounded.extend(centre + radius * np.column_stack([np.cos(angles), np.sin(angles)]))
    rounded.append(points[-1])
    return np.asarray(rounded)


def vertex_curvatures(points: np.ndarray) -> np.ndarray:
    """The signed curvature at each point of a polyline sampling a curve: each inner vertex's
    turn over the mean of its two segments; the ends take their neighbours'."""
    legs = np.diff(points, axis=0)
    lengths = np.hypot(legs[:, 0], legs[:, 1])
    turns = np.diff(np.unwrap(np.arctan2(legs[:, 1], legs[:, 0])))
    inner = turns / np.maximum(0.5 * (lengths[:-1] + lengths[1:]), 1e-12)
    if not len(inner):
        return np.zeros(len(points))
    return np.concatenate(([inner[0]], inner, [inner[-1]]))


def _turn(where: np.ndarray, heading: float, goal: float, top: float, rate: float) -> Timeline:
    """A turn in place from rest to rest: a trapezoid (or a triangle) of the turn rate."""
    sweep = abs(goal - heading)
    peak = min(top, math.sqrt(sweep * rate))
    total = (sweep / peak + peak / rate) if peak > 0 else 0.0
    time = np.linspace(0.0, total, 41)
    ramp = peak / rate
    rate_at = np.minimum.reduce([np.full_like(time, peak), time * rate, (total - time) * rate])
    swept = np.where(time <= ramp, 0.5 * rate * time ** 2,
                     np.where(time >= total - ramp, sweep - 0.5 * rate * (total - time) ** 2,
                              0.5 * peak * ramp + peak * (time - ramp)))
    sign = 1.0 if goal >= heading else -1.0
    poses = np.column_stack([np.full_like(time, where[0]), np.full_like(time, where[1]),
                             heading + sign * np.clip(swept, 0.0, sweep)])
    velocities = np.column_stack([np.zeros_like(time), sign * np.maximum(rate_at, 0.0)])
    return Timeline(time, poses, velocities, np.zeros_like(time))


def _stretch(points: np.ndarray, heading0: float, top: float, turn_rate: float,
             rate: float) -> Timeline:
    """One stretch from rest to rest, starting at `heading0` (unwrapped), each sample at the
    speed its curvature allows, speeding up and braking at `rate`."""
    arc = Polyline(points).cumulative_length
    xy = resampled(points, _SPACING_M)
    samples = np.linspace(0.0, arc[-1], len(xy))
    heading = np.unwrap(np.arctan2(*np.gradient(xy, axis=0).T[::-1]))
    heading += 2.0 * math.pi * round((heading0 - heading[0]) / (2.0 * math.pi))
    curvature = np.interp(samples, arc, vertex_curvatures(points))
    speed = np.minimum(top, turn_rate / np.maximum(np.abs(curvature), 1e-9))
    speed[0] = speed[-1] = 0.0
    gaps = np.diff(samples)
    for index in range(1, len(speed)):  # speeding up
        speed[index] = min(speed[index],
                           math.sqrt(speed[index - 1] ** 2 + 2 * rate * gaps[index - 1]))
    for index in range(len(speed) - 2, -1, -1):  # braking
        speed[index] = min(speed[index], math.sqrt(speed[index + 1] ** 2 + 2 * rate * gaps[index]))
    # each gap: from the lower speed to the higher at `rate`, then on at the higher
    low, high = np.minimum(speed[:-1], speed[1:]), np.maximum(np.maximum(speed[:-1], speed[1:]),
                                                               1e-9)
    ramp_m = (high ** 2 - low ** 2) / (2.0 * rate)
    time = np.concatenate(([0.0], np.cumsum((high - low) / rate + (gaps - ramp_m) / high)))
    turn = speed * curvature
    return Timeline(time, np.column_stack([xy, heading]), np.column_stack([speed, turn]),
                    samples)
