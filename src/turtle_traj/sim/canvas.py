"""The turtlesim window as images: a trail layer, the background and turtle icons (Pillow)."""

from __future__ import annotations

import math
from functools import cache

from PIL import Image, ImageDraw

from turtle_traj.sim.physics import (
    CANVAS_SIZE_PX,
    PIXELS_PER_METER,
    WORLD_SIZE_M,
    Segment,
    Turtle,
)

_ICON_SIZE_PX = 45
_TRANSPARENT_WHITE = (255, 255, 255, 0)


def to_pixel(x_m: float, y_m: float) -> tuple[float, float]:
    """World metres (y up) to canvas pixels (y down), as turtlesim draws."""
    return x_m * PIXELS_PER_METER, (WORLD_SIZE_M - y_m) * PIXELS_PER_METER


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
    """Pen trails on a transparent 500x500 layer, plus rendering of the full window."""

    def __init__(self) -> None:
        self.trails = Image.new('RGBA', (CANVAS_SIZE_PX, CANVAS_SIZE_PX), _TRANSPARENT_WHITE)
        self._draw = ImageDraw.Draw(self.trails)

    def clear(self) -> None:
        self._draw.rectangle((0, 0, CANVAS_SIZE_PX, CANVAS_SIZE_PX), fill=_TRANSPARENT_WHITE)

    def draw(self, segment: Segment) -> None:
        """Stroke a segment with a square cap (the line is extended by half the width)."""
        (x0, y0), (x1, y1) = to_pixel(*segment.start), to_pixel(*segment.end)
        pen = segment.pen
        half = pen.width_px / 2.0
        length = math.hypot(x1 - x0, y1 - y0)
        if length > 0.0 and pen.width_px > 1:
            ux, uy = (x1 - x0) / length * half, (y1 - y0) / length * half
            x0, y0, x1, y1 = x0 - ux, y0 - uy, x1 + ux, y1 + uy
        self._draw.line((x0, y0, x1, y1), fill=(pen.r, pen.g, pen.b, 255), width=pen.width_px)

    def color_under(self, turtle: Turtle) -> tuple[int, int, int]:
        """RGB of the trail layer under the turtle, as turtlesim's color sensor reads it."""
        px, py = to_pixel(turtle.x, turtle.y)
        column = min(max(math.floor(px + 0.5), 0), CANVAS_SIZE_PX - 1)
        row = min(max(math.floor(py + 0.5), 0), CANVAS_SIZE_PX - 1)
        r, g, b, _ = self.trails.getpixel((column, row))
        return r, g, b

    def render(self, background: tuple[int, int, int], turtles: list[Turtle]) -> Image.Image:
        """The window as a user sees it: background, trails, then turtles in name order."""
        frame = Image.new('RGBA', self.trails.size, (*background, 255))
        frame.alpha_composite(self.trails)
        for turtle in turtles:
            icon = turtle_icon().rotate(math.degrees(turtle.theta) - 90.0, expand=True)
            px, py = to_pixel(turtle.x, turtle.y)
            frame.alpha_composite(
                icon, (round(px - icon.width / 2), round(py - icon.height / 2)))
        return frame.convert('RGB')
