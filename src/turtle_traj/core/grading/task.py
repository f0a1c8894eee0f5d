"""A lab's task file: what is run, what drawing is expected, and what each check is worth.
Pure Python.

A task file is YAML::

    name: square
    run:
      entry_point: turtle_square/square   # a package's, as `ros2 run` names it
      script: square.py      # or a single script (a task may take either)
      args: []
      time_limit: 40         # s of wall time the run may take
      settle: 5              # s the turtle stands after moving before a run still going ends
    expected:
      shape: square          # square, polygon, circle, spiral, points, or none
      size: 2.0              # side (square, polygon), radius (circle, a spiral's last)
      goal: [8.0, 3.0]       # where the turtle must end (the goal check), if anywhere
      tolerance: 0.1         # m: how far the drawing may lie from the reference
      allow: [position, orientation, direction]   # and scale
    checks:                  # points for each
      shape: 4
      sides: 3
      closure: 1
      stops: 1
      in_bounds: 1
      no_teleport: 1
      goal: 0

`read_task` checks every field and raises `TaskError` naming the one that is wrong.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

SHAPES = ('square', 'polygon', 'circle', 'spiral', 'points', 'none')
TRANSFORMS = ('position', 'orientation', 'direction', 'scale')
CHECKS = ('shape', 'sides', 'closure', 'stops', 'in_bounds', 'no_teleport', 'goal')
_DRAWING_CHECKS = ('shape', 'sides', 'closure')
_POLYGONAL = ('square', 'polygon')
MAX_TIME_LIMIT_S = 600.0
MAX_POINTS = 1000


class TaskError(ValueError):
    """A task file this grader cannot use: the message names the field."""


@dataclass(frozen=True)
class ExpectedDrawing:
    """The drawing expected, and what may differ from the reference."""

    shape: str
    size: float = 0.0
    sides: int = 4  # a polygon's
    points: tuple[tuple[float, float], ...] = ()  # a path given as points (x, y)
    tolerance: float = 0.1
    allow: frozenset[str] = frozenset({'position', 'orientation', 'direction'})
    turns: float = 3.0  # a spiral's
    goal: tuple[float, float] | None = None  # where the turtle must end (x, y)

    @property
    def closed(self) -> bool:
        return self.shape not in ('points', 'spiral')

    @property
    def polygonal(self) -> bool:
        return self.shape in _POLYGONAL


@dataclass(frozen=True)
class Task:
    """A lab's task (see the module)."""

    name: str
    script: str = ''  # a script of the submission, run with Python
    entry_point: str = ''  # package/executable, as `ros2 run` names it (taken first)
    args: tuple[str, ...] = ()
    time_limit_s: float = 60.0
    settle_s: float = 5.0
    expected: ExpectedDrawing = field(default_factory=lambda: ExpectedDrawing('square', 2.0))
    points: Mapping[str, float] = field(default_factory=dict)  # check -> points

    @property
    def max_score(self) -> float:
        return sum(self.points.values())


def read_task(data: object) -> Task:
    """The task a task file's parsed YAML describes.

    :raises TaskError: naming the field that is missing or wrong.
    """
    top = _mapping(data, 'the task file')
    run = _mapping(top.get('run', {}), 'run')
    script, entry_point = str(run.get('script', '') or ''), str(run.get('entry_point', '') or '')
    if not (script or entry_point):
        raise TaskError('run: give a script, an entry_point (package/executable), or both')
    if entry_point and entry_point.count('/') != 1:
        raise TaskError(f'run.entry_point {entry_point!r} must be package/executable')
    args = run.get('args', [])
    if not isinstance(args, list) or not all(isinstance(arg, (str, int, float)) for arg in args):
        raise TaskError('run.args must be a list of words')
    time_limit = _number(run.get('time_limit', 60.0), 'run.time_limit', 1.0, MAX_TIME_LIMIT_S)
    settle = _number(run.get('settle', 5.0), 'run.settle', 0.5, MAX_TIME_LIMIT_S)
    expected = _expected(_mapping(top.get('expected'), 'expected'))
    scores = _scores(_mapping(top.get('checks', {}), 'checks'), expected)
    return Task(str(top.get('name', 'task')), script, entry_point,
                tuple(str(arg) for arg in args), time_limit, settle, expected, scores)


