"""Qt's pen rasterisation (sim.raster) against plain geometry, at any heading and at the ends.

tests/test_pen_scan.py checks the pixels against the real turtlesim at three headings; these
check the rules themselves everywhere: a wide pen fills the pixels whose centre lies in its
square-capped rectangle, a 1 px pen puts exactly one pixel under the line per whole coordinate
of its major axis, from the pixel holding one end to the pixel holding the other.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from turtle_traj.sim.raster import cosmetic_line, wide_line

SIZE = 500
# Qt snaps corners to 1/64 px and steps edges in 16.16 fixed point: pixels whose centre lies
# closer than this to an edge may fall either way.
EDGE_PX = 0.05
SETTINGS = settings(max_examples=300, deadline=None)

coordinate = st.floats(min_value=20.0, max_value=480.0, allow_nan=False)
heading = st.floats(min_value=-math.pi, max_value=math.pi, allow_nan=False)
length = st.one_of(st.just(0.0), st.floats(min_value=0.05, max_value=15.0))


def _painted(spans: list[tuple[int, int, int]]) -> np.ndarray:
    canvas = np.zeros((SIZE, SIZE), dtype=bool)
    for row, first, last in spans:
        assert not canvas[row, first:last + 1].any(), 'a pixel painted twice'
        canvas[row, first:last + 1] = True
    return canvas


def _segment(x: float, y: float, theta: float, distance: float):
    return (x, y), (x + distance * math.cos(theta), y + distance * math.sin(theta))


@SETTINGS
@given(x=coordinate, y=coordinate, theta=heading, distance=length,
       width=st.integers(min_value=2, max_value=12))
def test_a_wide_pen_fills_the_pixels_whose_centre_is_in_its_capped_rectangle(
        x, y, theta, distance, width):
    start, end = _segment(x, y, theta, distance)
    painted = _painted(wide_line(start, end, float(width), SIZE))
    rows, columns = np.mgrid[0:SIZE, 0:SIZE]
    centre_x, centre_y = columns + 0.5, rows + 0.5
    if distance > 0.0:
        ux, uy = (end[0] - start[0]) / distance, (end[1] - start[1]) / distance
    else:  # Qt draws a point as a square, axis-aligned
        ux, uy = 1.0, 0.0
    along = (centre_x - start[0]) * ux + (centre_y - start[1]) * uy
    across = -(centre_x - start[0]) * uy + (centre_y - start[1]) * ux
    half = width / 2.0
    outside_by = np.maximum.reduce([-half - along, along - (distance + half),
                                    np.abs(across) - half])
    assert painted[outside_by < -EDGE_PX].all(), 'a pixel inside the pen left out'
    assert not painted[outside_by > EDGE_PX].any(), 'a pixel outside the pen painted'


@SETTINGS
@given(x=coordinate, y=coordinate, theta=heading, distance=length,
       backwards=st.booleans())
def test_a_one_pixel_pen_puts_one_pixel_under_the_line_per_step_of_its_major_axis(
        x, y, theta, distance, backwards):
    start, end = _segment(x, y, theta, distance)
    if backwards:  # turtlesim strokes from the new position back to the old one
        start, end = end, start
    painted = _painted(cosmetic_line(start, end, SIZE))
    rows, columns = np.nonzero(painted)
    if start == end:  # a point: the pixel it rounds to
        assert (rows.tolist(), columns.tolist()) == (
            [math.floor(start[1] + 0.5)], [math.floor(start[0] + 0.5)])
        return
    dx, dy = end[0] - start[0], end[1] - start[1]
    steep = abs(dy) > abs(dx)
    major, minor = (rows, columns) if steep else (columns, rows)
    ends = sorted((start[1], end[1]) if steep else (start[0], end[0]))
    # Qt takes the major axis and the ends in 1/64 px: near 45 degrees or near the grid, the
    # truncation may go either way.
    if abs(abs(dx) - abs(dy)) > 2 / 64 and all(abs(e * 64 - round(e * 64)) > 1e-6 for e in ends):
        # One pixel per whole coordinate, from the pixel holding one end to that of the other.
        assert sorted(major.tolist()) == list(range(math.floor(ends[0]),
                                                    math.floor(ends[1]) + 1))
    # Each pixel is one the (infinite) line passes through.
    for row, column in zip(rows, columns, strict=True):
        corners = [((column + cx) - start[0]) * dy - ((row + cy) - start[1]) * dx
                   for cx in (0.0, 1.0) for cy in (0.0, 1.0)]
        # Qt truncates the ends to 1/64 px, which tilts a short line: off by up to 1/64 px at
        # its ends, more where the caps and pixel centres reach past them.
        slack = (math.hypot(dx, dy) + 3.0) / 32
        assert min(corners) <= slack and max(corners) >= -slack, (row, column)


def test_strokes_reaching_far_off_the_canvas_are_drawn_to_its_edge_at_once():
    """A teleport can put an end anywhere a float reaches; the stroke is drawn up to the
    canvas's edge and costs no more than one across it."""
    for far in ((1e300, 1e300), (4.5e10, 4.5e10), (1.7e308, 1.7e308)):
        for spans in (cosmetic_line((250.0, 250.0), far, SIZE),
                      wide_line((250.0, 250.0), far, 3.0, SIZE),
                      wide_line(far, (250.0, 250.0), 3.0, SIZE)):
            painted = _painted(spans)
            assert np.diag(painted)[250:].all()  # the diagonal, to the canvas's corner
            rows, columns = np.nonzero(painted)
            assert np.abs(rows - columns).max() <= 2 and rows.min() >= 248
    assert cosmetic_line((-1.7e308, 0.0), (1.7e308, 5.0), SIZE) == []  # no line left to draw
