"""Drawings: strokes drawn with the pen down, joined by pen-up moves in a short order.

A stroke is an (N, 2) polyline in metres. `order_strokes` picks the order and direction of
the strokes (nearest neighbour from the turtle, each stroke entered at its nearer end), and
`drawing_path` turns them into one Path: a pen-up curve to each stroke's start (turning in
place first), then the stroke itself with its sharp corners turned in place.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from turtle_traj.core.geometry.angles import wrap_angle
from turtle_traj.core.geometry.path import Leg, Path, Pose2D, Turn, legs_from_polyline

MIN_STROKE_M = 1e-6  # shorter strokes leave no ink and are dropped
TWO_OPT_PASSES = 20  # each O(n^2): 500 strokes are ordered in under half a second


def _nearest_neighbour(strokes: Sequence[np.ndarray], here: np.ndarray) -> list[np.ndarray]:
    remaining = list(strokes)
    ordered = []
    while remaining:
        to_first = np.hypot(*(np.array([stroke[0] for stroke in remaining]) - here).T)
        to_last = np.hypot(*(np.array([stroke[-1] for stroke in remaining]) - here).T)
        index = int(np.argmin(np.minimum(to_first, to_last)))
        stroke = remaining.pop(index)
        ordered.append(stroke[::-1] if to_last[index] < to_first[index] else stroke)
        here = ordered[-1][-1]
    return ordered


def _two_opt(strokes: list[np.ndarray], here: np.ndarray) -> list[np.ndarray]:
    """Reverse runs of strokes (order and direction) while that shortens the pen-up moves, for
    at most TWO_OPT_PASSES passes over the strokes."""
    strokes = list(strokes)
    def ends_of(strokes: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Each stroke's start, and where the turtle is before each stroke (and after all)."""
        return (np.array([stroke[0] for stroke in strokes]),
                np.array([here] + [stroke[-1] for stroke in strokes]))
    starts, ends = ends_of(strokes)
    for _ in range(TWO_OPT_PASSES):
        improved = False
        for i in range(len(strokes)):
            # Reversing strokes i..j joins ends[i] to the end of j, and the start of i to j + 1.
            j = np.arange(i, len(strokes))
            before = np.hypot(*(ends[i] - starts[i]))
            after_j = np.hypot(*(starts[j[:-1] + 1] - ends[j[:-1] + 1]).T)
            old = before + np.append(after_j, 0.0)
            new = (np.hypot(*(ends[j + 1] - ends[i]).T)
                   + np.append(np.hypot(*(starts[j[:-1] + 1] - starts[i]).T), 0.0))
            gain = old - new
            best = int(np.argmax(gain))
            if gain[best] > 1e-9:
                last = i + best
                strokes[i:last + 1] = [stroke[::-1] for stroke in reversed(strokes[i:last + 1])]
                starts, ends = ends_of(strokes)
                improved = True
        if not improved:
            break
    return strokes


def order_strokes(strokes: Sequence[np.ndarray], start: tuple[float, float]) -> list[np.ndarray]:
    """The strokes in an order with short pen-up moves from `start`: nearest neighbour (each
    stroke entered at its nearer end), improved by 2-opt (reversing runs of strokes), and never
    worse than the order given. Stroke direction carries no meaning in a drawing."""
    here = np.asarray(start, dtype=float)
    improved = _two_opt(_nearest_neighbour(strokes, here), here)
    given = list(strokes)
    return min((improved, given), key=lambda order: pen_up_length(order, start))


def pen_up_length(strokes: Sequence[np.ndarray], start: tuple[float, float]) -> float:
    """Distance travelled with the pen up to draw `strokes` in this order from `start`."""
    ends = [np.asarray(start, dtype=float)] + [stroke[-1] for stroke in strokes[:-1]]
    return float(sum(math.dist(end, stroke[0]) for end, stroke in zip(ends, strokes, strict=True)))


def _heading_after(legs: Sequence[Leg], heading: float) -> float:
    if not legs:
        return heading
    leg = legs[-1]
    if isinstance(leg, Turn):
        return wrap_angle(leg.start_heading + leg.sweep_rad)
    return float(leg.headings[-1])


def _lined_up(x: float, y: float, heading: float, points: np.ndarray, *,
              corner_angle_rad: float, pen: bool) -> list[Leg]:
    """The legs along `points` from (x, y): a turn in place onto the first segment however
    small (a stroke starts exactly on its line), then the polyline's own legs."""
    legs: list[Leg] = []
    first = points[1] - points[0]
    change = wrap_angle(math.atan2(first[1], first[0]) - heading)
    if abs(change) > 1e-9:
        legs.append(Turn(x, y, heading, change))
        heading += change
    return legs + legs_from_polyline(Pose2D(x, y, heading), points,
                                     corner_angle_rad=corner_angle_rad, pen=pen)


def drawing_path(start: Pose2D, strokes: Sequence[np.ndarray], *,
                 corner_angle_rad: float) -> Path:
    """Drive to each stroke with the pen up and along it with the pen down, in this order;
    every pen-up move and every stroke starts with a turn onto its first segment."""
    legs: list[Leg] = []
    x, y, heading = start.x, start.y, start.theta
    for stroke in strokes:
        stroke = stroke[np.concatenate(([True], np.hypot(*np.diff(stroke, axis=0).T) > 1e-9))]
        if len(stroke) < 2:
            continue
        for points, pen in (np.array([(x, y), stroke[0]]), False), (stroke, True):
            if not pen and math.dist((x, y), stroke[0]) <= MIN_STROKE_M:
                continue
            added = _lined_up(x, y, heading, points, corner_angle_rad=corner_angle_rad, pen=pen)
            legs += added
            heading = _heading_after(added, heading)
            x, y = points[-1]
    return Path(tuple(legs))
