"""When each turtle of a fleet may start its next move, so that none comes near another. Pure.

Each turtle follows a route of moves (the travel to a piece, the piece), each a path it draws
exactly. Turtles keep apart by timing alone, never by leaving their paths: a turtle starts a
move only when the move's whole path keeps `clearance` from every other turtle's whereabouts,
and waits where it stands until then. Another turtle's whereabouts are the path of the move it
is driving, or the pose it stands at between moves (its start, or its last move's end).

This is velocity tuning in the sense of path-velocity decomposition (Kant and Zucker, 1986):
the paths are fixed, only the timing is chosen. Read on a coordination diagram (Siméon, Leroy
and Laumond, IEEE T-RA 18(1), 2002), it crosses the diagram's obstacle boxes never: a move is a
box edge, and two moves run at once only when their paths are apart. The rule needs no speeds,
so it holds applied to moves as they really end; `simulate` applies it to their nominal
durations to predict the makespan and find a deadlock (two turtles each waiting where the
other's next move goes) before a turtle moves. Turtles are served in their order: the first
waiting turtle whose move is clear starts.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely

from turtle_traj.core.geometry.path import Pose2D


@dataclass(frozen=True)
class Move:
    """A stretch a turtle drives as one request: its path, and how long it takes. A piece of
    the drawing follows its path; any other move (a travel, a turn onto a piece) turns to face
    its end, drives there and turns onto `heading`."""

    points: np.ndarray  # (N, 2), N >= 1
    duration_s: float
    pen: bool = False  # driven with the pen down
    heading: float = 0.0  # [rad] the heading it ends in
    pieces: tuple[int, ...] = ()  # a piece: the drawing's pieces it draws

    @property
    def end(self) -> tuple[float, float]:
        return float(self.points[-1][0]), float(self.points[-1][1])

    @cached_property
    def shape(self) -> shapely.Geometry:
        """Its path as shapely measures it (made once: a waiting move is asked about again)."""
        points = self.points
        return shapely.LineString(points) if len(points) > 1 else shapely.Point(points[0])


class Whereabouts:
    """Where each turtle may be now: the path of the move it drives, or the point it stands at."""

    def __init__(self, starts: Sequence[Pose2D]) -> None:
        self.shapes: list[shapely.Geometry] = [shapely.Point(s.x, s.y) for s in starts]

    def driving(self, turtle: int, move: Move) -> None:
        self.shapes[turtle] = move.shape

    def standing(self, turtle: int, at: tuple[float, float]) -> None:
        self.shapes[turtle] = shapely.Point(at)

    def clear(self, turtle: int, move: Move, clearance: float) -> bool:
        """Whether `turtle` may drive `move` now: its path keeps `clearance` from every other
        turtle's whereabouts."""
        return all(other == turtle or shapely.distance(move.shape, shape) >= clearance
                   for other, shape in enumerate(self.shapes))


@dataclass(frozen=True)
class Timing:
    """When each turtle starts each of its moves, as `simulate` predicts it."""

    starts_s: tuple[tuple[float, ...], ...]  # per turtle, per move
    order: tuple[tuple[int, int], ...]  # (turtle, move) of every move, in the order they start
    ends_s: tuple[float, ...]  # per turtle: when its last move ends (0 without moves)
    drawn_s: float  # when the last move that draws a piece ends: the drawing is complete
    waited_s: tuple[float, ...]  # per turtle: time spent waiting for others

    @property
    def makespan_s(self) -> float:
        return max(self.ends_s, default=0.0)


class Deadlock(Exception):
    """No waiting turtle can ever start: each waits for another; the message says which."""


def simulate(routes: Sequence[Sequence[Move]], starts: Sequence[Pose2D],
             clearance: float) -> Timing:
    """The timing the rule gives when every move takes its nominal duration.

    :raises Deadlock: the turtles would wait for each other for ever.
    """
    where = Whereabouts(starts)
    next_move = [0] * len(routes)
    busy_until: list[float | None] = [None] * len(routes)
    ready_at = [0.0] * len(routes)  # since when each has waited for its next move
    begun: list[list[float]] = [[] for _ in routes]
    order: list[tuple[int, int]] = []
    waited = [0.0] * len(routes)
    now = 0.0
    while True:
        for turtle, until in enumerate(busy_until):  # moves ending now leave their turtle there
            if until is not None and until <= now + 1e-12:
                busy_until[turtle], ready_at[turtle] = None, now
                where.standing(turtle, routes[turtle][next_move[turtle] - 1].end)
        for turtle, route in enumerate(routes):  # in order: the first clear one starts
            if busy_until[turtle] is None and next_move[turtle] < len(route):
                move = route[next_move[turtle]]
                if where.clear(turtle, move, clearance):
                    waited[turtle] += now - ready_at[turtle]
                    begun[turtle].append(now)
                    order.append((turtle, next_move[turtle]))
                    where.driving(turtle, move)
                    busy_until[turtle] = now + move.duration_s
                    next_move[turtle] += 1
        pending = [until for until in busy_until if until is not None]
        if not pending:
            stuck = [t for t, route in enumerate(routes) if next_move[t] < len(route)]
            if stuck:
                raise Deadlock('turtles ' + ', '.join(str(t + 1) for t in stuck) + ' each wait '
                               'for another to move out of the way of its next move')
            break
        now = min(pending)
    ends = tuple(begun[t][-1] + routes[t][-1].duration_s if routes[t] else 0.0
                 for t in range(len(routes)))
    return Timing(tuple(map(tuple, begun)), tuple(order), ends, _drawn_s(routes, begun),
                  tuple(waited))


def _drawn_s(routes: Sequence[Sequence[Move]], begun: Sequence[Sequence[float]]) -> float:
    """When the last move that draws a piece ends."""
    return max((at + move.duration_s for route, starts_s in zip(routes, begun, strict=True)
                for move, at in zip(route, starts_s, strict=True) if move.pieces), default=0.0)
