"""Corners that swing out: a racing line through a tube around a path of straight legs.

A base that must stay within a tolerance of a corner turns widest, and so fastest, if it comes
in along the outer edge of the tube, cuts to the inner edge at the apex and leaves along the
outer edge again. `swung_out` moves each corner's vertex outwards along its bisector so that
both legs there run a given offset outside the path; rounding the moved corners within the
tolerance plus that offset (`corners.rounded_path`) then spends the tube's whole width. Pure
Python.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from turtle_traj.core.geometry.path import Leg, Polyline

_STRAIGHT_RAD = 1e-6  # a smaller change of direction is no corner


def swung_out(stretch: Sequence[Leg], offset: float) -> list[Leg]:
    """`stretch` (polylines joined by turns in place, `corners._stretches`) with the vertex of
    every corner moved outwards along its bisector, to where lines `offset` outside the two
    segments beside it meet; those segments tilt to it, their other ends kept. The turns in
    place are kept as they were."""
    polylines = [np.array(leg.points, dtype=float) for leg in stretch[::2]]
    pairs = list(itertools.pairwise(polylines))
    moved = [_moved(before, after, offset) for before, after in pairs]
    for (before, after), vertex in zip(pairs, moved, strict=True):
        before[-1] = after[0] = vertex
    legs = list(stretch)
    for index, points in zip(range(0, len(legs), 2), polylines, strict=True):
        leg = legs[index]
        assert isinstance(leg, Polyline)
        legs[index] = replace(leg, points=points)
    return legs


def _moved(before: np.ndarray, after: np.ndarray, offset: float) -> np.ndarray:
    """The vertex where `before` meets `after`, moved outwards by `offset` from both."""
    vertex = before[-1]
    incoming = _unit(vertex - before[-2])
    outgoing = _unit(after[1] - vertex)
    turn = math.atan2(incoming[0] * outgoing[1] - incoming[1] * outgoing[0],
                      float(incoming @ outgoing))
    if abs(turn) < _STRAIGHT_RAD:
        return vertex
    inward = _unit(outgoing - incoming)  # along the bisector, into the corner
    return vertex - offset / math.cos(0.5 * turn) * inward


def _unit(vector: np.ndarray) -> np.ndarray:
    return vector / max(float(np.hypot(*vector)), 1e-12)
