"""A turtle's moves that run back to back, driven as one request where that changes nothing
for the others. Pure.

Each move a turtle is sent costs a request besides its driving (`pieces.request_s`: its run's
end is heard, the next is sent and started; three control periods). Where the prediction
(`timing.simulate`) has a turtle start a move the moment its last one ends, and no other
turtle's whereabouts come within the clearance of either while it drives them, the two can be
one request: the stretches of one pen-up way as one go-to, pen-down pieces and the turns
between them as one follow-path that turns in place exactly where the drawing does
(`Move.corner_angle`). The routes so chained are predicted again, a turtle at a time, and kept
where every turtle has parked sooner.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import shapely

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.fleet.pieces import JOINED_M, request_s
from turtle_traj.core.fleet.timing import Deadlock, Move, StepAside, Timing, simulate
from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.table import PARAMETER

PASSES = 3  # rounds over the turtles, while one of them makes the makespan shorter
_CORNER = PARAMETER['corner_angle']  # the corner angles a node takes


def chained(timing: Timing, starts: Sequence[Pose2D], clearance: float, config: ControlConfig,
            step_aside: StepAside | None = None, staying: int = 0) -> Timing:
    """`timing` with each turtle's back-to-back moves chained (`chain`), a turtle at a time,
    where the prediction of the chained routes ends sooner (its arguments are `simulate`'s)."""
    best = timing
    for _ in range(PASSES):
        shorter = False
        for turtle, route in enumerate(best.routes):
            chained_route = chain(best, turtle, starts, clearance, config)
            if len(chained_route) == len(route):
                continue
            routes = [*best.routes[:turtle], chained_route, *best.routes[turtle + 1:]]
            try:
                again = simulate(routes, starts, clearance, step_aside, staying)
            except Deadlock:
                continue
            if again.makespan_s < best.makespan_s - 1e-9:
                best, shorter = again, True
        if not shorter:
            break
    return best


def chain(timing: Timing, turtle: int, starts: Sequence[Pose2D], clearance: float,
          config: ControlConfig) -> list[Move]:
    """`turtle`'s route in `timing`, each run of moves it starts back to back made one move
    (`joined`) wherever no other turtle may be within `clearance` of it meanwhile."""
    route, begun = timing.routes[turtle], timing.starts_s[turtle]
    others = _Others(timing, starts, turtle)
    chained: list[Move] = []
    run: list[Move] = []  # the moves of the chain being made
    whole: Move | None = None  # that chain as one move
    since, facing = 0.0, starts[turtle].theta
    for index, move in enumerate(route):
        if run and abs(begun[index] - begun[index - 1] - route[index - 1].duration_s) < 1e-9:
            longer = joined([*run, move], facing, config)
            if longer is not None and others.apart(longer.shape, since,
                                                   begun[index] + move.duration_s, clearance):
                run, whole = [*run, move], longer
                continue
        facing = _close(run, whole, chained, facing, config)
        run, whole, since = [move], move, begun[index]
    _close(run, whole, chained, facing, config)
    return chained


def _close(run: list[Move], whole: Move | None, chained: list[Move], facing: float,
           config: ControlConfig) -> float:
    """Put `run` in `chained` as one move, `whole` (but a turn onto a piece that ends it stays
    a move of its own: a follow-path ends facing its last segment); the heading it leaves the
    turtle in."""
    if not run or whole is None:
        return facing
    if len(run) > 1 and run[-1].pen and not run[-1].pieces:
        *run, turn = run
        whole = joined(run, facing, config)
        assert whole is not None  # a part of a run that joined joins
        chained.extend((whole, turn))
    else:
        chained.append(whole)
    return chained[-1].heading


def joined(moves: Sequence[Move], facing: float, config: ControlConfig) -> Move | None:
    """`moves`, driven one after the other by a turtle facing `facing`, as one move; None if
    one request cannot drive them as they are (pen up and down mixed, a way that turns)."""
    if len(moves) == 1:
        return moves[0]
    if any(math.dist(a.end, b.points[0]) > JOINED_M
           for a, b in zip(moves, moves[1:], strict=False)):
        return None
    duration = sum(move.duration_s for move in moves) - (len(moves) - 1) * request_s(config)
    if all(move.pen for move in moves):
        return _drawn(moves, facing, duration)
    if not any(move.pen for move in moves):
        return _way(moves, duration)
    return None


def _way(moves: Sequence[Move], duration: float) -> Move | None:
    """Stretches of one straight pen-up way, as one go-to."""
    directions = [math.atan2(*(move.points[-1] - move.points[0])[::-1]) for move in moves]
    straight = all(len(move.points) == 2 for move in moves) and all(
        abs(wrap_angle(direction - directions[0])) < JOINED_M for direction in directions)
    if not straight or any(abs(wrap_angle(move.heading - directions[0])) > JOINED_M
                           for move in moves[:-1]):
        return None
    return Move(np.array([moves[0].points[0], moves[-1].points[-1]]), duration,
                heading=moves[-1].heading)


def _drawn(moves: Sequence[Move], facing: float, duration: float) -> Move | None:
    """Pieces and the turns between them as one follow-path: it turns in place where they do
    (where a move turns first) and nowhere else, or None if no corner angle tells the two
    apart."""
    points, corners = [moves[0].points[0]], [moves[0].turns_first]
    for move in moves:
        corners[-1] = corners[-1] or move.turns_first
        for point in move.points:
            if math.dist(point, points[-1]) > 1e-9:
                points.append(point)
                corners.append(False)
    if len(points) < 2:
        return None
    path = np.array(points)
    directions = np.arctan2(*np.diff(path, axis=0).T[::-1])
    changes = np.abs(wrap_angle(np.diff(np.concatenate(([facing], directions)))))
    turned = np.array(corners[:-1])  # where each segment begins
    if not turned.any():
        angle = 0.0  # as a single piece: its node's own
    else:
        sharp, smooth = changes[turned].min(), changes[~turned].max(initial=0.0)
        angle = min(0.5 * (sharp + smooth), _CORNER.high)
        if not smooth < angle < sharp or angle < _CORNER.low:
            return None
    return Move(path, duration, pen=True, heading=moves[-1].heading,
                pieces=tuple(index for move in moves for index in move.pieces),
                turns_first=moves[0].turns_first, corner_angle=angle)


class _Others:
    """Where the turtles other than `turtle` may be, and when, as `timing` predicts: each move
    while it is driven, each standing point between moves (and for ever after the last)."""

    def __init__(self, timing: Timing, starts: Sequence[Pose2D], turtle: int) -> None:
        froms, tos, shapes = [], [], []
        for other, (route, begun) in enumerate(zip(timing.routes, timing.starts_s, strict=True)):
            if other == turtle:
                continue
            here, free_s = shapely.Point(starts[other].x, starts[other].y), 0.0
            for move, at in zip(route, begun, strict=True):
                froms += [free_s, at]
                tos += [at, at + move.duration_s]
                shapes += [here, move.shape]
                here, free_s = move.end_shape, at + move.duration_s
            froms.append(free_s)
            tos.append(math.inf)
            shapes.append(here)
        self.froms, self.tos = np.array(froms), np.array(tos)
        self.shapes = np.array(shapes, dtype=object)

    def apart(self, shape: shapely.Geometry, begin_s: float, end_s: float,
              clearance: float) -> bool:
        """Whether every other turtle's whereabouts between `begin_s` and `end_s` keep
        `clearance` from `shape`."""
        meanwhile = (self.froms < end_s - 1e-9) & (self.tos > begin_s + 1e-9)
        if not meanwhile.any():
            return True
        return bool(shapely.distance(shape, self.shapes[meanwhile]).min() >= clearance)
