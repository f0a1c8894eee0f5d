"""Independent geometry for checking recorded poses and drawings (deliberately not the planner's
code): distances to a polyline, the strokes a path draws, the ink on a canvas."""

import math

import numpy as np

from turtle_traj.core.geometry.path import Path, Polyline, Turn
from turtle_traj.core.turtlesim_contract import CANVAS_SIZE_PX
from turtle_traj.sim.canvas import Canvas, to_pixel


def regular_polygon(x: float, y: float, theta: float, sides: int, side: float,
                    clockwise: bool) -> np.ndarray:
    """Vertices (closed) of a polygon whose first side leaves (x, y) along theta."""
    sign = -1.0 if clockwise else 1.0
    vertices = [(x, y)]
    for k in range(sides):
        heading = theta + sign * 2.0 * math.pi * k / sides
        px, py = vertices[-1]
        vertices.append((px + side * math.cos(heading), py + side * math.sin(heading)))
    return np.array(vertices)


def xy(poses) -> np.ndarray:
    return np.array([(p.x, p.y) for p in poses])


def distance_to_polyline(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Per point, the distance to the nearest segment of the polyline through `vertices`."""
    starts, along = vertices[:-1], np.diff(vertices, axis=0)
    squared = np.maximum((along ** 2).sum(axis=1), 1e-300)
    distances = []
    for chunk in np.array_split(points, max(1, len(points) // 256)):  # chunk x segments x 2
        offset = chunk[:, None, :] - starts[None]
        t = np.clip((offset * along[None]).sum(axis=2) / squared, 0.0, 1.0)
        gap = offset - t[..., None] * along[None]
        distances.append(np.sqrt((gap ** 2).sum(axis=2)).min(axis=1))
    return np.concatenate(distances)


def drawn_strokes(path: Path) -> list[np.ndarray]:
    """The pen-down polylines of a path, consecutive pen-down curves joined (for checks)."""
    strokes: list[list[np.ndarray]] = []
    pen_was_down = False
    for leg in path.legs:
        if isinstance(leg, Turn):
            continue
        if leg.pen and pen_was_down:
            strokes[-1].append(leg.points[1:])
        elif leg.pen:
            strokes.append([leg.points])
        pen_was_down = leg.pen
    return [np.concatenate(parts) for parts in strokes]


def pen_up_moves(path: Path) -> list[np.ndarray]:
    """The polylines driven with the pen up."""
    return [leg.points for leg in path.legs if isinstance(leg, Polyline) and not leg.pen]


def ink_at(canvas: Canvas, points_m: np.ndarray, rgb: tuple[int, int, int]) -> np.ndarray:
    """Per point (world metres, (N, 2)): the trail pixel of `canvas` under it has colour `rgb`."""
    pixels = np.array([to_pixel(x, y) for x, y in np.reshape(points_m, (-1, 2))])
    columns, rows = (np.clip(np.floor(pixels.reshape(-1, 2)).astype(int), 0,
                             CANVAS_SIZE_PX - 1).T)
    under = canvas.trails[rows, columns]
    return np.all(under[:, :3] == rgb, axis=1) & (under[:, 3] > 0)


def resampled(points: np.ndarray, spacing: float) -> np.ndarray:
    """Points along a polyline, at most `spacing` apart, its vertices included."""
    pieces = [np.linspace(a, b, max(math.ceil(math.dist(a, b) / spacing), 1) + 1)[:-1]
              for a, b in zip(points[:-1], points[1:], strict=True)]
    return np.concatenate(pieces + [points[-1:]])
