"""Independent geometry for checking recorded poses (deliberately not our planner's code)."""

import math

import numpy as np

from turtle_traj.geometry.path import distance_to_polyline  # noqa: F401  (re-exported)


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
