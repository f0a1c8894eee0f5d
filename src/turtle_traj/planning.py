"""Requests to checked plans: validate the numbers, build the path, check it against the arena.

Pure Python (no ROS). A request is read by attribute only, so a service request, an action goal
or a plain namespace plan alike, in the node and in a client estimating a call's duration.
Each trajectory kind has a sketch function (`trajectories.py` names them): it validates the
request and returns the path as a function of its one scalable size; `plan` checks that path
against the arena, and `largest_size` finds the largest size that fits from a pose.
"""

from __future__ import annotations

import math
import pathlib
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import partial
from typing import Any

import numpy as np

from turtle_traj.control.plan import Plan
from turtle_traj.geometry import curves, drawing, shapes, svg, text
from turtle_traj.geometry.path import Path, Pose2D, legs_from_polyline
from turtle_traj.geometry.shapes import Arena, ShapeError
from turtle_traj.limits import (
    MAX_FREQUENCY,
    MAX_FREQUENCY_RATIO,
    MAX_PETALS,
    MAX_POINTS,
    MAX_SIDES,
    MAX_STROKES,
    MAX_TIPS,
    MIN_SIZE,
    POLYGON_SIDES,
)
from turtle_traj.parameter_table import PARAMETER
from turtle_traj.settings import Settings, pen_color_problem, pen_style
from turtle_traj.turtlesim_contract import PenStyle

STAR_INNER_RATIO = 0.382  # a regular five-pointed star's inner / outer radius
SVG_TOLERANCE_M = 0.0005  # SVG curves sampled within this of the true curve, at the size drawn
# Drawings and curves turn in place at kinks sharper than this (or the corner_angle parameter,
# if smaller): a font's glyphs are coarse polylines, a heart has cusps, and cutting either
# would smear the picture. Curves sampled every 5 mm kink this much only below a 5 cm radius.
DRAWING_CORNER_ANGLE_RAD = 0.1


class PlanError(ValueError):
    """A request that cannot become a safe path; the message says why."""


@dataclass(frozen=True)
class Sketch:
    """A validated request before its arena check: its path as a function of one size."""

    what: str  # the trajectory in words, for refusals ('square of side 2 m')
    build: Callable[[float], Path]  # the path to check for a size
    size: float = 0.0  # the size asked for
    size_unit: str = ''  # 'm (side length)'; empty: nothing here scales (size is ignored)
    drive: Callable[[float], Path] | None = None  # the path driven, when not the one checked
    linear_speed: float | None = None  # per-run overrides of the node's top speeds
    angular_speed: float | None = None
    end_tolerance: float | None = None
    pen: PenStyle | None = None  # drawings: the pen to draw with (None: leave it alone)
    pen_up_unordered: float = 0.0  # drawings: pen-up distance in the strokes' given order


SketchFunction = Callable[[Any, Pose2D, Settings], Sketch]


def plan(trajectory: str, request: Any, start: Pose2D, settings: Settings) -> Plan:
    """Validate a request of this kind of trajectory (a registry name), build its path and check
    it against the arena; PlanError if not."""
    try:
        drawn = SKETCHES[trajectory](request, start, settings)
        checked = _checked(drawn, settings.arena, start)
        path = drawn.drive(drawn.size) if drawn.drive is not None else checked
    except ShapeError as error:
        raise PlanError(str(error)) from None
    if not path.legs:  # the follower and the report need at least one leg
        raise PlanError('nothing to drive: the turtle is already there')
    return Plan(trajectory, path, drawn.linear_speed, drawn.angular_speed, drawn.end_tolerance,
                drawn.pen, drawn.pen_up_unordered)


def largest_size(trajectory: str, request: Any, start: Pose2D,
                 settings: Settings) -> float | None:
    """Largest size of this request that fits from `start`, or None when nothing scales."""
    try:
        drawn = SKETCHES[trajectory](request, start, settings)
    except (PlanError, ShapeError):
        return None
    if not drawn.size_unit:
        return None
    return shapes.largest_fitting(drawn.build, lambda p: _fits(p, settings.arena, start),
                                  _diagonal(settings.arena))


