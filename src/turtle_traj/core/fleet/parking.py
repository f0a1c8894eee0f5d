"""Where a turtle that drew its part parks: out of the others' way, near where it ended. Pure.

A turtle parked on the drawing would keep the others from it for ever, so a spot keeps the
clearance from every piece (no turtle drawing one comes nearer), from the turtles that stand
still and from the spots taken before it. Of those, the turtle takes the nearest to where its
last piece ended: the drawing is done once every turtle has parked, so the way there is part
of what a user waits for.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import shapely

from turtle_traj.core.fleet.pieces import Piece
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.shapes import Arena

SPOT_STEP_M = 0.25  # the grid of spots tried, across the arena
_CHUNK = 64  # spots judged at once


class Parking:
    """The spots `clearance` from the `pieces` and the turtles `standing` still, inside the
    `arena` (within its margin)."""

    def __init__(self, pieces: Sequence[Piece], clearance: float, arena: Arena,
                 standing: Sequence[Pose2D] = ()) -> None:
        self.distance = clearance
        keep = shapely.union_all([*(shapely.LineString(piece.polyline.points)
                                    for piece in pieces),
                                  *(shapely.Point(pose.x, pose.y) for pose in standing)])
        self._keep = keep
        xs = np.arange(arena.min_x + arena.margin, arena.max_x - arena.margin + 1e-9,
                       SPOT_STEP_M)
        ys = np.arange(arena.min_y + arena.margin, arena.max_y - arena.margin + 1e-9,
                       SPOT_STEP_M)
        grid = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
        self._spots = grid[self.clear_points(grid)]

    def spot(self, end: Pose2D, taken: Sequence[Pose2D]) -> Pose2D:
        """The spot nearest `end` that keeps the distance from the spots `taken` (`end` itself
        where it does), facing the way there; `end` where no spot does."""
        here = np.array([end.x, end.y])
        candidates = np.concatenate(([here], self._spots)) if self._clear(here) else self._spots
        candidates = candidates[np.argsort(np.hypot(*(candidates - here).T), kind='stable')]
        others = np.array([(pose.x, pose.y) for pose in taken]).reshape(-1, 2)
        for first in range(0, len(candidates), _CHUNK):  # nearest first, a chunk at a time
            chunk = candidates[first:first + _CHUNK]
            gaps = np.hypot(*(chunk[:, None, :] - others[None]).transpose(2, 0, 1))
            keeps = np.flatnonzero(np.all(gaps >= self.distance, axis=1))
            if len(keeps):
                break
        else:
            return end
        x, y = chunk[keeps[0]]
        if math.dist((x, y), (end.x, end.y)) < 1e-9:
            return end
        return Pose2D(float(x), float(y), math.atan2(y - end.y, x - end.x))

    def clear(self, pose: Pose2D) -> bool:
        """`pose` keeps the distance from the pieces and the turtles standing still."""
        return self._clear(np.array([pose.x, pose.y]))

    def clear_points(self, points: np.ndarray) -> np.ndarray:
        """Per point of `points` (N, 2): it keeps the distance, as `clear` says."""
        if self._keep.is_empty:
            return np.ones(len(points), dtype=bool)
        return shapely.distance(shapely.points(points), self._keep) >= self.distance

    def _clear(self, point: np.ndarray) -> bool:
        return bool(self.clear_points(point[None])[0])
