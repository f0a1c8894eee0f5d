"""Independent geometry for checking recorded poses (deliberately not our planner's code)."""

import math

import numpy as np


def distance_to_polyline(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Distance of each point to the nearest segment of a polyline."""
    a, b = vertices[:-1], vertices[1:]
    ab = b - a
    ap = points[:, None, :] - a[None, :, :]
    t = np.clip(np.einsum('pkj,kj->pk', ap, ab) / np.einsum('kj,kj->k', ab, ab), 0.0, 1.0)
    nearest = a[None] + t[..., None] * ab[None]
    return np.min(np.linalg.norm(points[:, None, :] - nearest, axis=2), axis=1)


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
