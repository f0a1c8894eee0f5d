"""A polyline smoothed within a tube around it: the whole of a tolerance spent where that pays.

`tube_smoothed` repeats two steps. It averages the points with a Gaussian window along the
curve (`gaussian_smoothed`: the ends kept), then brings each point that
left the tube back to its edge: to `width` from the nearest sample of the path near the part
the point came from. Where the path runs straight or gently curved the passes smooth on; at a
corner or a tight turn the points rest on the tube's edge, so the curve cuts across as far as
the tolerance lets it, and the window sets how sharply it turns there. Which window is
fastest depends on the robot, so the planner tries `WINDOWS_M` and keeps the fastest. Pure
Python.
"""

from __future__ import annotations

import math

import numpy as np

from turtle_traj.core.geometry.path import Polyline
from turtle_traj.core.geometry.projection import all_near, nearest_samples

SPACING_M = 0.02  # between samples (the speed profile's grid)
PASSES = 60
_WALK = 3  # samples a point's nearest one may move by in a pass
_PASSING_SHARE = 2.0  # corners of inner angles from 60 degrees are cut to the edge
_EDGE_SHARE = 0.98  # of the width, where the passes bring points back: chords stay within
WINDOWS_M = tuple(0.02 * math.sqrt(2.0) ** power for power in range(9))  # 2 cm to 32 cm


def resampled(points: np.ndarray, spacing: float) -> np.ndarray:
    """Points evenly along the polyline through `points`, its ends kept: as many as fit
    `spacing` apart, at least three."""
    polyline = Polyline(np.asarray(points, dtype=float))
    arc = np.linspace(0.0, polyline.length, max(int(polyline.length / spacing), 2) + 1)
    return np.stack([np.interp(arc, polyline.cumulative_length, polyline.points[:, axis])
                     for axis in (0, 1)], axis=1)


def gaussian_smoothed(samples: np.ndarray, sigma: float) -> np.ndarray:
    """`samples` averaged with a Gaussian window `sigma` samples wide, the ends kept (the curve
    is extended by its point reflection at either end, so it leaves each end along the mean
    direction of the samples near it)."""
    reach = min(int(3.0 * sigma) + 1, len(samples) - 1)
    window = np.exp(-0.5 * (np.arange(-reach, reach + 1) / sigma) ** 2)
    window /= window.sum()
    head = 2.0 * samples[0] - samples[1:reach + 1][::-1]
    tail = 2.0 * samples[-1] - samples[-reach - 1:-1][::-1]
    padded = np.concatenate((head, samples, tail))
    smooth = np.stack([np.convolve(padded[:, axis], window, mode='valid') for axis in (0, 1)],
                      axis=1)
    smooth[0], smooth[-1] = samples[0], samples[-1]
    return smooth


def tube_smoothed(points: np.ndarray, width: float, window_m: float) -> np.ndarray | None:
    """The curve through `points` smoothed by PASSES passes of a Gaussian `window_m` wide, each
    followed by bringing the points back within `width` of the path (see the module), then
    resampled every SPACING_M; its ends those of `points`. None unless it is within `width` of
    the path, and the path within _PASSING_SHARE * `width` of it: the passes can draw the
    points apart along the curve, and shrink a short stroke or a small loop away (a corner
    cut to the tube's edge leaves its tip 1 / sin(half its inner angle) widths off)."""
    path = resampled(points, SPACING_M)
    # each point is brought back to the nearest of the path's samples around the one it was
    # brought back to last (its own, at first): a point of a cut corner to the samples it cuts
    # across, never to a later part of the path passing by
    nearest = np.arange(len(path))
    edge = _EDGE_SHARE * width
    curve = path
    for _ in range(PASSES):
        curve = gaussian_smoothed(curve, window_m / SPACING_M)
        nearest = nearest_samples(curve, path, nearest, _WALK)
        away = curve - path[nearest]
        distance = np.hypot(away[:, 0], away[:, 1])
        curve = path[nearest] + away * np.minimum(1.0, edge / np.maximum(distance, 1e-12))[:, None]
    curve = resampled(curve, SPACING_M)
    # no segment of no length: its heading would be nobody's (a pass can bring the first
    # samples back onto the start)
    curve = curve[np.concatenate(([True], np.hypot(*np.diff(curve, axis=0).T) > 1e-12))]
    drawn = np.asarray(points, dtype=float)
    return curve if (all_near(curve, drawn, width)
                     and all_near(path, curve, _PASSING_SHARE * width)) else None

