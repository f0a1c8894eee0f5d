"""Requests to checked plans: validate the numbers, build the path, check it against the arena.

Pure Python (no ROS). A request is read by attribute only, so a service request, an action goal
or a plain namespace plan alike, in the node and in a client estimating a call's duration.
Each trajectory kind has a sketch function (`sketches/`; `core/registry.py` names the kinds): it
validates the request and returns the path as a function of its one scalable size; `plan`
checks that path against the arena, and `largest_size` finds the largest size that fits from a
pose.
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import partial
from typing import Any

import numpy as np

from turtle_traj.core.control.config import ControlConfig
from turtle_traj.core.control.duration import least_time_s
from turtle_traj.core.control.plan import Plan
from turtle_traj.core.control.profile import (
    ANGULAR_ACCEL_SHARE,
    FULL_LIMITS,
    PLANNING_SHARES,
    SpeedProfile,
    profile_for,
)
from turtle_traj.core.geometry import shapes
from turtle_traj.core.geometry.corners import CLOTHOID_PAIR, arc_shape, rounded_path
from turtle_traj.core.geometry.join import joined_start
from turtle_traj.core.geometry.path import Path, Polyline, Pose2D
from turtle_traj.core.geometry.shapes import Arena, ShapeError
from turtle_traj.core.geometry.tube import SPACING_M, resampled
from turtle_traj.core.parameters.settings import Settings
from turtle_traj.core.planning.limits import POLYGON_SIDES
from turtle_traj.core.planning.sketches import curves, drawings, motions
from turtle_traj.core.planning.sketches.base import (
    PlanError,
    Sketch,
    SketchFunction,
    arena_diagonal,
    corner_tolerance,
    fits_in_arena,
)

__all__ = ['SKETCHES', 'PlanError', 'largest_size', 'plan', 'plans_by_limit']

LIMIT_NODES_PER_M = 13  # the minimum-time trajectory's intervals, for a candidate of a plan
LIMIT_NODES = (30, 240)  # at the least and the most
LIMIT_WIDTH_SHARE = 0.92  # of the tube's width: its motion between nodes strays a little
_APART_M = 1e-6  # the limit's positions closer than this to the last one are dropped
_TIMED_SHARE = 0.01  # a motion's time along its polyline within this share of its own: timed


def plan(trajectory: str, request: Any, start: Pose2D, settings: Settings, *,
         start_speed: float = 0.0) -> Plan:
    """Validate a request of this kind of trajectory (a registry name), build its path and check
    it against the arena; PlanError if not. `start_speed`: the robot's speed as the plan takes
    over (a path replacing the one it drives), where its first curve's profile begins."""
    try:
        drawn = SKETCHES[trajectory](request, start, settings)
        tolerance = corner_tolerance(request, settings, drawing=drawn.pen is not None)
        checked = _checked(drawn, settings.arena, start)
        path = drawn.drive(drawn.size) if drawn.drive is not None else checked
    except ShapeError as error:
        raise PlanError(str(error)) from None
    if not path.legs:  # the follower and the report need at least one leg
        raise PlanError('nothing to drive: the turtle is already there')
    planned = Plan(trajectory, path, drawn.linear_speed, drawn.angular_speed,
                   drawn.end_tolerance, drawn.pen if settings.lifts_pen else None,
                   drawn.pen_up_unordered)
    run = planned.control(settings.control)
    shares = PLANNING_SHARES
    if tolerance > 0.0:  # measured against the path as checked (one lap of a circle)
        shares = FULL_LIMITS  # the tolerance's reserve is the steering's (profile.py)
        planned = replace(planned, path=_rounded(path, tolerance, run,
                                                 settings.defaults.minimum_time_corners),
                          drawn=checked.points(), tolerance=tolerance)
    if run.limited or tolerance > 0.0:  # planned here, not in the control loop
        planned = replace(planned, profiles=tuple(
            profile_for(leg, run.limits, start_speed if index == 0 else 0.0, shares)
            if isinstance(leg, Polyline) else None
            for index, leg in enumerate(planned.path.legs)))
    return planned


