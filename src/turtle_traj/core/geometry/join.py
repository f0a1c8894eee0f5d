"""Joining a path from the robot's heading: where a tolerance allows, the robot drives off
along the heading it has and curves onto the path, instead of turning in place first.

A join is a quintic Hermite curve. It leaves the start along the robot's heading, curving as
sharply as the turn ahead asks (a base turns cheaply while it is still slow), and meets a point
of the path's first stretch along its tangent and at its curvature, so the turn rate changes
smoothly where it meets the path. `joined_start` tries meeting points from one tolerance to 32
along the stretch, with a few shapes each, keeps the joins within the tolerance of the path as
drawn, and takes the fastest by the caller's measure of time where it beats turning in place;
where the tube is too tight to curve through the whole turn, half of it may be turned first.
Pure Python.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.corners import shape_width
from turtle_traj.core.geometry.path import Path, Polyline, Turn
from turtle_traj.core.geometry.projection import all_near
from turtle_traj.core.geometry.tube import SPACING_M, resampled

MEETING_TOLERANCES = tuple(math.sqrt(2.0) ** power for power in range(11))  # 1 to 32
# A join's shape: its tangents' lengths at the start and at the meeting point (shares of the
# chord), and its curvature at the start (the turn to make, over the chord, times the third)
Shape = tuple[float, float, float]
SHAPES: tuple[Shape, ...] = tuple(itertools.product((0.7, 1.0), (0.7, 1.0, 1.4),
                                                    (4.0, 8.0, 16.0, 32.0, 64.0)))
SCOUTING_SHAPES: tuple[Shape, ...] = ((0.7, 1.0, 8.0), (0.7, 1.4, 64.0))
SCOUTED = 3  # meeting points tried with every shape
TURNED_FIRST = (0.0, 0.5)  # shares of the turn made in place before a join
# Sharpest curvature of a join, 1/m: 0.1 rad per 2 cm step of the speed profile's grid, where
# alone TOPP-RA checks the limits (a sharper hook between two steps would be timed as free)
MAX_CURVATURE = 5.0
_FACING_RAD = 1e-3  # a smaller turn in place at the start is left as it is
_FINE = 400  # samples of a join, before the joined stretch is resampled every SPACING_M
_RUN_ON_M = 1.0  # past the farthest meeting point, where the candidates' times are compared


@dataclass(frozen=True)
class Joined:
    """A stretch joined from the robot's heading, and where the join meets it (m along it)."""

    meeting: float
    stretch: Polyline


def hermite_join(start: np.ndarray, heading: float, start_curvature: float, end: np.ndarray,
                 end_heading: float, end_curvature: float,
                 tangents_m: tuple[float, float]) -> np.ndarray:
    """Points of the quintic from `start` along `heading` at `start_curvature` to `end` along
    `end_heading` at `end_curvature` (curvatures signed, 1/m), its tangents at either end
    `tangents_m` long; finely sampled, its ends kept."""
    t = np.linspace(0.0, 1.0, _FINE + 1)[:, None]
    t2, t3, t4, t5 = t * t, t ** 3, t ** 4, t ** 5
    leaving, arriving = tangents_m

    def direction(angle: float) -> np.ndarray:
        return np.array([math.cos(angle), math.sin(angle)])

    return ((1 - 10 * t3 + 15 * t4 - 6 * t5) * start
            + (t - 6 * t3 + 8 * t4 - 3 * t5) * leaving * direction(heading)
            + (0.5 * t2 - 1.5 * t3 + 1.5 * t4 - 0.5 * t5)
            * leaving ** 2 * start_curvature * direction(heading + 0.5 * math.pi)
            + (0.5 * t3 - t4 + 0.5 * t5)
            * arriving ** 2 * end_curvature * direction(end_heading + 0.5 * math.pi)
            + (-4 * t3 + 7 * t4 - 3 * t5) * arriving * direction(end_heading)
            + (10 * t3 - 15 * t4 + 6 * t5) * end)


