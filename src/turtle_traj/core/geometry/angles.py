"""Angle helpers; every heading lives in [-pi, pi)."""

import math

import numpy as np


def wrap_angle(angle_rad: float) -> float:
    """Wrap an angle into [-pi, pi)."""
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


def shortest_angular_distance(from_rad: float, to_rad: float) -> float:
    """Signed smallest rotation that turns `from_rad` into `to_rad`, in [-pi, pi)."""
    return wrap_angle(to_rad - from_rad)


def wrap_angles(angles_rad: np.ndarray) -> np.ndarray:
    """`wrap_angle` of every element."""
    return (np.asarray(angles_rad) + math.pi) % (2.0 * math.pi) - math.pi