def require_finite(**values: float) -> None:
    """Refuse NaN and infinities, naming the field."""
    for name, value in values.items():
        if not math.isfinite(value):
            raise PlanError(f'{name} must be a finite number, got {value}')


def _non_negative(name: str, value: float, default: float, unit: str,
                  upper: float = math.inf) -> float:
    """A size: finite, 0 (the default) or at least MIN_SIZE, and at most `upper` (a size that
    scales has no upper bound here: the arena check names the largest that fits)."""
    require_finite(**{name: value})
    if value < 0 or 0 < value < MIN_SIZE:
        raise PlanError(f'{name} must be at least {MIN_SIZE:g} {unit}, or 0 for the default '
                        f'({default:g} {unit}); got {value:g}')
    if value > upper:
        raise PlanError(f'{name} {value:g} {unit} is too large (at most {upper:g} {unit})')
    return value or default


def _speed(name: str, value: float) -> float | None:
    """A speed a request asks for (0 = the node's parameter `name`), validated."""
    require_finite(**{name: value})
    spec = PARAMETER[name]
    if value != 0.0 and not spec.low <= value <= spec.high:
        raise PlanError(f'{name} must be 0 (the default) or within {spec.low:g} and '
                        f'{spec.high:g}; got {value:g}')
    return value or None


def _fits(path: Path, arena: Arena, start: Pose2D) -> bool:
    """Every planned point is inside the arena, except the start itself.

    The start is exempt so that a turtle parked near a wall may still drive away from it.
    """
    points = path.points()
    away = np.hypot(points[:, 0] - start.x, points[:, 1] - start.y) > 1e-9
    return arena.contains(points[away]) if away.any() else True


def _checked(sketch: Sketch, arena: Arena, start: Pose2D) -> Path:
    """The sketch's path if it fits in the arena; else PlanError naming the largest size that
    fits from here (a size beyond the arena's diagonal is refused unbuilt)."""
    diagonal = _diagonal(arena)
    if sketch.size <= diagonal or not sketch.size_unit:
        path = sketch.build(sketch.size)
        if not path.legs and sketch.size_unit:
            raise PlanError(f'the {sketch.what} is too small to drive')
        if _fits(path, arena, start):
            return path
    message = (f'the {sketch.what} would leave the arena ({arena.describe()}, after the wall '
               f'margin) from ({start.x:.2f}, {start.y:.2f})')
    if sketch.size_unit:
        largest = shapes.largest_fitting(sketch.build, lambda p: _fits(p, arena, start),
                                         min(sketch.size, diagonal))
        message += (f'; the largest that fits from here is {largest:.2f} {sketch.size_unit}'
                    if largest > 1e-3 else '; nothing of this kind fits from here: move the '
                                           'turtle away from the wall first')
    raise PlanError(message)


def _diagonal(arena: Arena) -> float:
    return math.hypot(arena.max_x - arena.min_x, arena.max_y - arena.min_y)


# -- one sketch per kind of trajectory ---------------------------------------------------------

def sketch_polygon(request: Any, start: Pose2D, settings: Settings, *,
                   sides: int | None = None, name: str = '') -> Sketch:
    """A regular polygon: `sides` fixed (square...) or from the request (polygon)."""
    sides = request.sides if sides is None else sides
    if not 3 <= sides <= MAX_SIDES:
        raise PlanError(f'a polygon needs 3 to {MAX_SIDES} sides, got {sides}')
    side = _non_negative('size', request.size, settings.defaults.side_length, 'm')

    def build(size: float) -> Path:
        return shapes.polygon(start, sides=sides, side_length=size, clockwise=request.clockwise)
    return Sketch(f'{name or f"{sides}-sided polygon"} of side {side:g} m', build, side,
                  'm (side length)', **_shape_speeds(request))


