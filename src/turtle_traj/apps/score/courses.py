"""The standard courses every controller is scored on.

- `turtlesim`: the demo's trajectories (each kind's example from the registry), and a grid
  planner's path around two walls (`grid_planner`: 5 cm cells, staircases of 45-degree steps,
  as a Nav2 planner gives), on turtlesim's physics (velocities change at once), the node's
  default settings.
- `inertia`: the DWPP paper's step curves (45, 90 and 135 degrees: three 3 m legs) and its sine,
  on a unicycle whose velocity follows each command within 0.5 m/s^2 and 1.0 rad/s^2, the
  node at the paper's limits (0.5 m/s, 1.0 rad/s) in an open arena.
- `base`: a 1 m square and a 0.5 m circle on the MuJoCo base (a TurtleBot3 Burger), driven
  by odometry through ROS, lock-step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS, Settings, settings_from_values
from turtle_traj.core.parameters.table import DEFAULTS
from turtle_traj.core.registry import BY_NAME, TRAJECTORIES
from turtle_traj.sim.physics import Inertia

PAPER_LIMITS = {'linear_speed': 0.5, 'angular_speed': 1.0, 'max_linear_accel': 0.5,
                'max_angular_accel': 1.0}
PAPER_INERTIA = Inertia(0.5, 1.0)
STEP_LEG_M = 3.0
ROBOTS = ('turtlesim', 'inertia', 'base')


@dataclass(frozen=True)
class Course:
    """One course: a trajectory request from a start pose, on one robot."""

    name: str
    robot: str  # one of ROBOTS
    trajectory: str  # a registry name
    request: object  # the service request (fields by name)
    start: Pose2D
    settings: Settings = DEFAULT_SETTINGS


def step_curve(degrees: float) -> np.ndarray:
    """The paper's step curve: a leg, a turn of `degrees`, a leg, back to the first heading,
    a leg."""
    turn = math.radians(degrees)
    points = [(1.0, 1.5), (1.0 + STEP_LEG_M, 1.5)]
    points.append((points[-1][0] + STEP_LEG_M * math.cos(turn),
                   points[-1][1] + STEP_LEG_M * math.sin(turn)))
    points.append((points[-1][0] + STEP_LEG_M, points[-1][1]))
    return np.array(points)


def paper_sine() -> np.ndarray:
    """The paper's sine: one period of amplitude 1 m over 6 m."""
    x = np.linspace(0.0, 6.0, 601)
    return np.stack([2.0 + x, 5.0 + np.sin(2.0 * math.pi * x / 6.0)], axis=1)


def follow_request(points: np.ndarray, **fields) -> SimpleNamespace:
    """A FollowPath request through `points`: exact corners, the node's speeds, no final
    heading, but for `fields`."""
    return SimpleNamespace(points=[SimpleNamespace(x=float(x), y=float(y), z=0.0)
                                   for x, y in points],
                           **{'linear_speed': 0.0, 'closed': False, 'corner_tolerance': 0.0,
                              'use_theta': False, 'theta': 0.0, **fields})


def _demo_courses() -> list[Course]:
    from turtle_traj.api.ros_interface import make_request
    return [Course(kind.name, 'turtlesim', kind.name, make_request(kind, kind.example.given),
                   Pose2D(*kind.example.start)) for kind in TRAJECTORIES]


def planner_path() -> np.ndarray:
    """A grid planner's path across turtlesim's arena, between two walls (0.5 m of a robot's
    clearance included), from the lower left to the upper right."""
    def blocked(x: float, y: float) -> bool:
        return (3.5 <= x <= 4.5 and y <= 7.0) or (6.5 <= x <= 7.5 and y >= 4.0)
    from turtle_traj.apps.score.grid_planner import grid_path  # networkx, only when scored
    return grid_path((1.5, 1.5), (9.5, 9.2), blocked, (0.5, 10.5))


def _planner_course() -> Course:
    points = planner_path()
    heading = math.atan2(points[1, 1] - points[0, 1], points[1, 0] - points[0, 0])
    return Course('planner path', 'turtlesim', 'follow_path', follow_request(points),
                  Pose2D(float(points[0, 0]), float(points[0, 1]), heading))


def _paper_courses() -> list[Course]:
    settings = settings_from_values({**DEFAULTS, **PAPER_LIMITS, 'arena': 'none'})
    paths = [(f'step{angle}', step_curve(angle)) for angle in (45, 90, 135)]
    paths.append(('paper sine', paper_sine()))
    courses = []
    for name, points in paths:
        heading = math.atan2(points[1, 1] - points[0, 1], points[1, 0] - points[0, 0])
        courses.append(Course(name, 'inertia', 'follow_path', follow_request(points),
                              Pose2D(float(points[0, 0]), float(points[0, 1]), heading),
                              settings))
    return courses


def _base_courses() -> list[Course]:
    from turtle_traj.api.ros_interface import make_request
    start = Pose2D(0.0, 0.0, 0.0)  # where the base stands after a reset
    return [Course(f'base {name} {size:g} m', 'base', name,
                   make_request(BY_NAME[name], {'size': size}), start)
            for name, size in (('square', 1.0), ('circle', 0.5))]


def standard_courses(robots: tuple[str, ...] = ROBOTS) -> list[Course]:
    """Every standard course on these robots."""
    courses = []
    if 'turtlesim' in robots:
        courses += [*_demo_courses(), _planner_course()]
    if 'inertia' in robots:
        courses += _paper_courses()
    if 'base' in robots:
        courses += _base_courses()
    return courses
