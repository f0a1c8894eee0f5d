"""Sketches of the motions: polygons, circles, spirals, sine waves, go-to, moves, rotations and
paths through points."""

from __future__ import annotations

import math
from typing import Any

from turtle_traj.core.geometry import shapes
from turtle_traj.core.geometry.path import Path, Pose2D
from turtle_traj.core.geometry.shapes import Arena, ShapeError
from turtle_traj.core.parameters.settings import Settings
from turtle_traj.core.parameters.table import PARAMETER
from turtle_traj.core.planning.limits import MAX_FREQUENCY, MAX_POINTS, MAX_SIDES
from turtle_traj.core.planning.sketches.base import (
    PlanError,
    Sketch,
    arena_diagonal,
    fits_in_arena,
    non_negative,
    requested_speed,
    require_finite,
    shape_speeds,
    signed_amount,
)


def sketch_polygon(request: Any, start: Pose2D, settings: Settings, *,
                   sides: int | None = None, name: str = '') -> Sketch:
    """A regular polygon: `sides` fixed (square...) or from the request (polygon)."""
    sides = request.sides if sides is None else sides
    if not 3 <= sides <= MAX_SIDES:
        raise PlanError(f'a polygon needs 3 to {MAX_SIDES} sides, got {sides}')
    side = non_negative('size', request.size, settings.defaults.side_length, 'm')

    def build(size: float) -> Path:
        return shapes.polygon(start, sides=sides, side_length=size, clockwise=request.clockwise)
    return Sketch(f'{name or f"{sides}-sided polygon"} of side {side:g} m', build, side,
                  'm (side length)', **shape_speeds(request))


