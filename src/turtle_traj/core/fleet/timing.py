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
waiting turtle whose move is clear starts. Where each waits for another, the turtles in the way
of one waiting move step aside and come back after it (`StepAside`, `aside.SpotAside`): the
prediction puts those moves in the routes it returns, for the turtles to drive as any other.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Protocol

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
    turns_first: bool = False  # it begins with a turn in place (onto a piece)
    # [rad] pieces drawn as one follow-path: turned in place where its direction changes more
    # than this (0: as the node's corner_angle parameter has it)
    corner_angle: float = 0.0

    @property
    def end(self) -> tuple[float, float]:
        return float(self.points[-1][0]), float(self.points[-1][1])

    @cached_property
    def end_shape(self) -> shapely.Point:
        """Where it ends, as shapely measures it (made once)."""
        return shapely.Point(self.end)

    @cached_property
    def shape(self) -> shapely.Geometry:
        """Its path as shapely measures it (made once: a waiting move is asked about again)."""
        points = self.points
        return shapely.LineString(points) if len(points) > 1 else shapely.Point(points[0])


class Whereabouts:
    """Where each turtle may be now: the path of the move it drives, or the point it stands at."""

    def __init__(self, starts: Sequence[Pose2D]) -> None:
        self.shapes = np.array([shapely.Point(s.x, s.y) for s in starts], dtype=object)

    def driving(self, turtle: int, move: Move) -> None:
        self.shapes[turtle] = move.shape

    def standing(self, turtle: int, at: shapely.Point) -> None:
        self.shapes[turtle] = at

    def near(self, turtle: int, shape: shapely.Geometry, clearance: float) -> list[int]:
        """The other turtles whose whereabouts come within `clearance` of `shape`."""
        gaps = shapely.distance(shape, self.shapes)
        return [other for other in np.flatnonzero(gaps < clearance) if other != turtle]

    def clear(self, turtle: int, move: Move, clearance: float) -> bool:
        """Whether `turtle` may drive `move` now: its path keeps `clearance` from every other
        turtle's whereabouts."""
        return not self.near(turtle, move.shape, clearance)


class StepAside(Protocol):
    """Where a turtle standing `at` steps to, to let a waiting move pass: a move off its spot
    to one `clearance` from `clear_of` (and from `others`, the way there too), and the move
    back; None where there is no such spot. A turtle that has nothing left to drive (`stays`)
    stays there: the spot then keeps clear of the drawing too, as a parking spot does."""

    def __call__(self, at: Pose2D, clear_of: shapely.Geometry,
                 others: Sequence[shapely.Geometry],
                 stays: bool = False) -> tuple[Move, Move] | None: ...


@dataclass(frozen=True)
class Timing:
    """When each turtle starts each of its moves, as `simulate` predicts it, and the routes it
    predicted them for (those given, with any steps aside put in)."""

    starts_s: tuple[tuple[float, ...], ...]  # per turtle, per move
    order: tuple[tuple[int, int], ...]  # (turtle, move) of every move, in the order they start
    ends_s: tuple[float, ...]  # per turtle: when its last move ends (0 without moves)
    drawn_s: float  # when the last move that draws a piece ends: the drawing is complete
    waited_s: tuple[float, ...]  # per turtle: time spent waiting for others
    routes: tuple[tuple[Move, ...], ...] = ()
    asides: int = 0  # steps aside put in

    @property
    def makespan_s(self) -> float:
        return max(self.ends_s, default=0.0)


class Deadlock(Exception):
    """No waiting turtle can ever start: each waits for another; the message says which."""


def simulate(routes: Sequence[Sequence[Move]], starts: Sequence[Pose2D], clearance: float,
             step_aside: StepAside | None = None, staying: int = 0) -> Timing:
    """The timing the rule gives when every move takes its nominal duration.

    Where every turtle waits for another to move out of its way, and `step_aside` is given,
    the turtles in the way of the first waiting move that they can clear step aside (a move
    off and, if they have more to drive, one back once that move has ended), up to
    `MOST_ASIDES_PER_TURTLE` times the turtles. The last `staying` turtles never move.

    :raises Deadlock: the turtles would wait for each other for ever.
    """
    return _Prediction(routes, starts, clearance, step_aside, len(routes) - staying).run()


MOST_ASIDES_PER_TURTLE = 4


