"""What each turtle drives: its part of the pieces, as moves sent one request at a time. Pure.

A turtle gets to each of its pieces by a pen-up travel (in stretches of at most `PIECE_M`) that
ends facing the piece, or, standing at its start already, by a turn onto it (at a corner of the
drawing, the piece's own request turns first, as the drawing does: one request, not two); then
draws it; and parks once it drew its part, off the drawing and out of the others' way
(`parking`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.fleet.parking import Parking
from turtle_traj.core.fleet.pieces import JOINED_M, PIECE_M, Piece, request_s, travel_s
from turtle_traj.core.fleet.timing import Move
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.shapes import Arena


@dataclass(frozen=True)
class Share:
    """One turtle's part: the pieces it draws, by index in the tour, in the tour's order (or,
    `reverse`, from the last back to the first, each drawn end to start)."""

    pieces: tuple[int, ...]
    time_s: float  # travel included, from the turtle's start to its last piece's end
    reverse: bool = False


def routes(shares: Sequence[Share], pieces: Sequence[Piece], starts: Sequence[Pose2D],
           config: ControlConfig, parking: Parking | None = None,
           made: dict | None = None) -> list[list[Move]]:
    """Each turtle's moves, in order: for each of its pieces, a travel there (pen up) that ends
    facing it, or where the turtle stands there already, a turn onto it (pen down: it
    continues a stroke); then the piece. A turtle that drew then parks (`parking`'s spot
    nearest where it ended, clear of those of the turtles before it and of the turtles that
    stay), and so does one with nothing to draw that stands on the drawing (it would keep the
    others from it); without `parking`, a turtle that drew goes back where it started. `made`
    keeps the moves made, by what they are, for the next call (each sharing judged asks for
    most of the same moves again)."""
    made = {} if made is None else made
    moves: list[list[Move]] = []
    taken = [start for part, start in zip(shares, starts, strict=True)
             if not part.pieces and (parking is None or parking.clear(start))]
    for part, start in zip(shares, starts, strict=True):
        route: list[Move] = []
        here = start
        order = reversed(part.pieces) if part.reverse else part.pieces
        for index in order:
            piece = pieces[index]
            begin, end = piece.ends(part.reverse)
            turn, turn_s = abs(wrap_angle(begin.theta - here.theta)), 0.0
            if math.hypot(begin.x - here.x, begin.y - here.y) > JOINED_M:
                route += _made(made, ('way', here, begin), way, here, begin, config)
            elif turn > JOINED_M and piece.turned_onto(part.reverse):
                # a corner of the drawing: the piece's own follow-path turns onto it first
                turn_s = travel_s(here, begin, config)
            elif turn > JOINED_M:
                route += _made(made, ('turn', here, begin), _turn, here, begin, config)
            route += _made(made, ('piece', index, part.reverse, turn_s), _drawn, pieces, index,
                           part.reverse, turn_s, config)
            here = end
        if route or (parking is not None and not parking.clear(start)):
            home = start if parking is None else parking.spot(here, taken)
            taken.append(home)
            if math.hypot(home.x - here.x, home.y - here.y) > JOINED_M:
                route += _made(made, ('way', here, home), way, here, home, config)
        moves.append(route)
    return moves


def _made(made: dict, key: tuple, make: Callable[..., list[Move]], *args: Any) -> list[Move]:
    """The moves `key` names, made by `make(*args)` the first time."""
    moves = made.get(key)
    if moves is None:
        moves = made[key] = make(*args)
    return moves


def _turn(here: Pose2D, begin: Pose2D, config: ControlConfig) -> list[Move]:
    """The turn onto a piece that begins where the turtle stands (pen down)."""
    return [Move(np.array([(begin.x, begin.y)]), travel_s(here, begin, config)
                 + request_s(config), pen=True, heading=begin.theta, turns_first=True)]


def _drawn(pieces: Sequence[Piece], index: int, reverse: bool, turn_s: float,
           config: ControlConfig) -> list[Move]:
    """Piece `index`, drawn forwards or backwards, its turn onto it first if `turn_s`."""
    piece = pieces[index]
    points = piece.polyline.points
    return [Move(points[::-1] if reverse else points,
                 turn_s + piece.time_s + request_s(config), pen=True,
                 heading=piece.ends(reverse)[1].theta, pieces=(index,),
                 turns_first=turn_s > 0.0)]


def way(here: Pose2D, to: Pose2D, config: ControlConfig,
        longest: float = PIECE_M) -> list[Move]:
    """The pen-up way from `here` to `to`, in stretches no longer than `longest`: a turtle
    that waits for another to pass waits for a stretch of the way, not all of it."""
    count = max(1, math.ceil(math.hypot(to.x - here.x, to.y - here.y) / longest - 1e-9))
    facing = math.atan2(to.y - here.y, to.x - here.x)
    stops = [Pose2D(here.x + (to.x - here.x) * k / count, here.y + (to.y - here.y) * k / count,
                    facing) for k in range(1, count)] + [to]
    moves, at = [], here
    for stop in stops:
        moves.append(Move(np.array([(at.x, at.y), (stop.x, stop.y)]),
                          travel_s(at, stop, config) + request_s(config), heading=stop.theta))
        at = stop
    return moves


BORDER_STEP_M = 0.25  # spots along the arena's border tried for a turtle to stand out of the way


def clear_spot(preferred: Pose2D, keep: shapely.Geometry, distance: float,
               arena: Arena) -> Pose2D:
    """`preferred` if it is `distance` from `keep` (pieces, turtles), or else the spot along the
    arena's border nearest it that is; `preferred` when there is none."""
    low_x, low_y = arena.min_x + arena.margin, arena.min_y + arena.margin
    high_x, high_y = arena.max_x - arena.margin, arena.max_y - arena.margin
    border = shapely.LinearRing([(low_x, low_y), (high_x, low_y), (high_x, high_y),
                                 (low_x, high_y)])
    spots = [(preferred.x, preferred.y), *(border.interpolate(at).coords[0]
                                           for at in np.arange(0.0, border.length, BORDER_STEP_M))]
    clear = [spot for spot in spots
             if keep.is_empty or shapely.distance(shapely.Point(spot), keep) >= distance]
    if not clear:
        return preferred
    x, y = min(clear, key=lambda spot: math.dist(spot, (preferred.x, preferred.y)))
    return Pose2D(x, y, preferred.theta)
