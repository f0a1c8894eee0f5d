"""Which of the fleet's moves may start now, as the moves really end. Pure.

`timing.simulate` predicts, from nominal durations, an order in which the moves start while
keeping the turtles apart. Real moves end sooner or later than predicted, so the schedule keeps
that order only where it matters: a move waits until every move of another turtle whose path
comes within the clearance of its own, and which started before it in the prediction, has
ended. Moves whose paths stay apart run whenever their turtle is ready.

Two moves that come near each other then never run at once, and a turtle never stands where
another's move passes (a standing point lies on the paths of the moves on either side of it, so
those moves are ordered too). And no turtle waits for ever: the unstarted move that comes first
in the prediction waits only for moves that started before it, and they end. This is the
coordination diagram's passing order kept fixed (Siméon, Leroy and Laumond, IEEE T-RA 18(1),
2002) while the speed along the diagram is left to the robots.
"""

from __future__ import annotations

from collections.abc import Sequence

import shapely

from turtle_traj.core.fleet.timing import Move, Timing


class Schedule:
    """The moves of each turtle's route (`routes`), started in the order `timing` predicted
    wherever two of them come within `clearance`."""

    def __init__(self, routes: Sequence[Sequence[Move]], timing: Timing,
                 clearance: float) -> None:
        self.routes = routes
        self.next_move = [0] * len(routes)  # per turtle: its first move not yet started
        self.driving = [False] * len(routes)
        self._ended: set[tuple[int, int]] = set()
        self._after = _earlier_conflicts(routes, timing.order, clearance)

    def ready(self) -> list[int]:
        """The turtles whose next move may start now, in turtle order."""
        return [turtle for turtle, route in enumerate(self.routes)
                if not self.driving[turtle] and self.next_move[turtle] < len(route)
                and self._after[turtle, self.next_move[turtle]] <= self._ended]

    def start(self, turtle: int) -> Move:
        """Mark `turtle`'s next move started (it must be ready) and return it."""
        move = self.routes[turtle][self.next_move[turtle]]
        self.driving[turtle] = True
        return move

    def end(self, turtle: int) -> None:
        """Mark the move `turtle` drives ended."""
        self._ended.add((turtle, self.next_move[turtle]))
        self.driving[turtle] = False
        self.next_move[turtle] += 1

    def abandon(self, turtle: int) -> None:
        """Mark the move `turtle` drives given up: not ended, and driven no more."""
        self.driving[turtle] = False

    @property
    def done(self) -> bool:
        return all(index >= len(route) for index, route in zip(self.next_move, self.routes,
                                                               strict=True))

    def ended(self, turtle: int) -> list[Move]:
        """`turtle`'s moves that ended."""
        return list(self.routes[turtle][:self.next_move[turtle]])

    def left(self, turtle: int) -> list[Move]:
        """`turtle`'s moves not ended: the one it drives, and those after."""
        return list(self.routes[turtle][self.next_move[turtle]:])


def _earlier_conflicts(routes: Sequence[Sequence[Move]], order: Sequence[tuple[int, int]],
                       clearance: float) -> dict[tuple[int, int], frozenset[tuple[int, int]]]:
    """For every move (turtle, index): the other turtles' moves that come within `clearance`
    of its path and start before it in `order`."""
    shapes = [routes[turtle][index].shape for turtle, index in order]
    near = shapely.STRtree(shapes).query(shapes, predicate='dwithin', distance=clearance)
    after: dict[tuple[int, int], set[tuple[int, int]]] = {move: set() for move in order}
    for later, earlier in zip(*near, strict=True):
        if earlier < later and order[earlier][0] != order[later][0] and (
                shapely.distance(shapes[earlier], shapes[later]) < clearance):
            after[order[later]].add(order[earlier])
    return {move: frozenset(moves) for move, moves in after.items()}