def _scores(points: Mapping[str, object], expected: ExpectedDrawing) -> dict[str, float]:
    """Each check's points, every check one the expected drawing can be judged by."""
    unknown = sorted(set(points) - set(CHECKS))
    if unknown:
        raise TaskError(f"checks: {', '.join(unknown)} is not a check: choose from "
                        f"{', '.join(CHECKS)}")
    scores = {name: _number(value, f'checks.{name}', 0.0, MAX_POINTS)
              for name, value in points.items()}
    if not scores:
        raise TaskError('checks: give at least one check its points')
    if 'sides' in scores and not expected.polygonal:
        raise TaskError(f"checks.sides needs a square or a polygon, not a {expected.shape}")
    drawing = [check for check in _DRAWING_CHECKS if check in scores]
    if drawing and expected.shape == 'none':
        raise TaskError(f"checks.{drawing[0]} needs an expected.shape")
    if 'goal' in scores and expected.goal is None:
        raise TaskError('checks.goal needs an expected.goal [x, y]')
    return scores


def _expected(values: Mapping[str, object]) -> ExpectedDrawing:
    shape = values.get('shape', 'none')
    if shape not in SHAPES:
        raise TaskError(f"expected.shape {shape!r} is not one of {', '.join(SHAPES)}")
    tolerance = _number(values.get('tolerance', 0.1), 'expected.tolerance', 0.001, 5.0)
    allow = values.get('allow', ['position', 'orientation', 'direction'])
    if not isinstance(allow, list) or not set(allow) <= set(TRANSFORMS):
        raise TaskError(f"expected.allow must list some of {', '.join(TRANSFORMS)}, not "
                        f'{allow!r}')
    goal = None
    if 'goal' in values:
        goal = _points([values['goal'], values['goal']], 'expected.goal')[0]
    common = {'tolerance': tolerance, 'allow': frozenset(allow), 'goal': goal}
    if shape in ('points', 'none'):
        points = _points(values.get('points'), 'expected.points') if shape == 'points' else ()
        return ExpectedDrawing(shape, points=points, **common)
    size = _number(values.get('size'), 'expected.size', 0.01, 11.0)
    sides, turns = 4, 3.0
    if shape == 'polygon':
        sides = int(_number(values.get('sides'), 'expected.sides', 3, 12))
    if shape == 'spiral':
        turns = _number(values.get('turns', 3.0), 'expected.turns', 0.25, 20.0)
    return ExpectedDrawing(shape, size, sides, turns=turns, **common)


def _points(values: object, name: str) -> tuple[tuple[float, float], ...]:
    if not isinstance(values, list) or len(values) < 2:
        raise TaskError(f'{name} must list at least two points [x, y]')
    points = []
    for index, point in enumerate(values):
        where = name if name == 'expected.goal' else f'{name}[{index}]'
        if not isinstance(point, list) or len(point) != 2:
            raise TaskError(f'{where} must be [x, y], not {point!r}')
        points.append((_number(point[0], where, -100.0, 100.0),
                       _number(point[1], where, -100.0, 100.0)))
    return tuple(points)


def _mapping(value: object, name: str) -> Mapping[str, object]:
    if not isinstance(value, Mapping):
        raise TaskError(f'{name} must be a mapping of names to values, not {value!r}')
    return value


def _number(value: object, name: str, low: float, high: float) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (
            math.isfinite(value) and low <= value <= high):
        raise TaskError(f'{name} must be a number within [{low:g}, {high:g}], not {value!r}')
    return float(value)


def reference(expected: ExpectedDrawing, samples: int = 720) -> Sequence[tuple[float, float]]:
    """The reference drawing as points from its start (at the origin, leaving along +x,
    counter-clockwise): a polygon's vertices (closed), a circle's samples, the given points."""
    if expected.shape in ('points', 'none'):
        return list(expected.points)
    if expected.shape == 'spiral':  # Archimedean, from its centre: r = b theta
        end = 2.0 * math.pi * expected.turns
        pitch = expected.size / end
        return [(pitch * angle * math.cos(angle), pitch * angle * math.sin(angle))
                for angle in np.linspace(0.0, end, samples + 1)]
    if expected.polygonal:
        sides = 4 if expected.shape == 'square' else expected.sides
        vertices = [(0.0, 0.0)]
        for index in range(sides):
            heading = 2.0 * math.pi * index / sides
            x, y = vertices[-1]
            vertices.append((x + expected.size * math.cos(heading),
                             y + expected.size * math.sin(heading)))
        return vertices
    radius = expected.size
    return [(radius * math.sin(angle), radius * (1.0 - math.cos(angle)))
            for angle in (2.0 * math.pi * index / samples for index in range(samples + 1))]
