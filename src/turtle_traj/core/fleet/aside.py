"""Where a turtle in another's way steps aside to let it pass, and back. Pure.

Among many turtles, waiting alone can leave each of them waiting for another: one stands
where the next move of a second goes, while the second stands in the way of the first's. The
prediction (`timing.simulate`) then has the turtles in the way of one waiting move step aside:
each goes to the nearest spot, within the arena, that keeps the clearance from that move, from
where every other turtle may be and from the ways there, and comes back once the move has
ended (or stays, if it has nothing left to drive). This is the push of priority inheritance
with backtracking (PIBT, Okumura et al., Artificial Intelligence 310, 2022) on a continuous
floor: the waiting move is the agent with priority, the turtles in its way the ones pushed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import shapely

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.fleet.parking import Parking
from turtle_traj.core.fleet.pieces import request_s, travel_s
from turtle_traj.core.fleet.timing import Move
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.shapes import Arena

DIRECTIONS = 16  # spots tried round a turtle, on each ring
RING_STEP_M = 0.25  # the rings' spacing
FARTHEST_M = 4.0  # no spot farther than this


class SpotAside:
    """Steps aside (`timing.StepAside`) for turtles kept `clearance` apart in `arena`, timed as
    `config`'s turtles drive them; a turtle that stays where it stepped takes a spot `parking`
    allows too (clear of the drawing)."""

    def __init__(self, config: ControlConfig, clearance: float, arena: Arena,
                 parking: Parking | None = None) -> None:
        self.config, self.clearance, self.arena = config, clearance, arena
        self.parking = parking
        radii = np.arange(RING_STEP_M, FARTHEST_M + 1e-9, RING_STEP_M)
        angles = 2.0 * math.pi * np.arange(DIRECTIONS) / DIRECTIONS
        offsets = np.stack([np.outer(radii, np.cos(angles)).ravel(),
                            np.outer(radii, np.sin(angles)).ravel()], axis=1)
        self._offsets = offsets[np.argsort(np.hypot(*offsets.T), kind='stable')]

    def __call__(self, at: Pose2D, clear_of: shapely.Geometry,
                 others: Sequence[shapely.Geometry],
                 stays: bool = False) -> tuple[Move, Move] | None:
        spots = self._offsets + (at.x, at.y)
        spots = spots[self.arena.inside(spots)]
        if stays and self.parking is not None:
            spots = spots[self.parking.clear_points(spots)]
        keep = np.array([clear_of, *others], dtype=object)
        points = shapely.points(spots)
        apart = shapely.distance(points[:, None], keep[None, :]).min(axis=1) >= self.clearance
        away = np.array(others, dtype=object)
        for x, y in spots[apart]:  # nearest first
            way = shapely.LineString([(at.x, at.y), (x, y)])
            if not len(away) or shapely.distance(way, away).min() >= self.clearance:
                return self._moves(at, float(x), float(y))
        return None

    def _moves(self, at: Pose2D, x: float, y: float) -> tuple[Move, Move]:
        spot = Pose2D(x, y, math.atan2(y - at.y, x - at.x))
        off = Move(np.array([(at.x, at.y), (x, y)]),
                   travel_s(at, spot, self.config) + request_s(self.config), heading=spot.theta)
        back = Move(np.array([(x, y), (at.x, at.y)]),
                    travel_s(spot, at, self.config) + request_s(self.config), heading=at.theta)
        return off, back
