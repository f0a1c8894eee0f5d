"""Pen strokes as turtlesim's QPainter rasterises them: Qt 5's raster engine, aliased, square cap.

turtlesim strokes every move with `drawLine(new position, old position)` in pixel coordinates.
Qt then takes one of two paths, both reproduced here with Qt's own fixed-point arithmetic
(26.6 coordinates, 16.16 slopes), so the pixels agree at any heading and at the ends:

- a pen of width 0 or 1 is a *fast pen*: Qt's cosmetic stroker walks the major axis one pixel
  at a time from half a pixel before the start to half a pixel past the end (the square cap),
  taking the pixel the line crosses there (`cosmetic_line`);
- a wider pen goes to the rasteriser's line filler: the square-capped rectangle, its corners
  snapped to 1/64 px, filled at pixel centres (`wide_line`). A stroke of no length is a square.

A span is (row, first column, last column), clipped to the canvas.
"""

from __future__ import annotations

import math

Point = tuple[float, float]
Span = tuple[int, int, int]

_INT_MAX = 2**31 - 1
_FAR_PX = 1e6  # further than any pen reaches into a 500 px canvas


def _trunc_div(numerator: int, denominator: int) -> int:
    """C's integer division: rounds toward zero."""
    quotient = abs(numerator) // abs(denominator)
    return quotient if (numerator < 0) == (denominator < 0) else -quotient


def _to_16dot16(value: float) -> int:
    """A real as 16.16 fixed point, saturated as Qt's rasteriser does."""
    scaled = value * 65536.0
    return _INT_MAX if scaled > _INT_MAX else -_INT_MAX if scaled < -_INT_MAX else int(scaled)


def _safe_divide(x: float, y: float) -> float:
    return (1e20 if x > 0 else -1e20) if y == 0 else x / y


def _snap(value: float) -> float:
    """Down to the 26.6 grid."""
    return math.floor(value * 64) / 64


def _same_in_26dot6(a: float, b: float) -> bool:
    return int((b - a) * 64.0) == 0


# -- width 0 and 1: the cosmetic stroker -------------------------------------------------------

def _clip_axis(a1: float, b1: float, a2: float, b2: float, low: float,
               high: float) -> tuple[float, float, float, float] | None:
    """Cut a line to low <= a <= high, moving b along (the stroker's rough clip, one axis)."""
    if a1 < low or a1 > high:
        edge = low if a1 < low else high
        if (a2 <= low) if a1 < low else (a2 >= high):
            return None
        a1, b1 = edge, b1 + (b2 - b1) / (a2 - a1) * (edge - a1)
    if a2 < low or a2 > high:
        edge = low if a2 < low else high
        a2, b2 = edge, b2 + (b2 - b1) / (a2 - a1) * (edge - a2)
    return a1, b1, a2, b2


def _clip_to_band(start: Point, end: Point, low: float, high: float) -> tuple[Point, Point] | None:
    """The line cut to [low, high] on both axes, x first."""
    by_x = _clip_axis(start[0], start[1], end[0], end[1], low, high)
    if by_x is None:
        return None
    x1, y1, x2, y2 = by_x
    by_y = _clip_axis(y1, x1, y2, x2, low, high)
    if by_y is None:
        return None
    y1, x1, y2, x2 = by_y
    return (x1, y1), (x2, y2)


def _near(start: Point, end: Point) -> tuple[Point, Point] | None:
    """The part of a line within _FAR_PX of the canvas, measured from its nearer end (a
    teleport can put an end anywhere: Qt's arithmetic, and any, loses the line out there)."""
    swapped = max(map(abs, start)) > max(map(abs, end))
    origin, other = (end, start) if swapped else (start, end)
    dx, dy = other[0] - origin[0], other[1] - origin[1]
    if not (math.isfinite(dx) and math.isfinite(dy)):
        return None
    t1, t2 = 0.0, 1.0
    for at, delta in ((origin[0], dx), (origin[1], dy)):
        if delta == 0.0:
            if abs(at) > _FAR_PX:
                return None
            continue
        low, high = sorted(((-_FAR_PX - at) / delta, (_FAR_PX - at) / delta))
        t1, t2 = max(t1, low), min(t2, high)
        if t1 >= t2:
            return None
    first = (origin[0] + dx * t1, origin[1] + dy * t1)
    last = (origin[0] + dx * t2, origin[1] + dy * t2)
    return (last, first) if swapped else (first, last)


