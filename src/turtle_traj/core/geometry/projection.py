"""Distances to a polyline and projections onto it: every such search of the package. Pure
Python.

`NearestOnPolyline` answers for any point, exactly, over the whole polyline. A robot moves a
few millimetres a control period, so the segment nearest to it is the last one or one nearby:
`PolylineSegments` searches a few segments around the last match, with plain floats (too few
for numpy to pay) and each segment's constants computed once.
`PolylineSegments.project` searches a given window, `PolylineSegments.walk` walks to the
nearest segment nearby; `PathDeviation` walks so, and asks the whole polyline
(`NearestOnPolyline`) only when a pose could be the farthest yet, so a run's largest deviation
stays exact wherever the path crosses itself. `LengthLeft` measures what is left of a path,
`WithinDistance` checks a smoothed curve against the one it was smoothed from,
`nearest_point` searches a window of points (pure pursuit's), and `nearest_samples` a window
of samples for every point of a curve at once (a smoothing's, `tube`); `all_near` says
whether points all keep within a distance of a polyline, and `excess_distance` how far
the farthest of them strays beyond it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

_LEAST_SQUARED = 1e-18  # m²: a segment of no length is projected on as a point


class PolylineSegments:
    """A polyline's segments as plain floats: start, direction, squared length, length."""

    def __init__(self, points: np.ndarray) -> None:
        xs, ys = points[:, 0].tolist(), points[:, 1].tolist()
        self.count = len(xs) - 1
        self._segments = []
        for index in range(self.count):
            dx, dy = xs[index + 1] - xs[index], ys[index + 1] - ys[index]
            squared = dx * dx + dy * dy
            squared = _LEAST_SQUARED if squared < _LEAST_SQUARED else squared
            self._segments.append((xs[index], ys[index], dx, dy, squared, math.sqrt(squared)))

    def distance(self, index: int, px: float, py: float) -> float:
        """Distance from (px, py) to segment `index`."""
        ax, ay, dx, dy, squared, _ = self._segments[index]
        fraction = ((px - ax) * dx + (py - ay) * dy) / squared
        fraction = 0.0 if fraction < 0.0 else 1.0 if fraction > 1.0 else fraction
        return math.hypot(px - (ax + dx * fraction), py - (ay + dy * fraction))

    def walk(self, start: int, px: float, py: float) -> tuple[int, float]:
        """The segment nearest to (px, py) found walking from segment `start`: on while the
        next one is no farther, then back while the one before is nearer; its index and
        distance. Where a point near the polyline stands along it, from where it stood (never
        a later part that passes by, as a loop back to the start does)."""
        index, nearest = start, self.distance(start, px, py)
        for step in (1, -1):
            while 0 <= index + step < self.count:
                distance = self.distance(index + step, px, py)
                if distance > nearest or (step < 0 and distance == nearest):
                    break
                index, nearest = index + step, distance
        return index, nearest

    def along(self, index: int, fraction: float, distance: float) -> tuple[int, float, float]:
        """The point `distance` further along the polyline from `fraction` of segment `index`
        (its end, if the polyline ends first): its segment's index, and x, y."""
        while True:
            ax, ay, dx, dy, _, length = self._segments[index]
            fraction += distance / length
            if fraction <= 1.0 or index == self.count - 1:
                fraction = min(fraction, 1.0)
                return index, ax + dx * fraction, ay + dy * fraction
            distance = (fraction - 1.0) * length
            index, fraction = index + 1, 0.0

    def project(self, px: float, py: float,
                candidates: Iterable[int]) -> tuple[int, float, float]:
        """The nearest of the `candidates` segments (the first of equals): its index, the
        fraction along it (0 to 1) and the signed offset (left of it positive)."""
        best_distance, best = math.inf, None
        for index in candidates:
            ax, ay, dx, dy, squared, length = self._segments[index]
            rx, ry = px - ax, py - ay
            fraction = (rx * dx + ry * dy) / squared
            fraction = 0.0 if fraction < 0.0 else 1.0 if fraction > 1.0 else fraction
            distance = math.hypot(px - (ax + dx * fraction), py - (ay + dy * fraction))
            if best is None or distance < best_distance:
                best_distance, best = distance, (index, fraction, (dx * ry - dy * rx) / length)
        return best


