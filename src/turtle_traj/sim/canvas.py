"""The turtlesim window as images: a trail layer (numpy), the background and turtle icons
(Pillow)."""

from __future__ import annotations

import math
from functools import cache

import numpy as np
from PIL import Image, ImageDraw

from turtle_traj.core.turtlesim_contract import CANVAS_HEIGHT_M, CANVAS_SIZE_PX, PIXELS_PER_METER
from turtle_traj.sim.raster import cosmetic_line, wide_line
from turtle_traj.sim.state import Segment, Turtle

_ICON_SIZE_PX = 45
_TRANSPARENT_WHITE = (255, 255, 255, 0)


def to_pixel(x_m: float, y_m: float) -> tuple[float, float]:
    """World metres (y up) to canvas pixels (y down), as turtlesim draws and senses."""
    return x_m * PIXELS_PER_METER, (CANVAS_HEIGHT_M - y_m) * PIXELS_PER_METER


@cache
def turtle_icon() -> Image.Image:
    """A 45x45 top view of a turtle facing up (+y on screen), drawn once."""
    icon = Image.new('RGBA', (_ICON_SIZE_PX, _ICON_SIZE_PX), (0, 0, 0, 0))
    draw = ImageDraw.Draw(icon)
    skin, shell, rim = (120, 170, 90, 255), (70, 120, 60, 255), (40, 70, 35, 255)
    for cx, cy in ((12, 13), (33, 13), (12, 33), (33, 33)):  # legs
        draw.ellipse((cx - 5, cy - 5, cx + 5, cy + 5), fill=skin, outline=rim)
    draw.ellipse((17, 1, 28, 13), fill=skin, outline=rim)  # head
    draw.polygon([(20, 42), (25, 42), (22, 45)], fill=skin)  # tail
    draw.ellipse((9, 8, 36, 41), fill=shell, outline=rim, width=2)  # shell
    draw.line((22, 12, 22, 38), fill=rim, width=1)
    return icon


class Canvas:
    """Pen trails on a transparent 500x500 layer (RGBA, numpy), plus rendering of the window."""

    def __init__(self) -> None:
        self.trails = np.empty((CANVAS_SIZE_PX, CANVAS_SIZE_PX, 4), dtype=np.uint8)
        # Changes since `take_changes`, kept only once someone asks (a live view): whether the
        # trails were cleared, and the pixel rectangles strokes touched (row0, row1, col0, col1).
        self.tracking = False
        self._cleared = False
        self._touched: list[tuple[int, int, int, int]] = []
        self.clear()

    def clear(self) -> None:
        self.trails[:] = _TRANSPARENT_WHITE
        if self.tracking:
            self._cleared, self._touched = True, []

    def take_changes(self) -> tuple[bool, list[tuple[int, int, np.ndarray]]]:
        """What changed since the last call: whether the trails were cleared first, then each
        touched rectangle as (row, column, its RGBA pixels now). Starts tracking."""
        self.tracking = True
        patches = [(row0, col0, self.trails[row0:row1, col0:col1].copy())
                   for row0, row1, col0, col1 in self._touched]
        cleared, self._cleared, self._touched = self._cleared, False, []
        return cleared, patches

    def draw(self, segment: Segment) -> None:
        """Stroke a segment as turtlesim's QPainter does (`drawLine(new, old)`): aliased,
        square cap, in pixel coordinates with no half-pixel offset. See `sim.raster`;
        tests/test_pen_scan.py checks it against the real turtlesim's colour sensor."""
        new, old = to_pixel(*segment.end), to_pixel(*segment.start)
        pen = segment.pen
        colour = (pen.r, pen.g, pen.b, 255)
        spans = (cosmetic_line(new, old, CANVAS_SIZE_PX) if pen.width_px <= 1
                 else wide_line(new, old, float(pen.width_px), CANVAS_SIZE_PX))
        painted = []
        for row, first, last in spans:
            first, last = max(first, 0), min(last, CANVAS_SIZE_PX - 1)
            if 0 <= row < CANVAS_SIZE_PX and first <= last:
                self.trails[row, first:last + 1] = colour
                painted.append((row, first, last))
        if self.tracking and painted:  # one rectangle around what the stroke painted
            rows = [row for row, _, _ in painted]
            self._touched.append((min(rows), max(rows) + 1, min(f for _, f, _ in painted),
                                  max(last for _, _, last in painted) + 1))

    def color_under(self, turtle: Turtle) -> tuple[int, int, int]:
        """RGB of the trail layer under the turtle, as turtlesim's color sensor reads it."""
        px, py = to_pixel(turtle.x, turtle.y)
        column = min(max(math.floor(px + 0.5), 0), CANVAS_SIZE_PX - 1)
        row = min(max(math.floor(py + 0.5), 0), CANVAS_SIZE_PX - 1)
        r, g, b, _ = self.trails[row, column]
        return int(r), int(g), int(b)

    def render(self, background: tuple[int, int, int], turtles: list[Turtle]) -> Image.Image:
        """The window as a user sees it: background, trails, then turtles in name order."""
        frame = Image.new('RGBA', (CANVAS_SIZE_PX, CANVAS_SIZE_PX), (*background, 255))
        frame.alpha_composite(Image.fromarray(self.trails, 'RGBA'))
        for turtle in turtles:
            icon = turtle_icon().rotate(math.degrees(turtle.theta) - 90.0, expand=True)
            px, py = to_pixel(turtle.x, turtle.y)
            frame.alpha_composite(
                icon, (round(px - icon.width / 2), round(py - icon.height / 2)))
        return frame.convert('RGB')