def _rounded(path: Path, tolerance: float, run: ControlConfig, minimum_time: bool) -> Path:
    """`path` with its corners rounded within `tolerance`, each stretch of it as fast as
    `corners.rounded_path` finds (by its least time); on a base with angular limits, each
    corner is the faster (by its speed profile) of a clothoid pair and a
    clothoid-arc-clothoid; where the tolerance lets the robot curve onto the path from its
    heading faster than it turns in place first, it does (`join.joined_start`). With
    `minimum_time` each stretch may also be the minimum-time trajectory (`limit_path`), and
    the path is the faster of the two plans as a whole: the limit is solved from the path's
    own heading, and where the robot faces elsewhere the tube's join onto the path can beat
    it. Every stretch is timed, as it is driven, at the full limits."""
    duration = partial(_stretch_duration, config=run)
    drawn = Polyline(path.points())

    def joined(rounded: Path) -> Path:
        return joined_start(rounded, drawn, tolerance, duration,
                            lambda turn: least_time_s(Path(legs=(turn,)), run))

    if not run.max_angular_accel:
        return joined(rounded_path(path, tolerance, duration=duration))
    shapes = (CLOTHOID_PAIR, arc_shape(run.angular_speed, run.max_angular_accel))
    cost = partial(_corner_cost, config=run)
    by_tube = joined(rounded_path(path, tolerance, shapes, cost, duration))
    if not (minimum_time and plans_by_limit(run)):
        return by_tube
    by_limit = joined(rounded_path(path, tolerance, shapes, cost, duration,
                                   partial(limit_path, config=run)))
    return min((by_tube, by_limit), key=partial(_path_duration, config=run))


def plans_by_limit(config: ControlConfig) -> bool:
    """Whether `corner_planning: minimum_time` can offer the limit's motion on this base: one
    with both acceleration limits (elsewhere it plans as `tube` does)."""
    return bool(config.max_linear_accel and config.max_angular_accel)


def _path_duration(path: Path, *, config: ControlConfig) -> float:
    """The least time the controller drives a rounded `path` in, each leg from rest."""
    return least_time_s(path, config, tuple(
        profile_for(leg, config.limits, shares=FULL_LIMITS) if isinstance(leg, Polyline)
        else None for leg in path.legs))


def limit_path(points: np.ndarray, width: float, *,
               config: ControlConfig) -> tuple[np.ndarray, np.ndarray | None] | None:
    """The minimum-time trajectory within `width` of `points` on a base with `config`'s
    limits, its angular acceleration a little less (`min_time`): its positions, as finely as it was
    integrated between its nodes, and its speed at each (the follower keeps to its clock);
    where it turns in place on the way, only its path, every `tube.SPACING_M`, with no speeds
    (the follower plans them). None unless the solver converged and its motion keeps within
    the width between its nodes too (it is solved in a tube LIMIT_WIDTH_SHARE as wide)."""
    # only when asked: the command line starts without shapely and CasADi
    from turtle_traj.core.planning.min_time import minimum_time

    nodes = int(np.clip(LIMIT_NODES_PER_M * Polyline(points).length, *LIMIT_NODES))
    limits = config.limits
    # the angular acceleration's reserve is the steering's, as an exact path's profile keeps
    # it (`profile`): a motion at the very limits leaves nothing to pull back onto it with.
    # The turn rate needs none: where the steering asks for more, the timed tracker slows
    # down on the same curve.
    planned = replace(limits, angular_accel=ANGULAR_ACCEL_SHARE * limits.angular_accel)
    try:
        limit = minimum_time(points, LIMIT_WIDTH_SHARE * width, planned, nodes=nodes)
    except ImportError:
        raise PlanError("corner_planning 'minimum_time' needs CasADi (pip install casadi), "
                        "or set corner_planning to 'tube'") from None
    if not limit.solved or limit.max_error_m > width:
        return None
    moving = np.concatenate(([True], np.hypot(*np.diff(limit.motion, axis=0).T) > _APART_M))
    timed = Polyline(limit.motion[moving], speeds=limit.speeds[moving])
    if abs(SpeedProfile.timed(timed).duration_s - limit.time_s) > _TIMED_SHARE * limit.time_s:
        # it turns in place for a while: a motion along a polyline has no time for that
        return resampled(limit.motion, SPACING_M), None
    return timed.points, timed.speeds


