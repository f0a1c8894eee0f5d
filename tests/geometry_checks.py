"""Independent geometry for checking recorded poses (deliberately not our planner's code)."""

import math

import numpy as np


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