def _walk(major1: int, minor1: int, major2: int, minor2: int) -> list[tuple[int, int]]:
    """(major, minor) pixels of a line given in 26.6 coordinates along its major axis, both
    ends capped by half a pixel."""
    if major1 > major2:
        major1, minor1, major2, minor2 = major2, minor2, major1, minor1
    step = _trunc_div((minor2 - minor1) << 16, major2 - major1)  # minor per major, 16.16
    minor = (minor1 << 10) - (step >> 1)
    major1, major2 = major1 - 32, major2 + 32
    first, stop = (major1 + 32) >> 6, (major2 + 32) >> 6
    if first == stop:
        return []
    # The minor coordinate at the first pixel: at its centre on a rising line, at its first
    # edge on a falling one (Qt 5.15's rounding; older Qt took the centre for both, and then
    # a 1 px line at heading 0.5 would leave no pixel under the turtle's path).
    minor += (((first << 6) + (32 if step > 0 else 0) - major1) * step) >> 6
    pixels = []
    for major in range(first, stop):
        pixels.append((major, minor >> 16))
        minor += step
    return pixels


def cosmetic_line(start: Point, end: Point, size: int) -> list[Span]:
    """A 1 px line from `start` to `end` (pixels) on a size x size canvas."""
    if start == end:  # drawn as a point, rounded half up
        column, row = math.floor(start[0] + 0.5), math.floor(start[1] + 0.5)
        return [(row, column, column)] if 0 <= row < size and 0 <= column < size else []
    near = _near(start, end)
    clipped = near and _clip_to_band(*near, -1.0, size + 1.0)
    if clipped is None:
        return []
    (x1, y1), (x2, y2) = ((int(x * 64.0), int(y * 64.0)) for x, y in clipped)
    if abs(x2 - x1) < abs(y2 - y1):
        pixels = [(column, row) for row, column in _walk(y1, x1, y2, x2)]
    elif x1 != x2:
        pixels = _walk(x1, y1, x2, y2)
    else:
        return []
    return [(row, column, column) for column, row in pixels
            if 0 <= row < size and 0 <= column < size]


# -- width 2 and up: the rasteriser's line filler ----------------------------------------------

def wide_line(start: Point, end: Point, width: float, size: int) -> list[Span]:
    """A line `width` px wide with square caps from `start` to `end` (pixels)."""
    if start == end:  # Qt strokes it as a width-long line as wide as long: a square
        (x, y), half = start, width * 0.5
        return _fill_line((x - half, y), (x + half, y), 1.0, False, size)
    near = _near(start, end)
    if near is None:
        return []
    start, end = near
    dx, dy = end[0] - start[0], end[1] - start[1]
    return _fill_line(start, end, width / math.sqrt(dx * dx + dy * dy), True, size)


