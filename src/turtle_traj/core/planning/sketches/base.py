"""What every sketch shares: the Sketch itself, PlanError, and checks of request numbers.

A sketch validates a request of one kind of trajectory and returns its path as a function of
its one scalable size (`planning` checks that path against the arena). Pure Python (no ROS).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from turtle_traj.core.geometry.path import Path, Pose2D
from turtle_traj.core.geometry.shapes import Arena
from turtle_traj.core.parameters.settings import Settings
from turtle_traj.core.parameters.table import PARAMETER
from turtle_traj.core.planning.limits import MIN_SIZE
from turtle_traj.core.turtlesim_contract import PenStyle

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


def require_finite(**values: float) -> None:
    """Refuse NaN and infinities, naming the field."""
    for name, value in values.items():
        if not math.isfinite(value):
            raise PlanError(f'{name} must be a finite number, got {value}')


def non_negative(name: str, value: float, default: float, unit: str,
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


def requested_speed(name: str, value: float) -> float | None:
    """A speed a request asks for (0 = the node's parameter `name`), validated."""
    require_finite(**{name: value})
    spec = PARAMETER[name]
    if value != 0.0 and not spec.low <= value <= spec.high:
        raise PlanError(f'{name} must be 0 (the default) or within {spec.low:g} and '
                        f'{spec.high:g}; got {value:g}')
    return value or None


def fits_in_arena(path: Path, arena: Arena, start: Pose2D) -> bool:
    """Every planned point is inside the arena, except the start itself.

    The start is exempt so that a turtle parked near a wall may still drive away from it.
    """
    points = path.points()
    away = np.hypot(points[:, 0] - start.x, points[:, 1] - start.y) > 1e-9
    return arena.contains(points[away]) if away.any() else True


def arena_diagonal(arena: Arena) -> float:
    return math.hypot(arena.max_x - arena.min_x, arena.max_y - arena.min_y)


def shape_speeds(request: Any) -> dict[str, float | None]:
    return {'linear_speed': requested_speed('linear_speed', request.linear_speed),
            'angular_speed': requested_speed('angular_speed', request.angular_speed)}


def signed_amount(name: str, value: float, unit: str, negative: str,
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


def count_in_range(name: str, value: int, default: int, low: int, high: int) -> int:
    value = value or default
    if not low <= value <= high:
        raise PlanError(f'{name} must be {low} to {high} (0: {default}), got {value}')
    return value


def corner_tolerance(request: Any, settings: Settings, *, drawing: bool) -> float:
    """How far corners may be rounded: the request's `corner_tolerance`, else the node's
    parameter; a drawing's pen-down corners are rounded only when the request asks."""
    asked = getattr(request, 'corner_tolerance', 0.0)
    require_finite(corner_tolerance=asked)
    largest = PARAMETER['corner_tolerance'].high
    if not 0.0 <= asked <= largest:
        raise PlanError(f'corner_tolerance must be 0 (the default) to {largest:g} m, '
                        f'got {asked:g}')
    return asked or (0.0 if drawing else settings.defaults.corner_tolerance)
