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

import bisect
import math

import numpy as np

from turtle_traj.core.geometry.angles import wrap_angles
from turtle_traj.core.geometry.path import Polyline


class SampledCurve:
    """Points along the smooth curve through `polyline`'s vertices, by arc length along its
    chords (an endless loop's arc wraps round). Each chord's constants are plain floats, as
    `projection.PolylineSegments` keeps them: a control period asks for two points."""

    def __init__(self, polyline: Polyline) -> None:
        self.length = polyline.length
        self.repeat = polyline.repeat
        headings = polyline.headings
        bends = wrap_angles(np.diff(headings))
        inner = headings[:-1] + bends / 2.0
        if polyline.repeat:  # the closing vertex is the first and the last
            closing = headings[-1] + float(wrap_angles(headings[:1] - headings[-1:])[0]) / 2.0
            first = last = closing
        else:
            first, last = float(headings[0]), float(headings[-1])
        tangents = np.concatenate(([first], inner, [last]))
        points = polyline.points
        self._starts = polyline.cumulative_length[:-1].tolist()
        self._chords = [
            (x0, y0, x1, y1, chord, math.cos(leave), math.sin(leave), math.cos(arrive),
             math.sin(arrive))
            for (x0, y0), (x1, y1), chord, leave, arrive in zip(
                points[:-1].tolist(), points[1:].tolist(), polyline.segment_lengths.tolist(),
                tangents[:-1].tolist(), tangents[1:].tolist(), strict=True)]

    def point_at(self, arc: float) -> tuple[float, float]:
        """The curve's point `arc` metres along the chords from the first vertex (clamped to the
        ends of an open curve)."""
        length = self.length
        arc = arc % max(length, 1e-12) if self.repeat else min(max(arc, 0.0), length)
        index = min(max(bisect.bisect_right(self._starts, arc) - 1, 0), len(self._chords) - 1)
        x0, y0, x1, y1, chord, leave_x, leave_y, arrive_x, arrive_y = self._chords[index]
        t = (arc - self._starts[index]) / chord if chord > 1e-12 else 0.0
        # the cubic Hermite basis: the chord's ends, and the tangents there over its length
        t2 = t * t
        t3 = t2 * t
        at_end = 3.0 * t2 - 2.0 * t3
        at_start = 1.0 - at_end
        along_start, along_end = (t3 - 2.0 * t2 + t) * chord, (t3 - t2) * chord
        return (at_start * x0 + at_end * x1 + along_start * leave_x + along_end * arrive_x,
                at_start * y0 + at_end * y1 + along_start * leave_y + along_end * arrive_y)