def sketch_circle(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    turns = _non_negative('turns', request.turns, 1.0, 'turns', shapes.MAX_TURNS)
    if request.forever:
        if request.turns:
            raise PlanError(f'turns {request.turns:g} and forever contradict each other: give '
                            'one of them')
        turns = 0.0  # endless: until stopped
    radius = _non_negative('size', request.size, settings.defaults.radius, 'm')

    def one_lap(size: float) -> Path:  # every lap covers the same points: check one
        return shapes.circle(start, radius=size, clockwise=request.clockwise, turns=1.0)

    def drive(size: float) -> Path:
        return shapes.circle(start, radius=size, clockwise=request.clockwise, turns=turns)
    return Sketch(f'circle of radius {radius:g} m', one_lap, radius, 'm (radius)', drive,
                  **_shape_speeds(request))


def sketch_spiral(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    diagonal, defaults = _diagonal(settings.arena), settings.defaults
    turns = _non_negative('turns', request.turns, 0.0, 'turns', shapes.MAX_TURNS)
    start_radius = _non_negative('size', request.size, defaults.spiral_start_radius, 'm')
    growth = _non_negative('growth', request.growth, defaults.spiral_growth, 'm per turn',
                           diagonal)
    max_radius = _non_negative('max_radius', request.max_radius, 0.0, 'm', diagonal)

    def build(size: float) -> Path:
        return shapes.spiral(start, start_radius=size, growth=growth,
                             clockwise=request.clockwise, turns=turns, max_radius=max_radius,
                             arena=settings.arena)
    ends = [turns] if turns else []  # the end asked for, in turns: refused beyond the wall
    if max_radius:
        ends.append(max(max_radius - start_radius, 0.0) / growth)
    if ends:
        _require_spiral_turns_fit(start, start_radius, growth, request.clockwise, min(ends),
                                  settings.arena)
    return Sketch(f'spiral from radius {start_radius:g} m', build, start_radius,
                  'm (start radius)', **_shape_speeds(request))


def _require_spiral_turns_fit(start: Pose2D, start_radius: float, growth: float,
                              clockwise: bool, turns: float, arena: Arena) -> None:
    def build(count: float) -> Path:
        return shapes.spiral(start, start_radius=start_radius, growth=growth,
                             clockwise=clockwise, turns=count, max_radius=0.0, arena=arena)
    try:
        if _fits(build(turns), arena, start):
            return
    except ShapeError:
        pass  # too many turns or not beyond the start: said below, or by the sketch
    fitting = math.floor(shapes.largest_fitting(build, lambda p: _fits(p, arena, start),
                                                min(turns, shapes.MAX_TURNS)) * 10) / 10
    raise PlanError(
        f'{turns:g} turns of a spiral from radius {start_radius:g} m growing {growth:g} m per '
        f'turn would leave the arena ({arena.describe()}, after the wall margin) from '
        f'({start.x:.2f}, {start.y:.2f}); {fitting:g} turns fit from here. Ask for fewer '
        'turns, or for none: the spiral then ends before the wall')


def sketch_sine(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    diagonal, defaults = _diagonal(settings.arena), settings.defaults
    amplitude = _non_negative('size', request.size, defaults.sine_amplitude, 'm', diagonal)
    frequency = _non_negative('frequency', request.frequency, defaults.sine_frequency,
                              'cycles/m', MAX_FREQUENCY)
    length = _non_negative('length', request.length, defaults.sine_length, 'm')

    def build(size: float) -> Path:
        return shapes.sine(start, amplitude=amplitude, frequency=frequency, length=size,
                           corner_angle_rad=defaults.corner_angle)
    return Sketch(f'sine wave of length {length:g} m and amplitude {amplitude:g} m', build,
                  length, 'm (length)', **_shape_speeds(request))


def _shape_speeds(request: Any) -> dict[str, float | None]:
    return {'linear_speed': _speed('linear_speed', request.linear_speed),
            'angular_speed': _speed('angular_speed', request.angular_speed)}


def sketch_go_to(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    arena, defaults = settings.arena, settings.defaults
    x, y = request.x, request.y
    theta = request.theta if request.use_theta else None
    require_finite(x=x, y=y, tolerance=request.tolerance,
                   **({'theta': theta} if theta is not None else {}))
    tolerance = _non_negative('tolerance', request.tolerance, defaults.goal_tolerance, 'm', 1.0)
    if not arena.contains((x, y)):
        raise PlanError(f'goal ({x:g}, {y:g}) is outside the arena ({arena.describe()}, after '
                        'the wall margin)')
    path = shapes.go_to(start, x=x, y=y, final_heading=theta, tolerance=tolerance,
                        corner_angle_rad=defaults.corner_angle)
    return Sketch(f'way to ({x:g}, {y:g})', lambda _: path,
                  linear_speed=_speed('linear_speed', request.linear_speed),
                  end_tolerance=tolerance)


def _signed(name: str, value: float, unit: str, negative: str,
            limit: tuple[float, str] | None = None) -> float:
    """A signed amount whose sign is its direction: finite, not vanishing, within the
    `limit` (largest magnitude, and what exceeding it means) if there is one."""
    require_finite(**{name: value})
    if abs(value) < MIN_SIZE:
        raise PlanError(f'{name} must be at least {MIN_SIZE:g} {unit} either way (negative '
                        f'{negative}); got {value:g}')
    if limit is not None and abs(value) > limit[0]:
        raise PlanError(f'{name} {value:g} {unit} is {limit[1]}')
    return value


def sketch_move(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    distance = _signed('distance', request.distance, 'm', 'drives backwards')
    sign = math.copysign(1.0, distance)

    def build(size: float) -> Path:
        return shapes.straight(start, distance=sign * size)
    direction = 'backwards' if distance < 0 else 'forwards'
    return Sketch(f'move of {abs(distance):g} m {direction}', build, abs(distance), 'm',
                  linear_speed=_speed('linear_speed', request.speed))


def sketch_rotation(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    angle = _signed('angle', request.angle, 'rad', 'turns clockwise',
                    (2 * math.pi * shapes.MAX_TURNS, f'more than {shapes.MAX_TURNS:g} turns'))
    path = shapes.rotation(start, angle_rad=angle)
    return Sketch(f'rotation by {angle:g} rad', lambda _: path,
                  angular_speed=_speed('angular_speed', request.speed))


def sketch_follow(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    arena = settings.arena
    points = [(p.x, p.y) for p in request.points]
    if not points:
        raise PlanError('points is empty: give at least one point')
    if len(points) > MAX_POINTS:
        raise PlanError(f'{len(points)} points is too many (at most {MAX_POINTS})')
    for index, (x, y) in enumerate(points):
        require_finite(**{f'points[{index}].x': x, f'points[{index}].y': y})
        if not arena.contains((x, y)):
            raise PlanError(f'points[{index}] = ({x:g}, {y:g}) is outside the arena '
                            f'({arena.describe()}, after the wall margin)')
    path = shapes.follow(start, points=points, closed=request.closed,
                         corner_angle_rad=settings.defaults.corner_angle)
    return Sketch(f'path through {len(points)} points', lambda _: path,
                  linear_speed=_speed('linear_speed', request.linear_speed))


# -- parametric curves: one continuous stroke from where the turtle stands ---------------------

def _curve_sketch(what: str, local: Callable[[float], np.ndarray], size: float, unit: str,
                  request: Any, start: Pose2D, settings: Settings, *,
                  corner_angle_rad: float | None = None) -> Sketch:
    """A curve given in the drawing frame (`curves`), anchored at the turtle: its sharp
    corners (a star's, a heart's cusps) turned in place, the rest tracked continuously."""
    corner = min(settings.defaults.corner_angle, DRAWING_CORNER_ANGLE_RAD) \
        if corner_angle_rad is None else corner_angle_rad
    reference = min(size, _diagonal(settings.arena))  # larger is refused, unbuilt
    sampled = local(reference)  # once: a curve scaled down is the same curve, sampled finer

    def build(scale: float) -> Path:
        points = shapes.anchored(sampled * (scale / reference), start)
        return Path(tuple(legs_from_polyline(start, points, corner_angle_rad=corner)),
                    closed=bool(np.allclose(points[0], points[-1])))
    return Sketch(what, build, size, unit, **_shape_speeds(request))


def _count(name: str, value: int, default: int, low: int, high: int) -> int:
    value = value or default
    if not low <= value <= high:
        raise PlanError(f'{name} must be {low} to {high} (0: {default}), got {value}')
    return value


def sketch_star(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    tips = _count('tips', request.tips, 5, 3, MAX_TIPS)
    outer = _non_negative('size', request.size, settings.defaults.radius, 'm')
    inner = _non_negative('inner_radius', request.inner_radius, STAR_INNER_RATIO * outer, 'm')
    if inner >= outer:
        raise PlanError(f'inner_radius {inner:g} m must be smaller than the outer radius '
                        f'(size) {outer:g} m')
    return _curve_sketch(
        f'{tips}-pointed star of radius {outer:g} m',
        lambda size: curves.star(tips=tips, outer_radius=size, inner_radius=inner * size / outer),
        outer, 'm (outer radius)', request, start, settings, corner_angle_rad=1e-9)


def _curve_width(request: Any, settings: Settings) -> float:
    return _non_negative('size', request.size, settings.defaults.curve_width, 'm')


def sketch_heart(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    width = _curve_width(request, settings)
    return _curve_sketch(f'heart {width:g} m wide', lambda size: curves.heart(size=size), width,
                         'm (width)', request, start, settings)


def sketch_lemniscate(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    width = _curve_width(request, settings)
    return _curve_sketch(f'lemniscate {width:g} m wide',
                         lambda size: curves.lemniscate(size=size), width, 'm (width)', request,
                         start, settings)


def sketch_rose(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    petals = _count('petals', request.petals, 5, 1, MAX_PETALS)
    if curves.rose_k(petals) is None:
        raise PlanError(f'no rose r = sin(k t) has {petals} petals: odd k gives k petals and '
                        f'even k 2k, so ask for {petals - 1}, {petals + 1} or {petals + 2}')
    width = _curve_width(request, settings)
    return _curve_sketch(f'rose of {petals} petals {width:g} m wide',
                         lambda size: curves.rose(petals=petals, size=size), width, 'm (width)',
                         request, start, settings)


def sketch_lissajous(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    a = _count('a', request.a, 3, 1, MAX_FREQUENCY_RATIO)
    b = _count('b', request.b, 2, 1, MAX_FREQUENCY_RATIO)
    require_finite(phase=request.phase)
    width = _curve_width(request, settings)
    return _curve_sketch(
        f'Lissajous curve {a}:{b} {width:g} m wide',
        lambda size: curves.lissajous(a=a, b=b, phase=request.phase, size=size), width,
        'm (width)', request, start, settings)


# -- drawings: strokes joined by pen-up moves ----------------------------------------------------

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
    reference = min(size, _diagonal(settings.arena))  # larger is refused, unbuilt
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
    return Sketch(what, build, size, unit, **_shape_speeds(request), pen=_pen(request, settings),
                  pen_up_unordered=drawing.pen_up_length(unordered, here) * size / reference)


def sketch_text(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    height = _non_negative('height', request.height, settings.defaults.text_height, 'm')
    return _drawing_sketch(f'text {request.text!r} {height:g} m high',
                           lambda size: text.text_strokes(request.text, size), height,
                           'm (height)', request, start, settings)


def sketch_svg(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    size = _non_negative('size', request.size, settings.defaults.svg_size, 'm')
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
    units_per_metre = extent / min(size, _diagonal(settings.arena))
    strokes = svg.path_strokes(parsed, SVG_TOLERANCE_M * units_per_metre,
                               shapes.SAMPLE_SPACING_M * units_per_metre)

    def scaled(scale: float) -> list[np.ndarray]:  # lower-left corner at the origin, y up
        return [(stroke - (x_min, -y_max)) * (scale / extent) for stroke in strokes]
    return _drawing_sketch(f'{what} {size:g} m wide', scaled, size, 'm (larger side)', request,
                           start, settings)


# Each kind of trajectory in the registry (`trajectories`), by name, and its sketch.
SKETCHES: dict[str, SketchFunction] = {
    **{name: partial(sketch_polygon, sides=sides, name=name)
       for name, sides in POLYGON_SIDES.items()},
    'polygon': sketch_polygon,
    'circle': sketch_circle,
    'spiral': sketch_spiral,
    'sine': sketch_sine,
    'star': sketch_star,
    'heart': sketch_heart,
    'lemniscate': sketch_lemniscate,
    'rose': sketch_rose,
    'lissajous': sketch_lissajous,
    'text': sketch_text,
    'svg': sketch_svg,
    'go_to': sketch_go_to,
    'move': sketch_move,
    'rotate': sketch_rotation,
    'follow_path': sketch_follow,
}
