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
AHEAD_STEP_M, AHEAD_SPOTS = 0.05, 80  # and the spots straight ahead of a turtle, to 4 m
_CHUNK = 64  # spots judged at once


class Parking:
    """The spots `clearance` from the `pieces` and the turtles `standing` still, inside the
    `arena` (within its margin)."""

    def __init__(self, pieces: Sequence[Piece], clearance: float, arena: Arena,
                 standing: Sequence[Pose2D] = ()) -> None:
        self.distance, self._arena = clearance, arena
        self._sorted: dict[tuple[float, float, float], np.ndarray] = {}
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
        where it does), facing the way there; `end` where no spot does. The grid's spots are
        tried, and those straight ahead of `end` (finer: no turn to reach them)."""
        candidates = self._nearest_first(end)
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

    def _nearest_first(self, end: Pose2D) -> np.ndarray:
        """The spots that keep the distance, nearest `end` first (made once for each end)."""
        key = (end.x, end.y, end.theta)
        if key not in self._sorted:
            here = np.array([end.x, end.y])
            ahead = here + np.outer(np.arange(1, AHEAD_SPOTS + 1) * AHEAD_STEP_M,
                                    (math.cos(end.theta), math.sin(end.theta)))
            ahead = ahead[self._arena.inside(ahead)]
            spots = np.concatenate((ahead[self.clear_points(ahead)], self._spots))
            if self._clear(here):
                spots = np.concatenate(([here], spots))
            self._sorted[key] = spots[np.argsort(np.hypot(*(spots - here).T), kind='stable')]
        return self._sorted[key]

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
