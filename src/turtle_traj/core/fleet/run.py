"""One drawing by a fleet, as it happens: which turtle drives which move next, what each drew,
and the drawing shared again among the others when a turtle is lost. Pure.

The node tells it what happens (`start`, `end`, `lose`); it answers what may start (`ready`).
A turtle that is lost (its node gone, its turtle gone, a move that fails) keeps nothing: every
piece it had not finished, the one it was drawing included, goes back to the drawing. The others
finish the moves they drive, and once none drives, what is left is shared among them from where
they stand, kept clear of lost turtles that still stand in the arena. A piece that passes within
the clearance of such a turtle cannot be drawn without coming that near it: it is left undrawn
(`blocked`), and the run says so. Each turtle's route ends where it parks, clear of the
drawing, so that the drawing is done once every route is (`parked`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import shapely

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.fleet.aside import SpotAside
from turtle_traj.core.fleet.moves import clear_spot
from turtle_traj.core.fleet.parking import Parking
from turtle_traj.core.fleet.pieces import Piece
from turtle_traj.core.fleet.refine import share_apart
from turtle_traj.core.fleet.schedule import Schedule
from turtle_traj.core.fleet.sharing import Sharing
from turtle_traj.core.fleet.timing import Move
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.shapes import Arena


@dataclass
class TurtleRecord:
    """What one turtle of the fleet did."""

    name: str
    pieces: int = 0  # pieces it drew
    max_deviation: float = 0.0  # [m] its largest distance from the pieces it drew
    lost: str = ''  # why it was lost ('' while it serves)


class FleetRun:
    """The pieces of one drawing (`pieces`, in tour order) drawn by the turtles `names`,
    standing at `starts`, at least `clearance` apart; `standing`: turtles that do not draw.
    In an `arena`, a turtle that drew parks off the drawing, near where it ended (`Parking`);
    else it goes back where it started.

    :raises Deadlock: no sharing of the drawing keeps the turtles apart without a deadlock.
    """

    def __init__(self, pieces: Sequence[Piece], names: Sequence[str], starts: Sequence[Pose2D],
                 config: ControlConfig, clearance: float, standing: Sequence[Pose2D] = (),
                 arena: Arena | None = None) -> None:
        self.pieces, self.config, self.clearance = pieces, config, clearance
        self.arena = arena
        self.turtles = [TurtleRecord(name) for name in names]
        self.drawn: set[int] = set()  # the pieces drawn, by index
        self.blocked: set[int] = set()  # pieces within the clearance of a turtle standing still
        self.first_sharing: Sharing | None = None
        self._share(list(range(len(names))), starts, standing)

    def _share(self, serving: list[int], starts: Sequence[Pose2D],
               standing: Sequence[Pose2D]) -> None:
        """Share the pieces not yet drawn among the turtles `serving` (indices), at `starts`;
        those within the clearance of a turtle `standing` still are set aside."""
        self.blocked |= self._near(standing)
        left = [index for index in range(len(self.pieces))
                if index not in self.drawn and index not in self.blocked]
        pieces = [self.pieces[index] for index in left]
        parking = (Parking(self.pieces, self.clearance, self.arena, standing)
                   if self.arena is not None else None)
        aside = (SpotAside(self.config, self.clearance, self.arena, parking)
                 if self.arena is not None else None)
        sharing = share_apart(pieces, starts, self.config, self.clearance, standing, parking,
                              aside)
        if self.first_sharing is None:
            self.first_sharing = sharing
        assert sharing.timing is not None
        moves = [[_renumbered(move, left) for move in route]
                 for route in sharing.timing.routes[:len(starts)]]
        self._serving = serving
        self._schedule = Schedule(moves, sharing.timing, self.clearance)
        self._replan_due = False

    def _near(self, standing: Sequence[Pose2D]) -> set[int]:
        """The pieces not drawn that pass within the clearance of a point in `standing`."""
        if not standing:
            return set()
        points = shapely.points([(pose.x, pose.y) for pose in standing])
        return {index for index, piece in enumerate(self.pieces) if index not in self.drawn
                and shapely.distance(shapely.LineString(piece.polyline.points), points).min()
                < self.clearance}

    def out_of_the_way(self, preferred: Pose2D, others: Sequence[Pose2D]) -> Pose2D:
        """Where to put a lost turtle: `preferred` (where it started), or else the spot along
        the arena's border nearest it, that is twice the clearance from every piece not drawn
        and from `others` (the turtles that serve, where they stand); `preferred` without an
        arena or such a spot."""
        if self.arena is None:
            return preferred
        left = [shapely.LineString(piece.polyline.points)
                for index, piece in enumerate(self.pieces) if index not in self.drawn]
        keep = shapely.union_all([*left, *(shapely.Point(p.x, p.y) for p in others)])
        return clear_spot(preferred, keep, 2.0 * self.clearance, self.arena)

    @property
    def planned_makespan_s(self) -> float:
        """When the first sharing's timing has every turtle parked, the drawing done."""
        assert self.first_sharing is not None and self.first_sharing.timing is not None
        return self.first_sharing.timing.makespan_s

    def ready(self) -> list[int]:
        """The turtles (by index in `names`) whose next move may start now."""
        if self._replan_due:
            return []
        return [self._serving[slot] for slot in self._schedule.ready()]

    def start(self, turtle: int) -> Move:
        return self._schedule.start(self._serving.index(turtle))

    def end(self, turtle: int, deviation: float) -> None:
        """`turtle`'s move ended as planned, at most `deviation` from its path (an end heard
        of a move no longer driven is ignored)."""
        if not self.driving(turtle):
            return
        slot = self._serving.index(turtle)
        move = self._schedule.routes[slot][self._schedule.next_move[slot]]
        self._schedule.end(slot)
        if move.pen:
            record = self.turtles[turtle]
            record.pieces += len(move.pieces)
            record.max_deviation = max(record.max_deviation, deviation)
            self.drawn.update(move.pieces)

    def end_failed(self, turtle: int) -> None:
        """`turtle`'s move ended short of its end (or will never be heard of again)."""
        if self.driving(turtle):
            self._schedule.abandon(self._serving.index(turtle))

    def lose(self, turtle: int, why: str) -> None:
        """`turtle` serves no more; what it had not drawn is shared again."""
        if turtle not in self._serving or self.turtles[turtle].lost:
            return
        self.turtles[turtle].lost = why
        self._replan_due = not self.done

    def driving(self, turtle: int) -> bool:
        return turtle in self._serving and self._schedule.driving[self._serving.index(turtle)]

    @property
    def replan_due(self) -> bool:
        """A turtle was lost and no turtle that serves is driving: share what is left."""
        return self._replan_due and not any(
            self.driving(turtle) for turtle in self._serving if not self.turtles[turtle].lost)

    def replan(self, poses: dict[int, Pose2D], standing: Sequence[Pose2D]) -> None:
        """Share what is left among the turtles that serve, standing at `poses` (by index).

        :raises Deadlock: they cannot finish it without blocking each other.
        :raises ValueError: no turtle serves any more.
        """
        serving = [turtle for turtle in range(len(self.turtles)) if not self.turtles[turtle].lost]
        self._share(serving, [poses[turtle] for turtle in serving], standing)

    @property
    def parked(self) -> bool:
        """Every turtle that serves drove its whole route: it ends parked clear of the drawing
        (`Parking`)."""
        return self._schedule.done and not any(self._schedule.driving)

    @property
    def serving(self) -> list[int]:
        return [turtle for turtle in self._serving if not self.turtles[turtle].lost]

    @property
    def done(self) -> bool:
        """Every piece is drawn, or set aside."""
        return len(self.drawn) + len(self.blocked) == len(self.pieces)

    def progress(self) -> float:
        """The share of the drawing's time drawn, 0 to 1."""
        total = sum(piece.time_s for piece in self.pieces)
        return (sum(self.pieces[index].time_s for index in self.drawn) / total
                if total > 0.0 else 1.0)

    def turtle_progress(self, turtle: int) -> float:
        """The share of `turtle`'s current route it has driven, 0 to 1 (1 once lost or idle)."""
        if turtle not in self._serving or self.turtles[turtle].lost:
            return 1.0
        slot = self._serving.index(turtle)
        route = self._schedule.routes[slot]
        total = sum(move.duration_s for move in route)
        driven = sum(move.duration_s for move in route[:self._schedule.next_move[slot]])
        return driven / total if total > 0.0 else 1.0


def _renumbered(move: Move, left: Sequence[int]) -> Move:
    """`move` with its pieces numbered as in the whole drawing (not in `left`)."""
    if not move.pieces:
        return move
    return replace(move, pieces=tuple(left[index] for index in move.pieces))


def closest(poses: Sequence[tuple[float, float]]) -> float:
    """The least distance between two of `poses` (inf for fewer than two)."""
    return min((math.dist(a, b) for i, a in enumerate(poses) for b in poses[i + 1:]),
               default=math.inf)