def _stretch_duration(polyline: Polyline, *, config: ControlConfig) -> float:
    """The least time the controller drives rounded `polyline` in, from rest to rest."""
    profiles = (profile_for(polyline, config.limits, shares=FULL_LIMITS),)
    return least_time_s(Path(legs=(polyline,)), config, profiles)


def _corner_cost(points: np.ndarray, heading_in: float, heading_out: float, *,
                 config: ControlConfig) -> float:
    """Time a base takes through a corner, from rest to rest over the distance it needs to
    reach full speed on either side, less that distance at full speed."""
    speed = config.linear_speed
    run_up = speed * speed / (2.0 * (config.max_linear_accel or 1e6))
    before = points[0] - run_up * np.array([math.cos(heading_in), math.sin(heading_in)])
    after = points[-1] + run_up * np.array([math.cos(heading_out), math.sin(heading_out)])
    window = Polyline(np.concatenate(([before], points, [after])))
    return (SpeedProfile.plan(window, config.limits, FULL_LIMITS).duration_s
            - window.length / speed)


def largest_size(trajectory: str, request: Any, start: Pose2D,
                 settings: Settings) -> float | None:
    """Largest size of this request that fits from `start`, or None when nothing scales."""
    try:
        drawn = SKETCHES[trajectory](request, start, settings)
    except (PlanError, ShapeError):
        return None
    if not drawn.size_unit:
        return None
    return shapes.largest_fitting(drawn.build, lambda p: fits_in_arena(p, settings.arena, start),
                                  arena_diagonal(settings.arena))


def _checked(sketch: Sketch, arena: Arena, start: Pose2D) -> Path:
    """The sketch's path if it fits in the arena; else PlanError naming the largest size that
    fits from here (a size beyond the arena's diagonal is refused unbuilt)."""
    diagonal = arena_diagonal(arena)
    if sketch.size <= diagonal or not sketch.size_unit:
        path = sketch.build(sketch.size)
        if not path.legs and sketch.size_unit:
            raise PlanError(f'the {sketch.what} is too small to drive')
        if fits_in_arena(path, arena, start):
            return path
    message = (f'the {sketch.what} would leave the arena ({arena.describe()}, after the wall '
               f'margin) from ({start.x:.2f}, {start.y:.2f})')
    if sketch.size_unit:
        largest = shapes.largest_fitting(sketch.build, lambda p: fits_in_arena(p, arena, start),
                                         min(sketch.size, diagonal))
        message += (f'; the largest that fits from here is {largest:.2f} {sketch.size_unit}'
                    if largest > 1e-3 else '; nothing of this kind fits from here: move the '
                                           'turtle away from the wall first')
    raise PlanError(message)


# Each kind of trajectory in the registry (`trajectories`), by name, and its sketch.
SKETCHES: dict[str, SketchFunction] = {
    **{name: partial(motions.sketch_polygon, sides=sides, name=name)
       for name, sides in POLYGON_SIDES.items()},
    'polygon': motions.sketch_polygon,
    'circle': motions.sketch_circle,
    'spiral': motions.sketch_spiral,
    'sine': motions.sketch_sine,
    'star': curves.sketch_star,
    'heart': curves.sketch_heart,
    'lemniscate': curves.sketch_lemniscate,
    'rose': curves.sketch_rose,
    'lissajous': curves.sketch_lissajous,
    'text': drawings.sketch_text,
    'svg': drawings.sketch_svg,
    'go_to': motions.sketch_go_to,
    'move': motions.sketch_move,
    'rotate': motions.sketch_rotation,
    'follow_path': motions.sketch_follow,
}