def sketch_circle(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    turns = non_negative('turns', request.turns, 1.0, 'turns', shapes.MAX_TURNS)
    if request.forever:
        if request.turns:
            raise PlanError(f'turns {request.turns:g} and forever contradict each other: give '
                            'one of them')
        turns = 0.0  # endless: until stopped
    radius = non_negative('size', request.size, settings.defaults.radius, 'm')

    def one_lap(size: float) -> Path:  # every lap covers the same points: check one
        return shapes.circle(start, radius=size, clockwise=request.clockwise, turns=1.0)

    def drive(size: float) -> Path:
        return shapes.circle(start, radius=size, clockwise=request.clockwise, turns=turns)
    return Sketch(f'circle of radius {radius:g} m', one_lap, radius, 'm (radius)', drive,
                  **shape_speeds(request))


def sketch_spiral(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    diagonal, defaults = arena_diagonal(settings.arena), settings.defaults
    turns = non_negative('turns', request.turns, 0.0, 'turns', shapes.MAX_TURNS)
    start_radius = non_negative('size', request.size, defaults.spiral_start_radius, 'm')
    growth = non_negative('growth', request.growth, defaults.spiral_growth, 'm per turn',
                           diagonal)
    max_radius = non_negative('max_radius', request.max_radius, 0.0, 'm', diagonal)

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
                  'm (start radius)', **shape_speeds(request))


def _require_spiral_turns_fit(start: Pose2D, start_radius: float, growth: float,
                              clockwise: bool, turns: float, arena: Arena) -> None:
    def build(count: float) -> Path:
        return shapes.spiral(start, start_radius=start_radius, growth=growth,
                             clockwise=clockwise, turns=count, max_radius=0.0, arena=arena)
    try:
        if fits_in_arena(build(turns), arena, start):
            return
    except ShapeError:
        pass  # too many turns or not beyond the start: said below, or by the sketch
    fitting = math.floor(shapes.largest_fitting(build, lambda p: fits_in_arena(p, arena, start),
                                                min(turns, shapes.MAX_TURNS)) * 10) / 10
    raise PlanError(
        f'{turns:g} turns of a spiral from radius {start_radius:g} m growing {growth:g} m per '
        f'turn would leave the arena ({arena.describe()}, after the wall margin) from '
        f'({start.x:.2f}, {start.y:.2f}); {fitting:g} turns fit from here. Ask for fewer '
        'turns, or for none: the spiral then ends before the wall')


def sketch_sine(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    diagonal, defaults = arena_diagonal(settings.arena), settings.defaults
    amplitude = non_negative('size', request.size, defaults.sine_amplitude, 'm', diagonal)
    frequency = non_negative('frequency', request.frequency, defaults.sine_frequency,
                              'cycles/m', MAX_FREQUENCY)
    length = non_negative('length', request.length, defaults.sine_length, 'm')

    def build(size: float) -> Path:
        return shapes.sine(start, amplitude=amplitude, frequency=frequency, length=size,
                           corner_angle_rad=defaults.corner_angle)
    return Sketch(f'sine wave of length {length:g} m and amplitude {amplitude:g} m', build,
                  length, 'm (length)', **shape_speeds(request))


def sketch_go_to(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    arena, defaults = settings.arena, settings.defaults
    x, y = request.x, request.y
    theta = request.theta if request.use_theta else None
    require_finite(x=x, y=y, tolerance=request.tolerance,
                   **({'theta': theta} if theta is not None else {}))
    tolerance = non_negative('tolerance', request.tolerance, defaults.goal_tolerance, 'm', 1.0)
    if not arena.contains((x, y)):
        raise PlanError(f'goal ({x:g}, {y:g}) is outside the arena ({arena.describe()}, after '
                        'the wall margin)')
    path = shapes.go_to(start, x=x, y=y, final_heading=theta, tolerance=tolerance,
                        corner_angle_rad=_corner_angle(request, settings))
    return Sketch(f'way to ({x:g}, {y:g})', lambda _: path,
                  linear_speed=requested_speed('linear_speed', request.linear_speed),
                  end_tolerance=tolerance)


def sketch_move(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    distance = signed_amount('distance', request.distance, 'm', 'drives backwards')
    sign = math.copysign(1.0, distance)

    def build(size: float) -> Path:
        return shapes.straight(start, distance=sign * size)
    direction = 'backwards' if distance < 0 else 'forwards'
    return Sketch(f'move of {abs(distance):g} m {direction}', build, abs(distance), 'm',
                  linear_speed=requested_speed('linear_speed', request.speed))


def sketch_rotation(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    angle = signed_amount('angle', request.angle, 'rad', 'turns clockwise',
                    (2 * math.pi * shapes.MAX_TURNS, f'more than {shapes.MAX_TURNS:g} turns'))
    path = shapes.rotation(start, angle_rad=angle)
    return Sketch(f'rotation by {angle:g} rad', lambda _: path,
                  angular_speed=requested_speed('angular_speed', request.speed))


def sketch_follow(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    """The polyline through the points given. With a corner tolerance, its turns in place are
    rounded and it is smoothed within the tolerance (`corners.rounded_path`): a grid planner's
    staircase loses its steps."""
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
    corner_angle = _corner_angle(request, settings)
    reached = settings.defaults.goal_tolerance  # arrived there, as a go-to: no leg to it
    given = shapes.follow(start, points=points, closed=request.closed,
                          corner_angle_rad=corner_angle, reached=reached,
                          final_heading=request.theta if request.use_theta else None)
    return Sketch(f'path through {len(points)} points', lambda _: given,
                  linear_speed=requested_speed('linear_speed', request.linear_speed))


def _corner_angle(request: Any, settings: Settings) -> float:
    """Where a go-to or a follow-path turns in place: the request's `corner_angle`, else the
    node's."""
    asked = getattr(request, 'corner_angle', 0.0)
    require_finite(corner_angle=asked)
    spec = PARAMETER['corner_angle']
    if asked and not spec.low <= asked <= spec.high:
        raise PlanError(f'corner_angle must be 0 (the default) or {spec.low:g} to {spec.high:g} '
                        f'rad, got {asked:g}')
    return asked or settings.defaults.corner_angle
