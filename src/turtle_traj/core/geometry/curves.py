"""The classic parametric curves, as polylines in the drawing's own frame.

Each function returns (N, 2) points in metres in the drawing frame: x to the right, y up, the
curve's start at the origin. `shapes.anchored` places that frame on the turtle, x along its
heading, so a turtle heading east draws every curve upright, starting where it stands.
Points lie 5 mm apart along the curve, so the polyline stays within 0.1 mm of the curve
wherever its radius of curvature exceeds 3 cm; tighter spots (a heart's cusps) are kinks the
planner turns in place.
"""

from __future__ import annotations

import math

import numpy as np

SAMPLE_SPACING_M = 0.005
MIN_SAMPLES = 64
MAX_SAMPLES = 200_000  # a curve longer than 1 km is sampled more coarsely
# Evaluated this finely before resampling: the interpolation error is 4 um at a 3 cm radius.
DENSE_SPACING_M = 0.001
MAX_DENSE_SAMPLES = 400_000


def _sampled(curve, parameter_end: float) -> np.ndarray:
    """Points of `curve(t)` for t in [0, parameter_end], SAMPLE_SPACING_M apart along the
    curve (resampled by arc length: near a cusp, even steps of t bunch up, and the follower
    would cut the tight turn their tiny kinks hide), shifted so that the first is the origin."""
    rough = curve(np.linspace(0.0, parameter_end, 4097))
    rough_length = float(np.hypot(*np.diff(rough, axis=0).T).sum())
    count = min(max(4096, int(rough_length / DENSE_SPACING_M)), MAX_DENSE_SAMPLES)
    dense = curve(np.linspace(0.0, parameter_end, count + 1))
    arc = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(dense, axis=0).T))))
    count = min(max(MIN_SAMPLES, int(math.ceil(arc[-1] / SAMPLE_SPACING_M))), MAX_SAMPLES)
    even = np.linspace(0.0, arc[-1], count + 1)
    points = np.column_stack([np.interp(even, arc, dense[:, axis]) for axis in (0, 1)])
    return points - points[0]


def star(*, tips: int, outer_radius: float, inner_radius: float) -> np.ndarray:
    """A star of `tips` points, upright, starting at its top tip and drawn counter-clockwise:
    the corners (its only vertices) alternate between the outer and the inner radius."""
    angles = math.pi / 2 + np.pi * np.arange(2 * tips + 1) / tips
    radii = np.where(np.arange(2 * tips + 1) % 2 == 0, outer_radius, inner_radius)
    points = np.column_stack((radii * np.cos(angles), radii * np.sin(angles)))
    points[-1] = points[0]
    return points - points[0]


def heart(*, size: float) -> np.ndarray:
    """The classic heart (x = 16 sin^3 t, y = 13 cos t - 5 cos 2t - 2 cos 3t - cos 4t), `size`
    metres wide, upright, from its bottom tip: up the right lobe, down the left one."""
    scale = size / 32.0

    def curve(t: np.ndarray) -> np.ndarray:
        t = t + math.pi  # start at the bottom tip
        return scale * np.column_stack((
            -16 * np.sin(t) ** 3,
            13 * np.cos(t) - 5 * np.cos(2 * t) - 2 * np.cos(3 * t) - np.cos(4 * t)))
    return _sampled(curve, 2 * math.pi)


def lemniscate(*, size: float) -> np.ndarray:
    """The lemniscate of Bernoulli (the infinity sign), `size` metres wide, from its crossing:
    up into the right loop first."""
    half = size / 2.0

    def curve(t: np.ndarray) -> np.ndarray:
        t = t - math.pi / 2  # the crossing
        denominator = 1.0 + np.sin(t) ** 2
        return np.column_stack((half * np.cos(t) / denominator,
                                -half * np.sin(t) * np.cos(t) / denominator))
    return _sampled(curve, 2 * math.pi)


def rose_k(petals: int) -> int | None:
    """k of the rose r = sin(k t) with `petals` petals (odd k: k petals; even k: 2k), or None
    when no whole k gives that many (2, 6, 10, ...)."""
    if petals % 2 == 1:
        return petals
    return petals // 2 if petals % 4 == 0 else None


def rose(*, petals: int, size: float) -> np.ndarray:
    """A rose r = (size / 2) sin(k t) with `petals` petals, from its centre."""
    k = rose_k(petals)
    if k is None:
        raise ValueError(f'no rose has {petals} petals')
    radius = size / 2.0

    def curve(t: np.ndarray) -> np.ndarray:
        r = radius * np.sin(k * t)
        return np.column_stack((r * np.cos(t), r * np.sin(t)))
    return _sampled(curve, math.pi if k % 2 else 2 * math.pi)


def lissajous(*, a: int, b: int, phase: float, size: float) -> np.ndarray:
    """The Lissajous curve x = sin(a t + phase), y = sin(b t), in a square `size` metres wide,
    from t = 0."""
    half = size / 2.0

    def curve(t: np.ndarray) -> np.ndarray:
        return half * np.column_stack((np.sin(a * t + phase), np.sin(b * t)))
    return _sampled(curve, 2 * math.pi)
