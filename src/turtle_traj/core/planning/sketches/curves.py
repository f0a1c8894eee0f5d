"""Sketches of the parametric curves: one continuous stroke from where the turtle stands."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from turtle_traj.core.geometry import curves, shapes
from turtle_traj.core.geometry.path import Path, Pose2D, legs_from_polyline
from turtle_traj.core.parameters.settings import Settings
from turtle_traj.core.planning.limits import MAX_FREQUENCY_RATIO, MAX_PETALS, MAX_TIPS
from turtle_traj.core.planning.sketches.base import (
    DRAWING_CORNER_ANGLE_RAD,
    PlanError,
    Sketch,
    arena_diagonal,
    count_in_range,
    non_negative,
    require_finite,
    shape_speeds,
)

STAR_INNER_RATIO = 0.382  # a regular five-pointed star's inner / outer radius


def _curve_sketch(what: str, local: Callable[[float], np.ndarray], size: float, unit: str,
                  request: Any, start: Pose2D, settings: Settings, *,
                  corner_angle_rad: float | None = None) -> Sketch:
    """A curve given in the drawing frame (`curves`), anchored at the turtle: its sharp
    corners (a star's, a heart's cusps) turned in place, the rest tracked continuously."""
    corner = min(settings.defaults.corner_angle, DRAWING_CORNER_ANGLE_RAD) \
        if corner_angle_rad is None else corner_angle_rad
    reference = min(size, arena_diagonal(settings.arena))  # larger is refused, unbuilt
    sampled = local(reference)  # once: a curve scaled down is the same curve, sampled finer

    def build(scale: float) -> Path:
        points = shapes.anchored(sampled * (scale / reference), start)
        return Path(tuple(legs_from_polyline(start, points, corner_angle_rad=corner)),
                    closed=bool(np.allclose(points[0], points[-1])))
    return Sketch(what, build, size, unit, **shape_speeds(request))


def sketch_star(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    tips = count_in_range('tips', request.tips, 5, 3, MAX_TIPS)
    outer = non_negative('size', request.size, settings.defaults.radius, 'm')
    inner = non_negative('inner_radius', request.inner_radius, STAR_INNER_RATIO * outer, 'm')
    if inner >= outer:
        raise PlanError(f'inner_radius {inner:g} m must be smaller than the outer radius '
                        f'(size) {outer:g} m')
    return _curve_sketch(
        f'{tips}-pointed star of radius {outer:g} m',
        lambda size: curves.star(tips=tips, outer_radius=size, inner_radius=inner * size / outer),
        outer, 'm (outer radius)', request, start, settings, corner_angle_rad=1e-9)


def _curve_width(request: Any, settings: Settings) -> float:
    return non_negative('size', request.size, settings.defaults.curve_width, 'm')


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
    petals = count_in_range('petals', request.petals, 5, 1, MAX_PETALS)
    if curves.rose_k(petals) is None:
        raise PlanError(f'no rose r = sin(k t) has {petals} petals: odd k gives k petals and '
                        f'even k 2k, so ask for {petals - 1}, {petals + 1} or {petals + 2}')
    width = _curve_width(request, settings)
    return _curve_sketch(f'rose of {petals} petals {width:g} m wide',
                         lambda size: curves.rose(petals=petals, size=size), width, 'm (width)',
                         request, start, settings)


def sketch_lissajous(request: Any, start: Pose2D, settings: Settings) -> Sketch:
    a = count_in_range('a', request.a, 3, 1, MAX_FREQUENCY_RATIO)
    b = count_in_range('b', request.b, 2, 1, MAX_FREQUENCY_RATIO)
    require_finite(phase=request.phase)
    width = _curve_width(request, settings)
    return _curve_sketch(
        f'Lissajous curve {a}:{b} {width:g} m wide',
        lambda size: curves.lissajous(a=a, b=b, phase=request.phase, size=size), width,
        'm (width)', request, start, settings)