class NearestOnPolyline:
    """Distances of single points to a fixed polyline (K, 2), its segments prepared once.

    Exact, and quick for long polylines (a drawing has thousands of segments, and the distance
    is asked for at every pose): the segments are grouped in blocks with a bounding box each,
    and a block is searched only while its box is nearer than the nearest segment found.
    """

    _BLOCK = 256  # numpy calls cost more than their arithmetic below a few hundred

    def __init__(self, vertices: np.ndarray) -> None:
        vertices = np.asarray(vertices, dtype=float)
        if len(vertices) == 1:
            vertices = np.repeat(vertices, 2, axis=0)  # one point: a segment of no length
        self._starts = vertices[:-1]
        self._edges = np.diff(vertices, axis=0)
        self._squared = np.maximum(np.einsum('kj,kj->k', self._edges, self._edges), 1e-18)
        count = len(self._starts)
        self._blocks = [(first, min(first + self._BLOCK, count))
                        for first in range(0, count, self._BLOCK)]
        self._low = np.array([vertices[a:b + 1].min(axis=0)
                              for a, b in self._blocks])
        self._high = np.array([vertices[a:b + 1].max(axis=0) for a, b in self._blocks])
        self._vertices = vertices

    def _within(self, x: float, y: float, first: int, stop: int) -> tuple[float, int]:
        offsets = np.array([x, y]) - self._starts[first:stop]
        edges = self._edges[first:stop]
        along = np.clip(np.einsum('kj,kj->k', offsets, edges) / self._squared[first:stop],
                        0.0, 1.0)
        gaps = offsets - along[:, None] * edges
        squared = np.einsum('kj,kj->k', gaps, gaps)
        index = int(np.argmin(squared))
        return float(np.sqrt(squared[index])), first + index

    def distances(self, points: np.ndarray) -> np.ndarray:
        """Distance of each point (N, 2) to the nearest segment: all at once, by numpy for a
        polyline of one block, by shapely (GEOS, in C) for a longer one."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        if len(self._blocks) > 1:
            import shapely  # only when measured: the command line starts without it
            return shapely.distance(shapely.points(points), shapely.LineString(self._vertices))
        offsets = points[:, None, :] - self._starts[None, :, :]
        along = np.clip(np.einsum('nkj,kj->nk', offsets, self._edges) / self._squared, 0.0, 1.0)
        gaps = offsets - along[:, :, None] * self._edges[None, :, :]
        return np.sqrt(np.min(np.einsum('nkj,nkj->nk', gaps, gaps), axis=1))

    def distance(self, x: float, y: float) -> float:
        """Distance of (x, y) to the nearest segment."""
        return self.nearest(x, y)[0]

    def nearest(self, x: float, y: float) -> tuple[float, int]:
        """Distance of (x, y) to the nearest segment, and that segment's index."""
        if len(self._blocks) == 1:
            return self._within(x, y, 0, len(self._starts))
        point = np.array([x, y])
        outside = np.maximum(np.maximum(self._low - point, point - self._high), 0.0)
        bounds = np.hypot(outside[:, 0], outside[:, 1])
        nearest = (math.inf, 0)
        for block in np.argsort(bounds, kind='stable').tolist():
            if not bounds[block] < nearest[0]:
                break  # this box, and every later one, is no nearer than what was found
            nearest = min(nearest, self._within(x, y, *self._blocks[block]))
        return nearest


class PathDeviation:
    """Distances of successive poses from a fixed polyline, and the largest: exact.

    Each pose is first measured against the segment nearest to the last pose and its
    neighbours, walking on while the next one is nearer: a distance to some of the segments,
    never less than the true one. Only a pose whose walk finds it farther than the largest so
    far is measured against the whole polyline, which also gives the walk its new start.
    """

    def __init__(self, vertices: np.ndarray) -> None:
        vertices = np.asarray(vertices, dtype=float)
        if len(vertices) == 1:
            vertices = np.repeat(vertices, 2, axis=0)  # one point: a segment of no length
        self._whole = NearestOnPolyline(vertices)
        self._segments = PolylineSegments(vertices)
        self._segment = 0
        self._last: tuple[float, float] | None = None
        self.largest = 0.0

    def add(self, x: float, y: float) -> None:
        """A pose's position: measured, and the largest distance kept."""
        self._last = (x, y)
        if self._walk(x, y) > self.largest:
            distance, self._segment = self._whole.nearest(x, y)
            self.largest = max(self.largest, distance)

    @property
    def last(self) -> float:
        """The last pose's distance from the polyline (0 before any)."""
        return 0.0 if self._last is None else self.distance(*self._last)

    def distance(self, x: float, y: float) -> float:
        """Distance of any point from the polyline."""
        return self._whole.nearest(x, y)[0]

    def _walk(self, x: float, y: float) -> float:
        self._segment, nearest = self._segments.walk(self._segment, x, y)
        return nearest


