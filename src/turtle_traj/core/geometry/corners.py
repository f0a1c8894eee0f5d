"""Rounded corners and smoothed curves, within a tolerance of the path as drawn.

A corner (a turn in place between two polylines) becomes a symmetric pair of clothoids, or a
clothoid, an arc and a clothoid; a curve is smoothed (`smoothed_curve`); given how long a base
takes along a polyline, a stretch of polylines and corners becomes the fastest of that, its
corners swung out (`swing`: racing lines) and its smoothings within the tolerance's tube
(`tube`: a grid planner's staircase becomes a curve).

A clothoid's curvature grows linearly with arc length, so a base driving it at a steady speed
changes its turn rate steadily: it keeps moving through the corner, within its angular
acceleration. The pair is scaled so that its apex, the point farthest from the drawn path,
stays within the tolerance of both legs; it is made smaller when the legs are too short for
it. Pure Python.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from functools import lru_cache

import numpy as np

from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.cusps import cusps_cut_short
from turtle_traj.core.geometry.path import Leg, Path, Polyline, Turn
from turtle_traj.core.geometry.projection import WithinDistance, excess_distance
from turtle_traj.core.geometry.swing import swung_out
from turtle_traj.core.geometry.tube import (
    WINDOWS_M,
    gaussian_smoothed,
    resampled,
    tube_smoothed,
)

MAX_ROUNDED_RAD = math.radians(170.0)  # sharper corners are turned in place
_KINK_RAD = 0.02  # largest change of direction between two samples of a clothoid
_SAMPLE_M = 0.01  # largest distance between two samples (the speed profile's grid is 2 cm)
_INTEGRATION_STEPS = 4000
_SMOOTHING_SEARCH_STEPS = 12
# Shares of the tolerance the drawn shape may use: the rest, and at least _TRACKING_M, is for
# tracking it (the exact follower keeps within 0.3 mm of a circle on turtlesim).
_SHAPE_SHARE = 0.97
_SMOOTHING_SHARE = 0.95
_TRACKING_M = 0.0005
_AIM_RAD = 1e-9  # a turn in place off the heading of a stroke beside it by more is re-aimed
SWING_SHARES = (0.5, 0.75, 1.0)  # of the shape's width, how far a racing line swings out
_SWING_TRIES = 3  # roundings of a racing line, each narrowed by the last one's excess
_SWING_NARROWING = 1.2  # the rounding narrows by this much more than its apex's excess
_ROUNDING_M = 1e-9  # a moved vertex is as far outside as the shape may go, but for rounding


def shape_width(tolerance: float) -> float:
    """How far from the path as drawn a shape (a rounded corner, a smoothing, a join) may go
    within `tolerance`: the rest is for tracking it."""
    return _shape_width(tolerance, _SHAPE_SHARE)


def _shape_width(tolerance: float, share: float) -> float:
    """How far from the path as drawn the shape may go, of a `tolerance`."""
    return max(min(share * tolerance, tolerance - _TRACKING_M), 0.0)


@lru_cache(maxsize=256)
def _unit_half(deflection: float,
               top_curvature: float) -> tuple[np.ndarray, float, float, float]:
    """Half of a unit corner for a `deflection` > 0: curvature grows as arc length up to
    `top_curvature` (inf: a clothoid pair), then holds (an arc) until half the deflection.
    Its points from the tangent point to the apex in the frame of the incoming leg, finely
    integrated; its length; the tangent length (tangent point to corner); and the apex's
    distance from each leg."""
    half = 0.5 * deflection
    ramp = min(math.sqrt(2.0 * half), top_curvature)  # the clothoid's length (sharpness 1)
    length = ramp + max(half - 0.5 * ramp * ramp, 0.0) / ramp
    s = np.linspace(0.0, length, _INTEGRATION_STEPS + 1)
    heading = np.where(s <= ramp, 0.5 * s * s, 0.5 * ramp * ramp + ramp * (s - ramp))
    step = length / _INTEGRATION_STEPS
    # trapezoidal integration of (cos, sin) of the heading
    x = np.concatenate(([0.0], np.cumsum(0.5 * step * (np.cos(heading[1:])
                                                        + np.cos(heading[:-1])))))
    y = np.concatenate(([0.0], np.cumsum(0.5 * step * (np.sin(heading[1:])
                                                        + np.sin(heading[:-1])))))
    tangent = float(x[-1] + y[-1] * math.tan(half))
    return np.stack([x, y], axis=1), length, tangent, float(y[-1])


CLOTHOID_PAIR = math.inf  # the unit top curvature of a corner that is a clothoid pair

CornerCost = Callable[[np.ndarray, float, float], float]  # points, heading in, heading out
Timed = tuple[np.ndarray, np.ndarray]  # a motion's points (N, 2) and its speed at each (N,)


def arc_shape(turn_rate: float, turn_accel: float) -> float:
    """The unit top curvature of a clothoid-arc-clothoid corner that a base drives, scaled by
    k, at the steady speed k * sqrt(turn_accel) at its top `turn_rate`."""
    return turn_rate / math.sqrt(turn_accel)


def rounded_corner(corner: np.ndarray, heading_in: float, heading_out: float,
                   tolerance: float, room: float, shape: float = CLOTHOID_PAIR) -> np.ndarray:
    """Points replacing `corner`: a rounded corner of this `shape` (its unit top curvature)
    from the incoming leg to the outgoing one, its apex at most `tolerance` from either leg,
    reaching at most `room` along each leg."""
    deflection = wrap_angle(heading_out - heading_in)
    fine, length, tangent, apex = _unit_half(abs(deflection), shape)
    scale = min(_shape_width(tolerance, _SHAPE_SHARE) / apex, room / tangent)
    # samples every _SAMPLE_M at most, turning by at most _KINK_RAD from one to the next
    count = min(max(4, math.ceil(0.5 * abs(deflection) / _KINK_RAD),
                    math.ceil(length * scale / _SAMPLE_M)), _INTEGRATION_STEPS)
    half = fine[np.round(np.linspace(0, _INTEGRATION_STEPS, count + 1)).astype(int)]
    side = math.copysign(1.0, deflection)
    cos_in, sin_in = math.cos(heading_in), math.sin(heading_in)
    local = half * scale
    local[:, 0] -= tangent * scale  # from the tangent point, the corner at the origin
    local[:, 1] *= side
    first = np.stack([local[:, 0] * cos_in - local[:, 1] * sin_in,
                      local[:, 0] * sin_in + local[:, 1] * cos_in], axis=1)
    # the second half mirrors the first across the bisector through the corner
    normal = heading_in + 0.5 * deflection  # the bisector is perpendicular to this heading
    axis = np.array([math.cos(normal), math.sin(normal)])
    second = first - 2.0 * np.outer(first @ axis, axis)
    return corner + np.concatenate((first, second[-2::-1]))


def smoothed_curve(points: np.ndarray, tolerance: float) -> np.ndarray:
    """A curve through `points` smoothed as much as stays within `tolerance` of it: resampled
    every _SAMPLE_M and averaged with the widest Gaussian window along its length that keeps
    it there (`tube.gaussian_smoothed`: its ends and their directions kept)."""
    polyline = Polyline(np.asarray(points, dtype=float))
    samples = resampled(polyline.points, _SAMPLE_M)
    arc = np.linspace(0.0, polyline.length, len(samples))
    within = WithinDistance(polyline.points, polyline.cumulative_length, arc)
    best, low, high = samples, 0.0, max(polyline.length / 4.0, _SAMPLE_M)
    for _ in range(_SMOOTHING_SEARCH_STEPS):  # the widest window that keeps to the tolerance
        width = 0.5 * (low + high)
        candidate = gaussian_smoothed(samples, width / _SAMPLE_M)
        if within(candidate, _shape_width(tolerance, _SMOOTHING_SHARE)):
            best, low = candidate, width
        else:
            high = width
    return best


def rounded_path(path: Path, tolerance: float, shapes: Sequence[float] = (CLOTHOID_PAIR,),
                 cost: CornerCost | None = None,
                 duration: Callable[[Polyline], float] | None = None,
                 more: Callable[[np.ndarray, float], Timed | None] | None = None) -> Path:
    """`path` with its turns in place between two polylines replaced by rounded corners.

    A turn is rounded when both polylines are driven the same way with the pen in the same
    state and it turns by at most MAX_ROUNDED_RAD; a turn at the start or the end stays (the
    base starts and ends there). Polylines joined so make a stretch. Its corners are rounded
    one by one, each reaching at most half along either adjoining segment and taking the one
    of `shapes` its `cost` (the time it takes a base) finds least; a curve (a polyline of more
    than one segment) is smoothed within the tolerance first. Given the `duration` a base
    takes along a polyline, the stretch becomes the fastest of that, its corners swung out
    (`_swung_corners`), the stretch smoothed within the tolerance's tube by each of
    `tube.WINDOWS_M`, for a single curve the curve as it is, and `more(points, width)`:
    another curve of the caller's through the stretch's points within `width` of them, with
    the speed at each of its points where it is a motion planned in time (None: none). A turn
    too sharp to round that doubles the path back is turned short of the cusp
    (`cusps.cusps_cut_short`).
    """
    if tolerance <= 0.0:
        return path
    legs: list[Leg] = []
    for stretch in _stretches(path.legs):
        first = stretch[0]
        if isinstance(first, Turn) or (len(stretch) == 1 and (len(first.points) <= 2
                                                              or first.repeat)):
            legs.append(first)
            continue
        rounded, taken = _corners_rounded(stretch, tolerance, shapes, cost)
        candidates = [rounded]
        if duration is not None:
            candidates += _swung_corners(stretch, tolerance, taken)
            candidates += _smoothed_in_tube(stretch, tolerance, more)
            legs.append(min(candidates, key=duration))
        else:
            legs.append(candidates[0])
    return replace(path, legs=_turns_aimed(cusps_cut_short(
        legs, path.points(), shape_width(tolerance), MAX_ROUNDED_RAD)))


def _turns_aimed(legs: list[Leg]) -> tuple[Leg, ...]:
    """The turns in place beside a rounded stretch, aimed along it where that turns less: a
    smoothed curve leaves its start (and reaches its end) along its own tangent, not the
    path's first (last) segment, and a turn that ended on that segment's heading left the
    robot facing away from the curve it is to follow. A turn is never made longer: where the
    curve's tangent is further from the robot's heading, the follower steers onto it."""
    aimed = list(legs)
    for index, leg in enumerate(legs):
        if not isinstance(leg, Turn):
            continue
        before = legs[index - 1] if index > 0 else None
        after = legs[index + 1] if index + 1 < len(legs) else None
        start = leg.start_heading
        if isinstance(before, Polyline) and len(before.points) > 1:
            start = float(before.headings[-1]) + (math.pi if before.reverse else 0.0)
        end = leg.start_heading + leg.sweep_rad
        if isinstance(after, Polyline) and len(after.points) > 1:
            end = float(after.headings[0]) + (math.pi if after.reverse else 0.0)
        shift_start = wrap_angle(start - leg.start_heading)
        shift_end = wrap_angle(end - (leg.start_heading + leg.sweep_rad))
        sweep = leg.sweep_rad + shift_end - shift_start
        if ((abs(shift_start) > _AIM_RAD or abs(shift_end) > _AIM_RAD)
                and abs(sweep) < abs(leg.sweep_rad)):
            aimed[index] = Turn(leg.x, leg.y, leg.start_heading + shift_start, sweep)
    return tuple(aimed)


def _smoothed_in_tube(stretch: Sequence[Leg], tolerance: float,
                      more: Callable[[np.ndarray, float], Timed | None] | None = None,
                      ) -> list[Polyline]:
    """A stretch (see `_stretches`) smoothed within the tolerance's tube by each of
    `tube.WINDOWS_M` where that keeps to it, `more`'s curve (timed where it is driven
    forwards), and a single curve as it is."""
    first = stretch[0]
    assert isinstance(first, Polyline)
    joined = _joined_points(stretch)
    width = _shape_width(tolerance, _SHAPE_SHARE)
    smoothed = [(tube_smoothed(joined, width, window), None) for window in WINDOWS_M]
    if more is not None and (timed := more(joined, width)) is not None:
        smoothed.append((timed[0], None if first.reverse else timed[1]))
    candidates = [replace(first, points=points, speeds=speeds)
                  for points, speeds in smoothed if points is not None]
    return candidates + [first] if len(stretch) == 1 else candidates


def _swung_corners(stretch: Sequence[Leg], tolerance: float,
                   shapes: Sequence[float]) -> list[Polyline]:
    """A stretch with corners (see `_stretches`) as racing lines: its corners swung out
    (`swing.swung_out`) by each of SWING_SHARES of the width the shape may use, and rounded
    by these `shapes` (one for each corner) within the tolerance plus that, less what takes
    its apex beyond that width (its legs are tilted, so the apex's offset is measured, and
    the rounding narrowed by up to _SWING_TRIES measurements)."""
    if len(stretch) < 3:
        return []
    drawn = _joined_points(stretch)
    width = shape_width(tolerance)
    found = []
    for share in SWING_SHARES:
        moved = swung_out(stretch, share * width)
        rounding = (1.0 + share) * tolerance
        for _ in range(_SWING_TRIES):
            candidate, _ = _corners_rounded(moved, rounding, (), None, shapes)
            excess = excess_distance(candidate.points, drawn, width + _ROUNDING_M)
            if not excess:
                found.append(candidate)
                break
            rounding -= _SWING_NARROWING * excess / _SHAPE_SHARE
            if rounding <= 0.0:
                break
    return found


def _joined_points(stretch: Sequence[Leg]) -> np.ndarray:
    """The points of a stretch's polylines, one after the other."""
    first = stretch[0]
    assert isinstance(first, Polyline)
    return np.concatenate([first.points[:1]] + [leg.points[1:] for leg in stretch[::2]])


