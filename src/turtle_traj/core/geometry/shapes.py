"""Trajectories as Paths anchored at the turtle's pose, and the arena check."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from turtle_traj.core.geometry.angles import shortest_angular_distance
from turtle_traj.core.geometry.path import Path, Polyline, Pose2D, Turn, legs_from_polyline

SAMPLE_SPACING_M = 0.02  # chord error of a 1 m circle at this spacing: 0.05 mm
MAX_TURNS = 100.0


class ShapeError(ValueError):
    """A shape that cannot be built as asked; the message says why."""


@dataclass(frozen=True)
class Arena:
    """The rectangle the turtle may use, shrunk by a safety margin on every side."""

    min_x: float
    min_y: float
    max_x: float
    max_y: float
    margin: float

    def inside(self, points: np.ndarray) -> np.ndarray:
        """Per point: inside the rectangle shrunk by the margin."""
        points = np.atleast_2d(points)
        return ((points[:, 0] >= self.min_x + self.margin)
                & (points[:, 0] <= self.max_x - self.margin)
                & (points[:, 1] >= self.min_y + self.margin)
                & (points[:, 1] <= self.max_y - self.margin))

    def contains(self, points: np.ndarray) -> bool:
        return bool(self.inside(points).all())

    def describe(self) -> str:
        return (f'x in [{self.min_x + self.margin:.2f}, {self.max_x - self.margin:.2f}], '
                f'y in [{self.min_y + self.margin:.2f}, {self.max_y - self.margin:.2f}]')


def anchored(local: np.ndarray, start: Pose2D) -> np.ndarray:
    """Local (forward, left) coordinates to world coordinates anchored at `start`: the local
    origin at the turtle, the local x axis along its heading."""
    c, s = math.cos(start.theta), math.sin(start.theta)
    return np.column_stack((start.x + c * local[:, 0] - s * local[:, 1],
                            start.y + s * local[:, 0] + c * local[:, 1]))


def _start_xy(start: Pose2D) -> np.ndarray:
    return np.array([start.x, start.y])


def polygon(start: Pose2D, *, sides: int, side_length: float, clockwise: bool) -> Path:
    """A regular polygon whose first side runs along the current heading.

    Every vertex is turned in place, however small its angle: a polygon's corners stay sharp.
    """
    turn = (-1.0 if clockwise else 1.0) * 2.0 * math.pi / sides
    angles = start.theta + turn * np.arange(sides)
    steps = side_length * np.column_stack((np.cos(angles), np.sin(angles)))
    origin = _start_xy(start)
    vertices = np.vstack((origin, origin + np.cumsum(steps, axis=0)))
    vertices[-1] = vertices[0]  # close exactly, free of rounding
    legs = legs_from_polyline(start, vertices, corner_angle_rad=1e-9)
    return Path(tuple(legs), closed=True)


def circle(start: Pose2D, *, radius: float, clockwise: bool, turns: float) -> Path:
    """A circle tangent to the current heading; turns == 0 means endless."""
    side = -1.0 if clockwise else 1.0
    laps = turns if turns > 0 else 1.0
    count = max(int(math.ceil(2 * math.pi * radius * laps / SAMPLE_SPACING_M)), 16)
    phi = np.linspace(0.0, 2 * math.pi * laps, count + 1)
    local = np.column_stack((radius * np.sin(phi), side * radius * (1.0 - np.cos(phi))))
    points = anchored(local, start)
    whole_laps = abs(laps - round(laps)) < 1e-9
    if whole_laps:
        points[-1] = points[0]
    return Path((Polyline(points, repeat=turns <= 0),), closed=whole_laps, endless=turns <= 0)


def spiral_points(start: Pose2D, *, start_radius: float, growth: float, clockwise: bool,
                  end_radius: float) -> np.ndarray:
    """An Archimedean spiral tangent to the heading, growing `growth` metres per turn.

    With r(phi) = r0 + k' phi, the arc length (radial term neglected) is
    s = r0 phi + growth phi^2 / (4 pi); sampling s evenly and solving for phi puts the points
    SAMPLE_SPACING_M apart along the curve, in one vectorised step.
    """
    side = -1.0 if clockwise else 1.0
    k = growth / (4 * math.pi)
    phi_end = 2 * math.pi * (end_radius - start_radius) / growth
    length = start_radius * phi_end + k * phi_end ** 2
    arc = np.linspace(0.0, length, max(int(math.ceil(length / SAMPLE_SPACING_M)), 2) + 1)
    phi = (np.sqrt(start_radius ** 2 + 4 * k * arc) - start_radius) / (2 * k)
    radius = start_radius + growth * phi / (2 * math.pi)
    local = np.column_stack((radius * np.sin(phi),
                             side * (start_radius - radius * np.cos(phi))))
    # The radius grows from the first point on, so the curve leaves it angled outwards by
    # atan(growth / (2 pi r0)); turn the spiral so that it leaves along the heading instead.
    outward = math.atan2(-side * growth / (2 * math.pi), start_radius)
    return anchored(anchored(local, Pose2D(0.0, 0.0, -outward)), start)


def spiral(start: Pose2D, *, start_radius: float, growth: float, clockwise: bool,
           turns: float, max_radius: float, arena: Arena) -> Path:
    """A spiral ending after `turns`, at `max_radius`, or (neither given) before the wall.

    At most MAX_TURNS turns. Sampling stops at the arena's diagonal: a spiral that grows
    beyond it has left the arena anyway, so the check fails without building the rest.
    """
    limits = [start_radius + growth * turns] if turns > 0 else []
    limits += [max_radius] if max_radius > 0 else []
    if limits and min(limits) <= start_radius:
        raise ShapeError(f'the spiral must end beyond its start radius {start_radius:g} m')
    end_radius = min(limits or [start_radius + growth * MAX_TURNS])
    if (end_radius - start_radius) / growth > MAX_TURNS + 1e-9:
        raise ShapeError(f'the spiral would take more than {MAX_TURNS:g} turns; grow it faster')
    arena_diagonal = math.hypot(arena.max_x - arena.min_x, arena.max_y - arena.min_y)
    points = spiral_points(start, start_radius=start_radius, growth=growth,
                           clockwise=clockwise, end_radius=min(end_radius, arena_diagonal))
    if not limits:
        inside = arena.inside(points)
        points = points[:len(points) if inside.all() else int(np.argmin(inside))]
        if len(points) < 2 * math.pi * start_radius / SAMPLE_SPACING_M:
            raise ShapeError('not even one full turn of the spiral fits before the wall from '
                            'here')
    return Path((Polyline(points),))


def sine(start: Pose2D, *, amplitude: float, frequency: float, length: float,
         corner_angle_rad: float) -> Path:
    """A sine wave along the current heading: `frequency` cycles per metre for `length` m."""
    spacing = min(SAMPLE_SPACING_M, 1.0 / (frequency * 60.0))
    along = np.linspace(0.0, length, max(int(math.ceil(length / spacing)), 2) + 1)
    local = np.column_stack((along, amplitude * np.sin(2 * math.pi * frequency * along)))
    legs = legs_from_polyline(start, anchored(local, start), corner_angle_rad=corner_angle_rad)
    return Path(tuple(legs))


def straight(start: Pose2D, *, distance: float) -> Path:
    """Drive `distance` metres along the heading; negative drives backwards."""
    end = anchored(np.array([[distance, 0.0]]), start)[0]
    return Path((Polyline(np.vstack((_start_xy(start), end)), reverse=distance < 0),))


def rotation(start: Pose2D, *, angle_rad: float) -> Path:
    """Turn in place by `angle_rad` (counter-clockwise positive)."""
    return Path((Turn(start.x, start.y, start.theta, angle_rad),))


def go_to(start: Pose2D, *, x: float, y: float, final_heading: float | None,
          tolerance: float, corner_angle_rad: float) -> Path:
    """Turn towards the goal, drive to it, then turn to `final_heading` if one is given."""
    legs = []
    if math.hypot(x - start.x, y - start.y) > tolerance:
        legs += legs_from_polyline(start, np.array([[start.x, start.y], [x, y]]),
                                   corner_angle_rad=corner_angle_rad)
    heading = math.atan2(y - start.y, x - start.x) if legs else start.theta
    goal_heading = heading if final_heading is None else final_heading
    if final_heading is not None or not legs:  # already there: a (possibly zero) turn
        legs.append(Turn(x, y, heading, shortest_angular_distance(heading, goal_heading)))
    return Path(tuple(legs))


def follow(start: Pose2D, *, points: Sequence[tuple[float, float]], closed: bool,
           corner_angle_rad: float, reached: float = 0.0,
           final_heading: float | None = None) -> Path:
    """A polyline through `points`, reached from the current position unless that is within
    `reached` of the first point (a turtle standing there needs no leg to it); then a turn to
    `final_heading`, if one is given."""
    waypoints = np.array(points, dtype=float).reshape(-1, 2)
    if closed:
        waypoints = np.vstack((waypoints, waypoints[:1]))
    here = _start_xy(start)
    route = (waypoints if float(np.hypot(*(waypoints[0] - here))) <= reached
             else np.vstack((here, waypoints)))
    legs = legs_from_polyline(start, route, corner_angle_rad=corner_angle_rad)
    if final_heading is not None:
        x, y = (float(value) for value in route[-1])
        heading = Path(tuple(legs)).end_heading if legs else start.theta
        legs.append(Turn(x, y, heading, shortest_angular_distance(heading, final_heading)))
    return Path(tuple(legs), closed=closed)


def largest_fitting(build: Callable[[float], Path], fits: Callable[[Path], bool],
                    requested: float) -> float:
    """Largest size in (0, requested] whose path `fits` (0 if none), by bisection."""
    low, high = 0.0, requested
    for _ in range(40):
        middle = 0.5 * (low + high)
        try:
            fits_here = fits(build(middle))
        except ShapeError:
            fits_here = False
        low, high = (middle, high) if fits_here else (low, middle)
    return low