class _Prediction:
    """`simulate`'s state: the routes as they grow steps aside, what each turtle does."""

    def __init__(self, routes: Sequence[Sequence[Move]], starts: Sequence[Pose2D],
                 clearance: float, step_aside: StepAside | None, movable: int) -> None:
        self.routes = [list(route) for route in routes]
        self.movable = movable  # turtles 0 to this one excluded may step aside
        self.clearance, self.step_aside = clearance, step_aside
        self.where = Whereabouts(starts)
        self.facing = [start.theta for start in starts]
        self.next_move = [0] * len(routes)
        self.busy_until: list[float | None] = [None] * len(routes)
        self.waiting = {turtle for turtle, route in enumerate(routes) if route}  # idle, with
        # moves left
        self.ready_at = [0.0] * len(routes)  # since when each has waited for its next move
        self.begun: list[list[float]] = [[] for _ in routes]
        self.order: list[tuple[int, int]] = []
        self.waited = [0.0] * len(routes)
        self.ended: set[int] = set()  # ids of the moves ended
        self.held: dict[int, int] = {}  # id of a move back: id of the move it lets pass first
        self.asides = 0
        self.ends_heard = [0] * len(routes)  # per turtle: moves it ended
        # per turtle: its next move's id and the turtles found in its way, with their ends heard
        # then (while none of those ends another move, it stays in the way: a turtle that starts
        # a move only widens where it may be)
        self.in_the_way: list[tuple[int, dict[int, int]] | None] = [None] * len(routes)

    def run(self) -> Timing:
        now = 0.0
        while True:
            self._end_moves(now)
            self._start_moves(now)
            pending = [until for until in self.busy_until if until is not None]
            if pending:
                now = min(pending)
                continue
            stuck = sorted(self.waiting)
            if not stuck:
                break
            if not self._make_way(stuck):
                raise Deadlock('turtles ' + ', '.join(str(t + 1) for t in stuck) + ' each wait '
                               'for another to move out of the way of its next move')
        routes, begun = self.routes, self.begun
        ends = tuple(begun[t][-1] + routes[t][-1].duration_s if routes[t] else 0.0
                     for t in range(len(routes)))
        return Timing(tuple(map(tuple, begun)), tuple(self.order), ends, _drawn_s(routes, begun),
                      tuple(self.waited), tuple(map(tuple, routes)), self.asides)

    def _end_moves(self, now: float) -> None:
        """Moves ending now leave their turtle standing at their end."""
        for turtle, until in enumerate(self.busy_until):
            if until is not None and until <= now + 1e-12:
                move = self.routes[turtle][self.next_move[turtle] - 1]
                self.busy_until[turtle], self.ready_at[turtle] = None, now
                if self.next_move[turtle] < len(self.routes[turtle]):
                    self.waiting.add(turtle)
                self.ended.add(id(move))
                self.ends_heard[turtle] += 1
                self.facing[turtle] = move.heading
                self.where.standing(turtle, move.end_shape)

    def _start_moves(self, now: float) -> None:
        """In turtle order, every waiting turtle whose next move is clear starts it."""
        for turtle in sorted(self.waiting):
            move = self.routes[turtle][self.next_move[turtle]]
            if self._held(move) or self._blocked(turtle, move):
                continue
            self.waited[turtle] += now - self.ready_at[turtle]
            self.begun[turtle].append(now)
            self.order.append((turtle, self.next_move[turtle]))
            self.where.driving(turtle, move)
            self.busy_until[turtle] = now + move.duration_s
            self.next_move[turtle] += 1
            self.waiting.discard(turtle)

    def _blocked(self, turtle: int, move: Move) -> bool:
        """Whether another turtle may be within the clearance of `move` now (`Whereabouts`)."""
        known = self.in_the_way[turtle]
        if known is not None and known[0] == id(move) and known[1] and all(
                self.ends_heard[other] == heard for other, heard in known[1].items()):
            return True
        near = self.where.near(turtle, move.shape, self.clearance)
        self.in_the_way[turtle] = (id(move), {other: self.ends_heard[other] for other in near})
        return bool(near)

    def _held(self, move: Move) -> bool:
        """`move` is a step back that waits for the move it let pass to end."""
        return id(move) in self.held and self.held[id(move)] not in self.ended

    def _make_way(self, stuck: list[int]) -> bool:
        """The turtles in the way of the first of `stuck`'s moves that they can all clear step
        aside; False where none can, or the steps aside are used up."""
        if self.step_aside is None or self.asides >= MOST_ASIDES_PER_TURTLE * len(self.routes):
            return False
        for turtle in stuck:
            waiting = self.routes[turtle][self.next_move[turtle]]
            if self._held(waiting):
                continue  # it waits for a move that waits itself
            steps = self._steps_aside(turtle, waiting)
            if steps is None:
                continue
            for other, (off, back) in steps.items():
                index = self.next_move[other]
                more = index < len(self.routes[other])
                self.routes[other][index:index] = [off, back] if more else [off]
                self.waiting.add(other)  # it stands (all wait): its step aside is next
                if more:
                    self.held[id(back)] = id(waiting)
            self.asides += len(steps)
            return True
        return False

    def _steps_aside(self, turtle: int, waiting: Move) -> dict[int, tuple[Move, Move]] | None:
        """For each turtle in the way of `waiting`, its step aside and back; None if one of
        them has nowhere to go."""
        assert self.step_aside is not None
        others = list(self.where.shapes)
        steps: dict[int, tuple[Move, Move]] = {}
        for other in self.where.near(turtle, waiting.shape, self.clearance):
            if other >= self.movable:
                return None
            point = self.where.shapes[other]
            at = Pose2D(point.x, point.y, self.facing[other])
            step = self.step_aside(at, waiting.shape,
                                   [shape for index, shape in enumerate(others) if index != other],
                                   stays=self.next_move[other] >= len(self.routes[other]))
            if step is None:
                return None
            steps[other] = step
            others[other] = step[0].shape  # the next one keeps clear of its way
        return steps


def _drawn_s(routes: Sequence[Sequence[Move]], begun: Sequence[Sequence[float]]) -> float:
    """When the last move that draws a piece ends."""
    return max((at + move.duration_s for route, starts_s in zip(routes, begun, strict=True)
                for move, at in zip(route, starts_s, strict=True) if move.pieces), default=0.0)
