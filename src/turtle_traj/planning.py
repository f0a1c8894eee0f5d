"""Requests to checked paths: validate the numbers, build the path, check it against the arena.

Pure Python (no ROS): the node converts its service requests into calls of `plan`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from turtle_traj.geometry import shapes
from turtle_traj.geometry.path import Path, Pose2D
from turtle_traj.geometry.shapes import Arena, ShapeError

POLYGON_SIDES = {'square': 4, 'triangle': 3, 'hexagon': 6}
SHAPES = ('square', 'triangle', 'hexagon', 'polygon', 'circle', 'spiral', 'sine')
MAX_SIDES = 360
MAX_FREQUENCY = 20.0  # cycles per metre: beyond this the wave is finer than the sampling


class PlanError(ValueError):
    """A request that cannot become a safe path; the message says why."""


@dataclass(frozen=True)
class ShapeDefaults:
    """What a zero field of a request stands for (the node fills this from its parameters)."""

    side_length: float = 2.0
    radius: float = 1.5
    spiral_start_radius: float = 0.3
    spiral_growth: float = 0.4
    sine_amplitude: float = 0.5
    sine_frequency: float = 0.5
    sine_length: float = 4.0
    goal_tolerance: float = 0.01
    corner_angle: float = 0.35


@dataclass(frozen=True)
class ShapeRequest:
    """The fields of a DrawShape request, in SI units; zero means 'default'."""

    sides: int = 0
    size: float = 0.0
    clockwise: bool = False
    turns: float = 0.0
    growth: float = 0.0
    max_radius: float = 0.0
    frequency: float = 0.0
    length: float = 0.0


def require_finite(**values: float) -> None:
    """Refuse NaN and infinities, naming the field."""
    for name, value in values.items():
        if not math.isfinite(value):
            raise PlanError(f'{name} must be a finite number, got {value}')


MIN_SIZE = 0.001  # m (or turns, cycles/m): anything smaller is noise, not a request


def _non_negative(name: str, value: float, default: float, unit: str, upper: float) -> float:
    require_finite(**{name: value})
    if value < 0 or 0 < value < MIN_SIZE:
        raise PlanError(f'{name} must be at least {MIN_SIZE:g} {unit}, or 0 for the default '
                        f'({default:g} {unit}); got {value:g}')
    if value > upper:
        raise PlanError(f'{name} {value:g} {unit} is too large (at most {upper:g} {unit})')
    return value or default


def _fits(path: Path, arena: Arena, start: Pose2D) -> bool:
    """Every planned point is inside the arena, except the start itself.

    The start is exempt so that a turtle parked near a wall may still drive away from it.
    """
    points = path.points()
    away = np.hypot(points[:, 0] - start.x, points[:, 1] - start.y) > 1e-9
    return arena.contains(points[away]) if away.any() else True


def _checked(path: Path, arena: Arena, start: Pose2D, what: str,
             rebuild: Callable[[float], Path] | None, size: float, unit: str) -> Path:
    if not path.legs:
        raise PlanError(f'the {what} is too small to drive')
    if _fits(path, arena, start):
        return path
    message = (f'the {what} would leave the arena ({arena.describe()}, after the wall margin) '
               f'from ({start.x:.2f}, {start.y:.2f})')
    if rebuild is not None:
        largest = shapes.largest_fitting(rebuild, lambda p: _fits(p, arena, start), size)
        message += (f'; the largest that fits from here is {largest:.2f} {unit}' if largest > 1e-3
                    else '; nothing of this kind fits from here: move the turtle away from '
                         'the wall first')
    raise PlanError(message)


def plan_shape(shape: str, request: ShapeRequest, start: Pose2D, defaults: ShapeDefaults,
               arena: Arena) -> Path:
    """Validate a DrawShape request and return its path, or raise PlanError saying why."""
    try:
        return _plan_shape(shape, request, start, defaults, arena)
    except ShapeError as error:
        raise PlanError(str(error)) from None


def _plan_shape(shape: str, request: ShapeRequest, start: Pose2D, defaults: ShapeDefaults,
                arena: Arena) -> Path:
    if shape not in SHAPES:
        raise PlanError(f'unknown shape {shape!r}; known shapes: {", ".join(SHAPES)}')
    diagonal = math.hypot(arena.max_x - arena.min_x, arena.max_y - arena.min_y)
    corner = defaults.corner_angle

    if shape in POLYGON_SIDES or shape == 'polygon':
        sides = POLYGON_SIDES.get(shape, request.sides)
        if not 3 <= sides <= MAX_SIDES:
            raise PlanError(f'a polygon needs 3 to {MAX_SIDES} sides, got {sides}')
        side = _non_negative('size', request.size, defaults.side_length, 'm', diagonal)

        def build(size: float) -> Path:
            return shapes.polygon(start, sides=sides, side_length=size,
                                  clockwise=request.clockwise)
        name = shape if shape != 'polygon' else f'{sides}-sided polygon'
        return _checked(build(side), arena, start, f'{name} of side {side:g} m', build, side,
                        'm (side length)')

    turns = _non_negative('turns', request.turns, 0.0, 'turns', shapes.MAX_TURNS)
    if shape == 'circle':
        radius = _non_negative('size', request.size, defaults.radius, 'm', diagonal / 2)

        def one_lap(size: float) -> Path:
            return shapes.circle(start, radius=size, clockwise=request.clockwise, turns=1.0)
        # Checking one lap is enough: every lap covers the same points.
        _checked(one_lap(radius), arena, start, f'circle of radius {radius:g} m', one_lap,
                 radius, 'm (radius)')
        return shapes.circle(start, radius=radius, clockwise=request.clockwise, turns=turns)

    if shape == 'spiral':
        start_radius = _non_negative('size', request.size, defaults.spiral_start_radius, 'm',
                                     diagonal / 2)
        growth = _non_negative('growth', request.growth, defaults.spiral_growth, 'm per turn',
                               diagonal)
        max_radius = _non_negative('max_radius', request.max_radius, 0.0, 'm', diagonal)

        def build(size: float) -> Path:
            return shapes.spiral(start, start_radius=size, growth=growth,
                                 clockwise=request.clockwise, turns=turns,
                                 max_radius=max_radius, arena=arena)
        return _checked(build(start_radius), arena, start,
                        f'spiral from radius {start_radius:g} m', build, start_radius,
                        'm (start radius)')

    amplitude = _non_negative('size', request.size, defaults.sine_amplitude, 'm', diagonal)
    frequency = _non_negative('frequency', request.frequency, defaults.sine_frequency,
                              'cycles/m', MAX_FREQUENCY)
    length = _non_negative('length', request.length, defaults.sine_length, 'm', diagonal)

    def build(size: float) -> Path:
        return shapes.sine(start, amplitude=amplitude, frequency=frequency, length=size,
                           corner_angle_rad=corner)
    return _checked(build(length), arena, start,
                    f'sine wave of length {length:g} m and amplitude {amplitude:g} m', build,
                    length, 'm (length)')


def plan_go_to(start: Pose2D, *, x: float, y: float, theta: float | None, tolerance: float,
               defaults: ShapeDefaults, arena: Arena) -> Path:
    """Validate a GoTo request and return its path."""
    require_finite(x=x, y=y, tolerance=tolerance, **({'theta': theta} if theta is not None
                                                     else {}))
    tolerance = _non_negative('tolerance', tolerance, defaults.goal_tolerance, 'm', 1.0)
    if not arena.contains((x, y)):
        raise PlanError(f'goal ({x:g}, {y:g}) is outside the arena ({arena.describe()}, after '
                        'the wall margin)')
    return shapes.go_to(start, x=x, y=y, final_heading=theta, tolerance=tolerance,
                        corner_angle_rad=defaults.corner_angle)


def plan_move(start: Pose2D, *, distance: float, arena: Arena) -> Path:
    """Validate a straight move and return its path."""
    require_finite(distance=distance)
    if abs(distance) < MIN_SIZE:
        raise PlanError(f'distance must be at least {MIN_SIZE:g} m either way (negative '
                        f'drives backwards); got {distance:g}')
    limit = math.hypot(arena.max_x - arena.min_x, arena.max_y - arena.min_y)
    if abs(distance) > limit:
        raise PlanError(f'distance {distance:g} m is longer than the arena diagonal')
    sign = math.copysign(1.0, distance)

    def build(size: float) -> Path:
        return shapes.straight(start, distance=sign * size)
    direction = 'backwards' if distance < 0 else 'forwards'
    return _checked(build(abs(distance)), arena, start,
                    f'move of {abs(distance):g} m {direction}', build, abs(distance), 'm')


def plan_rotation(start: Pose2D, *, angle: float) -> Path:
    """Validate an in-place rotation and return its path."""
    require_finite(angle=angle)
    if abs(angle) < MIN_SIZE:
        raise PlanError(f'angle must be at least {MIN_SIZE:g} rad either way (negative turns '
                        f'clockwise); got {angle:g}')
    if abs(angle) > 2 * math.pi * shapes.MAX_TURNS:
        raise PlanError(f'angle {angle:g} rad is more than {shapes.MAX_TURNS:g} turns')
    return shapes.rotation(start, angle_rad=angle)


def plan_follow(start: Pose2D, *, points: Sequence[tuple[float, float]], closed: bool,
                defaults: ShapeDefaults, arena: Arena, max_points: int = 10_000) -> Path:
    """Validate a FollowPath request and return its path."""
    if not points:
        raise PlanError('points is empty: give at least one point')
    if len(points) > max_points:
        raise PlanError(f'{len(points)} points is too many (at most {max_points})')
    for index, (x, y) in enumerate(points):
        require_finite(**{f'points[{index}].x': x, f'points[{index}].y': y})
        if not arena.contains((x, y)):
            raise PlanError(f'points[{index}] = ({x:g}, {y:g}) is outside the arena '
                            f'({arena.describe()}, after the wall margin)')
    return shapes.follow(start, points=points, closed=closed,
                         corner_angle_rad=defaults.corner_angle)