def _fill_line(a: Point, b: Point, width: float, square_cap: bool, size: int) -> list[Span]:
    """Qt's aliased line fill; `width` is relative to the line's length."""
    (pax, pay), (pbx, pby) = a, b
    if square_cap:
        dx, dy = pbx - pax, pby - pay
        pax, pay = pax - 0.5 * width * dx, pay - 0.5 * width * dy
        pbx, pby = pbx + 0.5 * width * dx, pby + 0.5 * width * dy
    clipped = _clip_to_canvas((pax, pay), (pbx, pby), a, b, width, size)
    if clipped is None:
        return []
    (pax, pay), (pbx, pby) = clipped
    old_length2 = (a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2
    new_length2 = (pax - pbx) ** 2 + (pay - pby) ** 2
    if new_length2 == 0:
        return []
    width *= math.sqrt(old_length2 / new_length2)
    if _same_in_26dot6(pay, pby):  # horizontal: turned into its vertical twin
        x, half_length = (pax + pbx) * 0.5, abs(pbx - pax) * 0.5
        half_across = width * half_length
        (pax, pay), (pbx, pby), width = (x, pay - half_across), (x, pay + half_across), 1 / width
    if _same_in_26dot6(pax, pbx):
        return _vertical(pax, min(pay, pby), max(pay, pby), width, size)
    return _slanted((pax, pay), (pbx, pby), width, size)


def _clip_to_canvas(pa: Point, pb: Point, a: Point, b: Point, width: float,
                    size: int) -> tuple[Point, Point] | None:
    """Cut the capped line to the canvas grown by the pen's reach, as Qt does."""
    reach_x = abs(b[1] - a[1]) * width * 0.5
    reach_y = abs(b[0] - a[0]) * width * 0.5
    low, high = (-reach_x, -reach_y), (size + reach_x, size + reach_y)

    def inside(point: Point) -> bool:
        return all(low[i] <= point[i] <= high[i] for i in (0, 1))

    if inside(pa) and inside(pb):
        return pa, pb
    t1, t2 = 0.0, 1.0
    for i in (0, 1):
        delta = pb[i] - pa[i]
        if delta == 0:
            if pa[i] <= low[i] or pa[i] >= high[i]:
                return None
            continue
        t_low, t_high = sorted(((low[i] - pa[i]) / delta, (high[i] - pa[i]) / delta))
        t1, t2 = max(t1, t_low), min(t2, t_high)
        if t1 >= t2:
            return None
    dx, dy = pb[0] - pa[0], pb[1] - pa[1]
    return (pa[0] + dx * t1, pa[1] + dy * t1), (pa[0] + dx * t2, pa[1] + dy * t2)


def _vertical(x: float, top: float, bottom: float, width: float, size: int) -> list[Span]:
    half = 0.5 * width * (bottom - top)
    left = min(max(x - half, 0.0), float(size))
    right = min(max(x + half, 0.0), float(size))
    top, bottom = min(max(top, 0.0), float(size)), min(max(bottom, 0.0), float(size))
    if _same_in_26dot6(left, right) or _same_in_26dot6(top, bottom):
        return []
    first_row, last_row = int(top + 0.5), -1 if bottom < 0.5 else int(bottom - 0.5)
    first, last = int(left + 0.5), -1 if right < 0.5 else int(right - 0.5)
    last = min(last, size - 1)
    return [(row, first, last) for row in range(first_row, min(last_row, size - 1) + 1)
            if first <= last]


def _slanted(pa: Point, pb: Point, width: float, size: int) -> list[Span]:
    """The rectangle's four corners, top, left, right and bottom, filled row by row between
    its left and right edges, each taken at the row's centre."""
    if pa[1] > pb[1]:
        pa, pb = pb, pa
    (ax, ay), (bx, by) = pa, pb
    half_x, half_y = (bx - ax) * 0.5 * width, (by - ay) * 0.5 * width
    # top, left, right and bottom: each end moved either way along (half_y, -half_x)
    if ax < bx:
        corners = (ax + half_y, ay - half_x, ax - half_y, ay + half_x,
                   bx + half_y, by - half_x, bx - half_y, by + half_x)
    else:
        corners = (ax - half_y, ay + half_x, bx - half_y, by + half_x,
                   ax + half_y, ay - half_x, bx + half_y, by - half_x)
    top_x, top_y, left_x, left_y, right_x, right_y, bottom_x, bottom_y = map(_snap, corners)
    top_left = _safe_divide(left_x - top_x, left_y - top_y)
    top_right = _safe_divide(right_x - top_x, right_y - top_y)
    bottom_left = _safe_divide(bottom_x - left_x, bottom_y - left_y)
    bottom_right = _safe_divide(bottom_x - right_x, bottom_y - right_y)
    first_row = int(top_y + 0.5)
    left_row = -1 if left_y < 0.5 else int(left_y - 0.5)
    right_row = -1 if right_y < 0.5 else int(right_y - 0.5)
    bottom_row = -1 if bottom_y < 0.5 else int(bottom_y - 0.5)
    # The edges' crossings with the first row of each part, in 16.16: left edges at the
    # pixel centre's right, right edges at its left, so a pixel is in when its centre is.
    # Edges 0 to 3: top-left, left-bottom, top-right, right-bottom.
    edges = [_to_16dot16(top_x + 0.5 + (first_row + 0.5 - top_y) * top_left),
             _to_16dot16(left_x + 0.5 + (left_row + 1.5 - left_y) * bottom_left),
             _to_16dot16(top_x - 0.5 + (first_row + 0.5 - top_y) * top_right),
             _to_16dot16(right_x - 0.5 + (right_row + 1.5 - right_y) * bottom_right)]
    steps = [_to_16dot16(top_left), _to_16dot16(bottom_left), _to_16dot16(top_right),
             _to_16dot16(bottom_right)]
    spans, row, last_column = [], first_row, size - 1
    for end_row, left_edge, right_edge in ((min(left_row, right_row), 0, 2), (right_row, 1, 2),
                                           (left_row, 0, 3), (bottom_row, 1, 3)):
        skip_to = min(end_row + 1, 0)  # Qt's start at the clip's top (sic: qMin)
        if row < skip_to:
            edges[left_edge] += steps[left_edge] * (skip_to - row)
            edges[right_edge] += steps[right_edge] * (skip_to - row)
            row = skip_to
        left, right = edges[left_edge], edges[right_edge]
        left_step, right_step = steps[left_edge], steps[right_edge]
        while row <= min(end_row, last_column):
            first = max(left >> 16, 0)
            last = min(right >> 16, last_column)
            if last >= first and row >= 0:
                spans.append((row, first, last))
            left += left_step
            right += right_step
            row += 1
        edges[left_edge], edges[right_edge] = left, right
    return spans
