"""Sketches of drawings, text and SVG: strokes joined by pen-up moves."""

from __future__ import annotations

import pathlib
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from turtle_traj.core.geometry import drawing, shapes, svg, text
from turtle_traj.core.geometry.path import Path, Pose2D
from turtle_traj.core.parameters.settings import Settings, pen_color_problem, pen_style
from turtle_traj.core.planning.limits import MAX_STROKES
from turtle_traj.core.planning.sketches.base import (
    DRAWING_CORNER_ANGLE_RAD,
    PlanError,
    Sketch,
    arena_diagonal,
    non_negative,
    shape_speeds,
)
from turtle_traj.core.turtlesim_contract import PenStyle

SVG_TOLERANCE_M = 0.0005  # SVG curves sampled within this of the true curve, at the size drawn


def _pen(request: Any, settings: Settings) -> PenStyle:
    """The request's pen; its empty colour or zero width: the node's pen parameters."""
    color = request.pen_color.strip()
    if color and (problem := pen_color_problem(color)):
        raise PlanError(problem)
    width = request.pen_width or settings.pen.width
    return pen_style(color, width) if color else replace(settings.pen, width=width)


def _drawing_sketch(what: str, strokes: Callable[[float], list[np.ndarray]], size: float,
                    unit: str, request: Any, start: Pose2D, settings: Settings) -> Sketch:
    """Strokes in the drawing frame (metres at a size), anchored at the turtle and ordered for
    short pen-up moves. The order is found once: scaling about the turtle keeps it best."""
    reference = min(size, arena_diagonal(settings.arena))  # larger is refused, unbuilt
    unordered = [shapes.anchored(stroke, start) for stroke in strokes(reference)]
    if not unordered:
        raise PlanError(f'the {what} has nothing to draw')
    if len(unordered) > MAX_STROKES:
        raise PlanError(f'the {what} has {len(unordered)} strokes; at most {MAX_STROKES}')
    here = (start.x, start.y)
    order = drawing.order_strokes(unordered, here)
    corner = min(settings.defaults.corner_angle, DRAWING_CORNER_ANGLE_RAD)

    def build(scale: float) -> Path:
        factor = scale / reference
        origin = np.array(here)
        return drawing.drawing_path(start, [origin + (stroke - origin) * factor
                                            for stroke in order], corner_angle_rad=corner)
    return Sketch(what, build, size, unit, **shape_speeds(request), pen=_pen(request, settings),
                  pen_up_unordered=drawing.pen_up_length(unordered, here) * size / reference)


def sketch_text(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    height = non_negative('height', request.height, settings.defaults.text_height, 'm')
    return _drawing_sketch(f'text {request.text!r} {height:g} m high',
                           lambda size: text.text_strokes(request.text, size), height,
                           'm (height)', request, start, settings)


def sketch_svg(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    size = non_negative('size', request.size, settings.defaults.svg_size, 'm')
    if request.path_data.strip() and request.file:
        raise PlanError('give path_data or a file, not both')
    if request.path_data.strip():
        parsed, what = svg.parse_path_data(request.path_data), 'SVG path'
    else:
        parsed, what = svg.parse_file(pathlib.Path(settings.svg_dir), request.file), request.file
    x_min, y_min, x_max, y_max = svg.bounding_box(parsed)
    extent = max(x_max - x_min, y_max - y_min)
    if extent <= 0:
        raise PlanError(f'the {what} has no extent: nothing to draw')
    units_per_metre = extent / min(size, arena_diagonal(settings.arena))
    strokes = svg.path_strokes(parsed, SVG_TOLERANCE_M * units_per_metre,
                               shapes.SAMPLE_SPACING_M * units_per_metre)

    def scaled(scale: float) -> list[np.ndarray]:  # lower-left corner at the origin, y up
        return [(stroke - (x_min, -y_max)) * (scale / extent) for stroke in strokes]
    return _drawing_sketch(f'{what} {size:g} m wide', scaled, size, 'm (larger side)', request,
                           start, settings)