def _stretches(legs: Sequence[Leg]) -> list[list[Leg]]:
    """`legs` in runs: polylines joined by the turns between them that can be rounded
    (alternately a polyline and a turn, a polyline first and last), and every other leg alone."""
    runs: list[list[Leg]] = []
    for leg in legs:
        if (isinstance(leg, Polyline) and len(runs) >= 2 and len(runs[-1]) == 1
                and isinstance(runs[-1][0], Turn) and isinstance(runs[-2][-1], Polyline)
                and _joinable(runs[-2][-1], runs[-1][0], leg)):
            turn = runs.pop()[0]
            runs[-1] += [turn, leg]
        else:
            runs.append([leg])
    return runs


def _corners_rounded(stretch: Sequence[Leg], tolerance: float, shapes: Sequence[float],
                     cost: CornerCost | None,
                     each: Sequence[float] = ()) -> tuple[Polyline, list[float]]:
    """A stretch (see `_stretches`) as one polyline: its curves smoothed, then each corner
    rounded by the one of `shapes` its `cost` finds least, or by its own of `each` (a shape
    for each corner); and the shape each corner took."""
    joined: Polyline | None = None
    taken: list[float] = []
    for leg in stretch[::2]:
        assert isinstance(leg, Polyline)
        if len(leg.points) > 2:
            leg = replace(leg, points=smoothed_curve(leg.points, tolerance))
        if joined is None:
            joined = leg
            continue
        room = 0.499 * min(float(joined.segment_lengths[-1]), float(leg.segment_lengths[0]))
        heading_in = float(joined.headings[-1])
        heading_out = float(leg.headings[0])
        ours = each[len(taken):][:1] or shapes
        candidates = [(rounded_corner(joined.points[-1], heading_in, heading_out, tolerance,
                                      room, shape), shape) for shape in ours]
        corner, shape = candidates[0] if cost is None or len(candidates) == 1 else min(
            candidates, key=lambda pair: cost(pair[0], heading_in, heading_out))
        taken.append(shape)
        joined = replace(leg, points=np.concatenate((joined.points[:-1], corner,
                                                     leg.points[1:])))
    assert joined is not None
    return joined, taken


def _joinable(before: Polyline, turn: Turn, after: Polyline) -> bool:
    return (before.reverse == after.reverse and before.pen == after.pen
            and not before.repeat and not after.repeat
            and abs(turn.sweep_rad) <= MAX_ROUNDED_RAD
            and math.isclose(abs(wrap_angle(float(after.headings[0])
                                            - float(before.headings[-1]))),
                             abs(turn.sweep_rad), abs_tol=1e-6))