def join_candidates(stretch: Polyline, heading: float, drawn: Polyline, tolerance: float,
                    meetings: Sequence[float], shapes: Sequence[Shape]) -> list[Joined]:
    """`stretch` joined from its start along `heading` (see the module) at each of these
    `meetings` (metres along it) by each of these `shapes`, where the join keeps within the
    width a shape may use of `tolerance` (`corners.shape_width`) of `drawn` (the path as
    drawn, as far as the join can reach)."""
    points, arc = stretch.points, stretch.cumulative_length
    curvatures = stretch.tangent_curvatures
    slack = max(drawn.length - stretch.length, 0.0) + 2.0 * tolerance
    width = shape_width(tolerance)
    candidates = []
    for meeting in meetings:
        if meeting + 0.5 * SPACING_M >= arc[-1]:
            continue
        index = int(np.searchsorted(arc, meeting, side='right')) - 1  # the segment it is on
        fraction = (meeting - arc[index]) / (arc[index + 1] - arc[index])
        end = points[index] + fraction * (points[index + 1] - points[index])
        nearby = drawn.points[:max(int(np.searchsorted(drawn.cumulative_length,
                                                       meeting + slack)) + 1, 2)]
        rest = points[int(np.searchsorted(arc, meeting + 0.5 * SPACING_M)):]
        chord = float(np.hypot(*(end - points[0])))
        end_heading = float(stretch.headings[index])
        turn = wrap_angle(end_heading - heading)
        for leaving, arriving, bend in shapes:
            join = hermite_join(points[0], heading, bend * turn / chord, end, end_heading,
                                float(curvatures[index]), (leaving * chord, arriving * chord))
            if (np.max(np.abs(Polyline(join).curvatures)) <= MAX_CURVATURE
                    and all_near(join, nearby, width)):
                # evenly spaced throughout: uneven chords bend the heading's spline (`profile`)
                candidates.append(Joined(meeting, replace(stretch, points=resampled(
                    np.concatenate((join, rest)), SPACING_M), speeds=None)))
    return candidates


def joined_start(path: Path, drawn: Polyline, tolerance: float,
                 duration: Callable[[Polyline], float],
                 turn_duration: Callable[[Turn], float]) -> Path:
    """`path` with its first turn in place and the stretch after it replaced by the fastest
    join from the turn's start heading, where that takes less time than the turn and the
    stretch; `path` unchanged when it does not begin with a turn before a stretch driven
    forwards (where the follower steers onto a path that leaves off its heading, no time of
    its steering is known to compare a join with). Where no join through the whole turn
    beats it, a join may follow a share of the turn made in place (TURNED_FIRST: a tight
    tube leaves no room to curve through the whole turn). Every meeting point is scouted
    with SCOUTING_SHAPES, and the SCOUTED fastest with every one of SHAPES. Candidates are
    timed as far as _RUN_ON_M past the farthest meeting point, where they all drive the
    stretch again."""
    start = _turn_before_stretch(path)
    if start is None or tolerance <= 0.0:
        return path
    turn, stretch = start
    meetings = [share * tolerance for share in MEETING_TOLERANCES]
    compared = stretch.length - (meetings[-1] + _RUN_ON_M)

    def timed(joins: list[Joined]) -> list[tuple[float, Joined]]:
        """Each join's time as far as where the stretch has `compared` metres left, fastest
        first."""
        def window_s(polyline: Polyline) -> float:
            kept = max(np.count_nonzero(polyline.cumulative_length
                                        <= polyline.length - compared), 2)
            return duration(replace(polyline, points=polyline.points[:kept], speeds=None))
        return sorted(((window_s(joined.stretch), joined) for joined in joins),
                      key=lambda pair: pair[0])

    def fastest(heading: float) -> tuple[float, Joined | None]:
        """The fastest join from `heading` and its time: every meeting point scouted, the
        best few tried with every shape."""
        scouts = timed(join_candidates(stretch, heading, drawn, tolerance, meetings,
                                       SCOUTING_SHAPES))
        meeting = list(dict.fromkeys(joined.meeting for _, joined in scouts))[:SCOUTED]
        tried = scouts[:1] + timed(join_candidates(stretch, heading, drawn, tolerance, meeting,
                                                   SHAPES))[:1]
        return min(tried, key=lambda pair: pair[0], default=(math.inf, None))

    best_s = timed([Joined(0.0, stretch)])[0][0] + turn_duration(turn)
    for share in TURNED_FIRST:
        first = replace(turn, sweep_rad=share * turn.sweep_rad)
        took, joined = fastest(first.start_heading + first.sweep_rad)
        took += turn_duration(first) if share else 0.0
        if joined is not None and took < best_s:  # no turning first beats a whole join
            return replace(path, legs=((first,) if share else ()) + (joined.stretch,)
                           + path.legs[2:])
    return path


def _turn_before_stretch(path: Path) -> tuple[Turn, Polyline] | None:
    """The turn in place `path` begins with and the stretch after it, driven forwards; None
    when it does not begin so."""
    turn, stretch = path.legs[0], path.legs[1] if len(path.legs) > 1 else None
    if (isinstance(turn, Turn) and abs(turn.sweep_rad) > _FACING_RAD
            and isinstance(stretch, Polyline) and not stretch.reverse and not stretch.repeat):
        return turn, stretch
    return None
