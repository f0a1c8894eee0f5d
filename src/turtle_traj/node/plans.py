"""Service requests to plans: which path, at which speeds, ending how precisely.

Pure (requests are read by attribute only), so the node and a client estimating the duration
of a call plan exactly alike.
"""

from __future__ import annotations

from dataclasses import dataclass

from turtle_traj import planning
from turtle_traj.geometry.path import Path, Pose2D
from turtle_traj.planning import PlanError
from turtle_traj.settings import Settings

MIN_SPEED, MAX_SPEED = 0.01, 10.0  # m/s and rad/s a request may ask for (as the parameters)


@dataclass(frozen=True)
class Plan:
    """A checked path plus the per-run speed overrides and end tolerance."""

    kind: str
    path: Path
    speeds: dict[str, float]
    end_tolerance: float | None = None

    def lower_bound_s(self, settings: Settings) -> float:
        """Kinematic lower bound of the run's duration at its top speeds."""
        return self.path.lower_bound_s(
            self.speeds.get('linear_speed', settings.control.linear_speed),
            self.speeds.get('angular_speed', settings.control.angular_speed))


def speed_overrides(linear: float, angular: float) -> dict[str, float]:
    """Speeds a request asks for (0 = the node's parameter), validated."""
    overrides = {}
    for name, value in (('linear_speed', linear), ('angular_speed', angular)):
        planning.require_finite(**{name: value})
        if value != 0.0 and not MIN_SPEED <= value <= MAX_SPEED:
            raise PlanError(f'{name} must be 0 (the default) or within {MIN_SPEED:g} and '
                            f'{MAX_SPEED:g}; got {value:g}')
        if value > 0.0:
            overrides[name] = value
    return overrides


def plan_request(service: str, request, pose: Pose2D, settings: Settings) -> Plan:
    """The plan for a request to `service` (e.g. 'draw_square'), or PlanError saying why."""
    plan = _plan(service, request, pose, settings)
    if not plan.path.legs:  # the follower and the report need at least one leg
        raise PlanError('nothing to drive: the turtle is already there')
    return plan


def _plan(service: str, request, pose: Pose2D, settings: Settings) -> Plan:
    arena, defaults = settings.arena, settings.defaults
    if service.startswith('draw_'):
        shape = service.removeprefix('draw_')
        fields = planning.ShapeRequest(
            sides=request.sides, size=request.size, clockwise=request.clockwise,
            turns=request.turns, growth=request.growth, max_radius=request.max_radius,
            frequency=request.frequency, length=request.length)
        speeds = speed_overrides(request.linear_speed, request.angular_speed)
        return Plan(shape, planning.plan_shape(shape, fields, pose, defaults, arena), speeds)
    if service == 'go_to':
        speeds = speed_overrides(request.linear_speed, 0.0)
        path = planning.plan_go_to(
            pose, x=request.x, y=request.y, theta=request.theta if request.use_theta else None,
            tolerance=request.tolerance, defaults=defaults, arena=arena)
        return Plan('go_to', path, speeds, request.tolerance or defaults.goal_tolerance)
    if service == 'move':
        speeds = speed_overrides(request.speed, 0.0)
        return Plan('move', planning.plan_move(pose, distance=request.distance, arena=arena),
                    speeds)
    if service == 'rotate':
        speeds = speed_overrides(0.0, request.speed)
        return Plan('rotate', planning.plan_rotation(pose, angle=request.angle), speeds)
    if service == 'follow_path':
        speeds = speed_overrides(request.linear_speed, 0.0)
        points = [(p.x, p.y) for p in request.points]
        path = planning.plan_follow(pose, points=points, closed=request.closed,
                                    defaults=defaults, arena=arena)
        return Plan('follow_path', path, speeds)
    raise PlanError(f'unknown trajectory service {service!r}')
