"""A drawing's pieces, and how long a turtle takes to draw one and to get to it. Pure Python.

The drawing is planned as for one turtle: its pen-down pieces, between two corners or pen-up
moves, in the order and direction the planner draws them, are one tour that already keeps the
pen-up travel short (`pieces_in`; a star is ten pieces, not one outline, and a long stroke is
cut into pieces of at most `PIECE_M`, so that it can be shared too). Each piece is timed as the
exact follower draws it (`duration.least_time_s`), getting from one pose to the next as a turn
to face it, the drive there and the turn onto it (`travel_s`), and each move a turtle is sent as
a request of its own costs `request_s` besides.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.duration import least_time_s, ramp_s
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Path, Polyline, Pose2D, Turn

JOINED_M = 1e-6  # a piece beginning this near where the turtle stands (and as near its heading,
# in radians) continues from there


@dataclass(frozen=True)
class Piece:
    """A piece drawn with the pen down, between two corners or pen-up moves, and how long the
    exact follower takes to draw it."""

    polyline: Polyline
    time_s: float
    # the drawing turns in place onto it where it begins (drawn forwards, backwards) at a
    # corner that a follow-path from the piece before it turns at too (`pieces_in`)
    cornered: tuple[bool, bool] = (False, False)

    def turned_onto(self, reverse: bool) -> bool:
        """The drawing turns in place onto it, drawn forwards or backwards (`cornered`)."""
        return self.cornered[reverse]

    def ends(self, reverse: bool) -> tuple[Pose2D, Pose2D]:
        """The pose it is started in and the pose it ends in, drawn forwards or backwards."""
        points, headings = self.polyline.points, self.polyline.headings
        if reverse:
            return (Pose2D(*points[-1], wrap_angle(float(headings[-1]) + math.pi)),
                    Pose2D(*points[0], wrap_angle(float(headings[0]) + math.pi)))
        return Pose2D(*points[0], float(headings[0])), Pose2D(*points[-1], float(headings[-1]))


PIECE_M = 1.0  # pieces longer than this are cut into even parts no longer


def pieces_in(path: Path, config: ControlConfig, longest: float = PIECE_M,
              corner_angle: float = math.inf) -> list[Piece]:
    """The pen-down pieces of a drawing's path, in its order, each at most `longest` long: a
    long stroke is cut where it goes straight on, so that several turtles can share it and a
    turtle waiting for another waits for a short stretch, not a whole stroke. A piece is
    `cornered` where the drawing turns onto it by more than `corner_angle` (the drawing nodes'
    own: a follow-path through it turns in place there first)."""
    legs, pieces = path.legs, []
    for index, leg in enumerate(legs):
        if not (isinstance(leg, Polyline) and leg.pen):
            continue
        before, after = (0 <= other < len(legs) and isinstance(legs[other], Turn)
                         and abs(legs[other].sweep_rad) > corner_angle
                         for other in (index - 1, index + 1))
        parts = _parts(leg, longest)
        pieces += [Piece(part, least_time_s(Path((part,)), config),
                         (before and number == 0, after and number == len(parts) - 1))
                   for number, part in enumerate(parts)]
    return pieces


def _parts(leg: Polyline, longest: float) -> list[Polyline]:
    """`leg` cut into the fewest even parts no longer than `longest`."""
    count = max(1, math.ceil(leg.length / longest - 1e-9))
    if count == 1:
        return [leg]
    along, points = leg.cumulative_length, leg.points
    cuts = np.linspace(0.0, along[-1], count + 1)
    parts = []
    for begin, end in zip(cuts, cuts[1:], strict=False):
        inside = (along > begin + JOINED_M) & (along < end - JOINED_M)  # no sliver at a cut
        ends = np.array([[np.interp(at, along, points[:, axis]) for axis in (0, 1)]
                         for at in (begin, end)])
        parts.append(replace(leg, points=np.concatenate(([ends[0]], points[inside], [ends[1]])),
                             speeds=None))
    return parts


def _turn_s(sweep: float, config: ControlConfig) -> float:
    """A turn in place as the node makes it: braking towards its end at `angular_braking`."""
    return ramp_s(abs(sweep), config.angular_speed, config.max_angular_accel,
                  config.angular_braking)


REQUEST_PERIODS = 3  # a move's request costs this many control periods besides its driving


def request_s(config: ControlConfig) -> float:
    """What driving a move as a request of its own costs besides the driving: its run ends a
    period after the turtle stops (when it reports standing), and the next run's first command
    goes out at the period after its request, which waits for that end (measured in lock-step:
    2 to 3 periods)."""
    return REQUEST_PERIODS * config.period_s


def travel_s(start: Pose2D, to: Pose2D, config: ControlConfig) -> float:
    """About how long a turtle at `start` takes to stand at `to`: turn to face it, drive there,
    turn to its heading."""
    dx, dy = to.x - start.x, to.y - start.y
    distance = math.hypot(dx, dy)
    if distance < 1e-9:
        return _turn_s(wrap_angle(to.theta - start.theta), config)
    towards = math.atan2(dy, dx)
    return (_turn_s(wrap_angle(towards - start.theta), config)
            + ramp_s(distance, config.linear_speed, config.max_linear_accel,
                     config.linear_braking if config.max_linear_accel else 0.0)
            + _turn_s(wrap_angle(to.theta - towards), config))
