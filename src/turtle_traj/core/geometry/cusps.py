"""Cusps turned short: where a path doubles back (a turn in place too sharp to round, between
two polylines driven the same way), the robot turns up to a width before the cusp and leaves
along the next polyline as far past it, instead of driving to the cusp and back. Pure Python.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Leg, Polyline, Turn
from turtle_traj.core.geometry.projection import all_near
from turtle_traj.core.geometry.tube import resampled

_SAMPLE_M = 0.005  # the new connection is checked against the path this often
# a connection meeting the next polyline at a sharper bend than this is turned in place there
_BEND_RAD = math.radians(1.0)


def cusps_cut_short(legs: Sequence[Leg], drawn: np.ndarray, width: float,
                    sharpest_rounded: float) -> tuple[Leg, ...]:
    """`legs` with every turn in place sweeping more than `sharpest_rounded` between two
    polylines driven the same way (and the pen the same) moved back along the first polyline
    by `width` (at most half of either polyline), the second polyline leaving from there to
    its point as far past the cusp; a cusp is left as it is where that connection would stray
    farther than `width` from the path as drawn (the polyline through `drawn`)."""
    out = list(legs)
    index = 0
    while (index := index + 1) < len(out) - 1:  # `out` grows as cusps are turned twice
        before, turn, after = out[index - 1], out[index], out[index + 1]
        if not (isinstance(turn, Turn) and isinstance(before, Polyline)
                and isinstance(after, Polyline) and abs(turn.sweep_rad) > sharpest_rounded
                and before.reverse == after.reverse and before.pen == after.pen
                and not before.repeat and not after.repeat):
            continue
        cut = min(width, 0.5 * before.length, 0.5 * after.length)
        if cut <= 0.0:
            continue
        kept = _until(before.points, before.cumulative_length, before.length - cut)
        onward = _from(after.points, after.cumulative_length, cut)
        turned_at = kept[-1]
        if math.dist(turned_at, onward[0]) < 1e-9:  # the legs lie on one line
            onward = onward[1:]
        leaving = np.concatenate(([turned_at], onward))
        if len(leaving) < 2 or not all_near(resampled(leaving[:2], _SAMPLE_M), drawn, width):
            continue
        cut_legs = _turned_twice(replace(before, points=kept, speeds=None), turn, before,
                                 after, leaving)
        out[index - 1:index + 2] = cut_legs
        index += len(cut_legs) - 3  # past the turns made here
    return tuple(out)


def _turned_twice(shortened: Polyline, turn: Turn, before: Polyline, after: Polyline,
                  leaving: np.ndarray) -> list[Leg]:
    """The shortened polyline, a turn onto `leaving` (a connection from where the robot turned
    to the polyline after the cusp, then along that polyline), and `leaving`. Where the
    connection meets that polyline at a bend sharper than `_BEND_RAD`, the connection and the
    rest are legs of their own with a turn in place between them. The turns sweep as much, the
    same way round, as `turn` did from `before`'s end to `after`'s start."""
    left = replace(after, points=leaving, speeds=None)
    start_shift = wrap_angle(float(shortened.headings[-1]) - float(before.headings[-1]))
    start = turn.start_heading + start_shift
    onto = turn.sweep_rad - start_shift + wrap_angle(float(left.headings[0])
                                                     - float(after.headings[0]))
    x, y = (float(v) for v in leaving[0])
    if len(leaving) < 3:
        return [shortened, Turn(x, y, start, onto), left]
    bend = (wrap_angle(float(left.headings[1]) - float(after.headings[0]))
            - wrap_angle(float(left.headings[0]) - float(after.headings[0])))
    if abs(bend) <= _BEND_RAD:
        return [shortened, Turn(x, y, start, onto), left]
    bx, by = (float(v) for v in leaving[1])
    return [shortened, Turn(x, y, start, onto), replace(after, points=leaving[:2], speeds=None),
            Turn(bx, by, start + onto, bend), replace(after, points=leaving[1:], speeds=None)]


def _until(points: np.ndarray, arc: np.ndarray, length: float) -> np.ndarray:
    """The polyline's points up to `length` along it, ending at the point there."""
    inside = arc < length - 1e-12
    return np.concatenate((points[inside], [_at(points, arc, length)]))


def _from(points: np.ndarray, arc: np.ndarray, length: float) -> np.ndarray:
    """The polyline's points from `length` along it, starting at the point there."""
    return np.concatenate(([_at(points, arc, length)], points[arc > length + 1e-12]))


def _at(points: np.ndarray, arc: np.ndarray, length: float) -> np.ndarray:
    return np.array([np.interp(length, arc, points[:, 0]), np.interp(length, arc, points[:, 1])])

