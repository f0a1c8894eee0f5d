"""The pure closed loop of a base with acceleration limits, shared by the base benchmarks.

The DWPP paper's robot: a unicycle whose velocity follows each command within |a| <= a_max and
|alpha| <= alpha_max per 16 ms step (`sim.physics.World` with `Inertia`), driven by
turtle_traj's `ControlLoop` (a pose in, one command out per step, as the node does) or by the
DWPP reference. Every figure is measured here, from the poses, against the path as drawn.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from turtle_traj.api.controllers import choose
from turtle_traj.apps.score.courses import follow_request
from turtle_traj.apps.score.loop import drive
from turtle_traj.core.control.commands import Command
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.geometry.projection import NearestOnPolyline
from turtle_traj.core.parameters.settings import Settings, settings_from_values
from turtle_traj.core.parameters.table import DEFAULTS
from turtle_traj.core.planning import planner
from turtle_traj.core.turtlesim_contract import STEP_S
from turtle_traj.sim.physics import Inertia


@dataclass(frozen=True)
class Limits:
    """A base's limits: top speeds and accelerations."""

    v: float = 0.5
    omega: float = 1.0
    a: float = 0.5
    alpha: float = 1.0


DWPP_LIMITS = Limits()


@dataclass
class Run:
    """One run's record and figures."""

    poses: list[Pose2D] = field(default_factory=list)
    commands: list[Command] = field(default_factory=list)
    ended: bool = False
    success: bool = False
    message: str = ''
    steps: int = 0

    def figures(self, drawn: np.ndarray, limits: Limits, end: tuple[float, float]) -> dict:
        xy = np.array([(p.x, p.y) for p in self.poses])
        distances = NearestOnPolyline(drawn).distances(xy)
        return {'rmse_mm': 1e3 * float(np.sqrt(np.mean(distances ** 2))),
                'max_mm': 1e3 * float(distances.max()),
                'time_s': self.steps * STEP_S,
                'outside_pct': 100.0 * outside_share(self.commands, limits),
                'end_mm': 1e3 * math.dist((xy[-1, 0], xy[-1, 1]), end),
                'ended': self.ended, 'success': self.success, 'message': self.message}


def outside_share(commands: list[Command], limits: Limits) -> float:
    """Share of commands the base cannot take in one step from the one before."""
    if not commands:
        return 0.0
    outside, previous = 0, Command()
    for command in commands:
        if (abs(command.linear - previous.linear) > limits.a * STEP_S * (1 + 1e-6)
                or abs(command.angular - previous.angular) > limits.alpha * STEP_S * (1 + 1e-6)
                or abs(command.linear) > limits.v * (1 + 1e-9)
                or abs(command.angular) > limits.omega * (1 + 1e-9)):
            outside += 1
        previous = command
    return outside / len(commands)


def base_settings(limits: Limits, **values) -> Settings:
    """The node's settings for a base with these limits, in an open arena."""
    return settings_from_values({
        **DEFAULTS, 'linear_speed': limits.v, 'angular_speed': limits.omega,
        'max_linear_accel': limits.a, 'max_angular_accel': limits.alpha,
        'arena_min_x': -100.0, 'arena_min_y': -100.0, 'arena_max_x': 100.0,
        'arena_max_y': 100.0, **values})


def drive_turtle_traj(points: np.ndarray, start: Pose2D, limits: Limits, *,
                      inertia: Inertia | None = None, corner_tolerance: float = 0.0,
                      max_s: float = 120.0, controller: str = 'exact', **values) -> Run:
    """follow_path through `points`, on the loop the node runs, with one of its controllers
    (`exact`, `dwpp`, ...: the node's `controller` parameter)."""
    settings = base_settings(limits, **values)
    plan = planner.plan('follow_path', follow_request(points, corner_tolerance=corner_tolerance),
                        start, settings)
    record = drive(plan, start, settings, inertia=inertia or Inertia(limits.a, limits.alpha),
                   controller=choose(controller), max_s=max_s)
    success, message = record.run.ending
    return Run(poses=record.poses, commands=record.commands, ended=True, success=success,
               message=message, steps=record.steps)
