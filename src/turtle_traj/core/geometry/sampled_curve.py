"""The smooth curve a polyline's vertices sample: a cubic Hermite through them. Pure Python.

A sampled curve (a circle, a glyph's stroke, a sine) is followed along the curve its vertices
sample, not along its chords. At an inner vertex the curve's tangent lies halfway between the
headings of the chords that meet there; at an open end it lies along the end chord (a turtle
starts a curve facing its first chord). Between two vertices it is the cubic with those end
tangents, parametrised by the chord's length, so it leaves a chord by about a quarter of the
chord's length times half its bend, as an arc would. `path.legs_from_polyline` turns in place
at bends where that would exceed 2 mm.

SciPy's `CubicHermiteSpline` is the same curve; importing it costs 0.5 s, which a control loop
that meets its first curve cannot spend, so the few lines are evaluated here.
"""

from __future__ import annotations

import numpy as np

from turtle_traj.core.geometry.angles import wrap_angles
from turtle_traj.core.geometry.path import Polyline


class SampledCurve:
    """Points along the smooth curve through `polyline`'s vertices, by arc length along its
    chords (an endless loop's arc wraps round)."""

    def __init__(self, polyline: Polyline) -> None:
        self.polyline = polyline
        headings = polyline.headings
        bends = wrap_angles(np.diff(headings))
        inner = headings[:-1] + bends / 2.0
        if polyline.repeat:  # the closing vertex is the first and the last
            closing = headings[-1] + float(wrap_angles(headings[:1] - headings[-1:])[0]) / 2.0
            first = last = closing
        else:
            first, last = float(headings[0]), float(headings[-1])
        tangents = np.concatenate(([first], inner, [last]))
        self._directions = np.column_stack((np.cos(tangents), np.sin(tangents)))

    def point_at(self, arc: float) -> tuple[float, float]:
        """The curve's point `arc` metres along the chords from the first vertex (clamped to the
        ends of an open curve)."""
        polyline = self.polyline
        length = polyline.length
        arc = arc % max(length, 1e-12) if polyline.repeat else min(max(arc, 0.0), length)
        cumulative = polyline.cumulative_length
        index = min(max(int(np.searchsorted(cumulative, arc, side='right')) - 1, 0),
                    len(polyline.points) - 2)
        chord = float(polyline.segment_lengths[index])
        t = (arc - float(cumulative[index])) / chord if chord > 1e-12 else 0.0
        start, end = polyline.points[index], polyline.points[index + 1]
        leaving, arriving = self._directions[index], self._directions[index + 1]
        # the cubic Hermite basis
        t2, t3 = t * t, t * t * t
        at_start, at_end = 2.0 * t3 - 3.0 * t2 + 1.0, 3.0 * t2 - 2.0 * t3
        along_start, along_end = (t3 - 2.0 * t2 + t) * chord, (t3 - t2) * chord
        x = (at_start * start[0] + at_end * end[0] + along_start * leaving[0]
             + along_end * arriving[0])
        y = (at_start * start[1] + at_end * end[1] + along_start * leaving[1]
             + along_end * arriving[1])
        return float(x), float(y)