class LengthLeft:
    """The length of a fixed polyline left from the point nearest to a given one to its end."""

    def __init__(self, vertices: np.ndarray) -> None:
        vertices = np.asarray(vertices, dtype=float)
        if len(vertices) == 1:
            vertices = np.repeat(vertices, 2, axis=0)
        self._whole = NearestOnPolyline(vertices)
        self._segments = PolylineSegments(vertices)
        self._lengths = np.hypot(*np.diff(vertices, axis=0).T).tolist()
        # after each segment's end
        self._after = (np.cumsum(self._lengths[::-1])[::-1] - self._lengths).tolist()

    def __call__(self, x: float, y: float) -> float:
        _, index = self._whole.nearest(x, y)
        _, fraction, _ = self._segments.project(x, y, (index,))
        return self._after[index] + (1.0 - fraction) * self._lengths[index]


class WithinDistance:
    """Whether every point of a curve smoothed from a polyline lies within a distance of the
    polyline where it was sampled: of its segments around the point's own arc position
    (`_NEIGHBOURS` on either side). Near another part of the curve is not enough: a smoothing
    that draws a point there (a rose's petals pulled into the centre they all pass through)
    leaves out the part it came from. Cheap enough to ask a dozen times while planning.

    :param cumulative: the polyline's arc length at each vertex.
    :param arc: the arc length at which each point to be asked about was sampled.
    """

    _NEIGHBOURS = 24

    def __init__(self, vertices: np.ndarray, cumulative: np.ndarray, arc: np.ndarray) -> None:
        starts, edges = vertices[:-1], np.diff(vertices, axis=0)
        last = len(starts) - 1
        at = np.clip(np.searchsorted(cumulative, arc, side='right') - 1, 0, last)
        near = np.clip(at[:, None] + np.arange(-self._NEIGHBOURS, self._NEIGHBOURS + 1), 0, last)
        self._starts, self._edges = starts[near], edges[near]  # (N, M, 2): each point's segments
        self._squared = np.maximum(np.einsum('nmj,nmj->nm', self._edges, self._edges), 1e-18)

    def __call__(self, points: np.ndarray, limit: float) -> bool:
        offsets = points[:, None, :] - self._starts
        along = np.clip(np.einsum('nmj,nmj->nm', offsets, self._edges) / self._squared,
                        0.0, 1.0)
        gaps = offsets - along[:, :, None] * self._edges
        return bool(np.all(np.min(np.einsum('nmj,nmj->nm', gaps, gaps), axis=1)
                           <= limit * limit))


def nearest_point(points: np.ndarray, first: int, count: int, x: float, y: float) -> int:
    """The index of the point of `points` (N, 2) nearest (x, y) among the `count` from
    `first` on (the first of equals)."""
    window = points[first:first + count]
    return first + int(np.argmin(np.hypot(window[:, 0] - x, window[:, 1] - y)))


def nearest_samples(points: np.ndarray, samples: np.ndarray, around: np.ndarray,
                    reach: int) -> np.ndarray:
    """For each of `points` (N, 2), the index of the nearest of `samples` (N, 2) within
    `reach` of the index `around` gives it (the first of equals): where each point of a
    smoothed curve now stands along the path it was smoothed from, all at once."""
    nearby = np.clip(around[:, None] + np.arange(-reach, reach + 1), 0, len(samples) - 1)
    gaps = np.hypot(points[:, None, 0] - samples[nearby, 0],
                    points[:, None, 1] - samples[nearby, 1])
    return nearby[np.arange(len(points)), gaps.argmin(axis=1)]


def all_near(points: np.ndarray, vertices: np.ndarray, distance: float) -> bool:
    """Every one of `points` (N, 2) within `distance` of the polyline through `vertices`
    (shapely's prepared geometry: an index over its segments)."""
    import shapely  # only when asked: the command line starts without it

    line = shapely.LineString(vertices)
    shapely.prepare(line)
    return bool(np.all(shapely.dwithin(line, shapely.points(points), distance)))


def excess_distance(points: np.ndarray, vertices: np.ndarray, distance: float) -> float:
    """How much farther than `distance` the farthest of `points` (N, 2) is from the polyline
    through `vertices`; 0 when they all keep within it."""
    import shapely  # only when asked: the command line starts without it

    line = shapely.LineString(vertices)
    shapely.prepare(line)
    located = shapely.points(points)
    beyond = located[~shapely.dwithin(line, located, distance)]
    return float(shapely.distance(line, beyond).max()) - distance if len(beyond) else 0.0
