"""A run judged from what the simulator recorded, never from the student's output. Pure Python.

`judge` takes a task and a `Record` (the simulator's poses, what the pen drew, and the
services the run called) and answers a `Check` per check the task scores (none passes if the
turtle never moved): its points, and a sentence a student can act on ("side 3 is 1.62 m,
expected 2.00 ± 0.10 m"; "the turtle never stopped: still turning at 1.57 rad/s after 30.0 s").

The drawing is compared with the reference under the transforms the task allows
(`ExpectedDrawing.allow`): the reference is placed by the centroid (position), turned by the angle
that fits best (orientation, every degree, then refined), mirrored (direction) and scaled by the
drawing's spread (scale). The shape distance is the symmetric Hausdorff distance (shapely's).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely

from turtle_traj.core.grading.task import ExpectedDrawing, Task, reference
from turtle_traj.core.turtlesim_contract import WORLD_SIZE_M

NEVER_MOVED = 'the turtle never moved'
STOPPED = (1e-3, 1e-3)  # m/s, rad/s: slower counts as stopped
WALL_MARGIN_M = 0.1  # closer to a wall is off the arena's floor
CHEATS = ('teleport_absolute', 'teleport_relative', 'clear', 'reset', 'kill')
_JOINED_M = 1e-9  # a segment starting this close to the last one's end continues its stroke
_SIMPLIFY_SHARE = 0.5  # of the tolerance: a drawn corner's wobble is not a side
_BAND_M = 0.01  # the half-width of the band whose centroid is a line's centre
_COARSE = 120  # points of the drawing and the reference in the search over angles


@dataclass(frozen=True)
class Record:
    """What the simulator saw of one run: poses (time s, x, y, theta, linear, angular), what
    the pen drew (polylines), and the services called (time s, name)."""

    poses: np.ndarray  # (N, 6)
    strokes: Sequence[np.ndarray] = ()  # each (M, 2)
    calls: Sequence[tuple[float, str]] = ()

    @classmethod
    def from_simulator(cls, data: dict, turtle: str = 'turtle1') -> Record:
        """The record our simulator keeps (`sim.run_record.RunRecord.as_dict`, or its JSON),
        of `turtle`: its poses, the pen's segments joined into strokes where each goes on
        from the last, and the calls on it or on every turtle (a clear, a reset)."""
        poses = np.array(data['poses'].get(turtle, []), dtype=float).reshape(-1, 6)
        strokes: list[list[tuple[float, float]]] = []
        for _time, x0, y0, x1, y1 in data['segments']:
            if not strokes or math.dist(strokes[-1][-1], (x0, y0)) > _JOINED_M:
                strokes.append([(x0, y0)])
            strokes[-1].append((x1, y1))
        calls = [(time, service) for time, service, name in data['calls']
                 if name in ('', turtle)]
        return cls(poses, [np.array(stroke) for stroke in strokes], calls)


@dataclass(frozen=True)
class Check:
    """One check's verdict."""

    name: str
    score: float
    max_score: float
    message: str

    @property
    def passed(self) -> bool:
        return self.score >= self.max_score


@dataclass(frozen=True)
class Fit:
    """The reference placed on the drawing: its points, and its distance from the drawing."""

    points: np.ndarray
    distance: float
    transform: dict = field(default_factory=dict)


def judge(task: Task, record: Record, placed: Fit | None = None) -> list[Check]:
    """Every check `task` scores, judged on `record`, in the task's order."""
    drawn = drawn_points(record)
    verdicts = {'shape': lambda: _shape(task.expected, drawn, placed),
                'sides': lambda: _sides(task.expected, drawn),
                'closure': lambda: _closure(task.expected, drawn),
                'stops': lambda: _stops(record),
                'in_bounds': lambda: _in_bounds(record),
                'no_teleport': lambda: _no_teleport(record),
                'goal': lambda: _goal(task.expected, record)}
    if not _moved(record):  # standing still earns nothing: not even 'stops' or 'in_bounds'
        return [Check(name, 0.0, points, NEVER_MOVED)
                for name, points in task.points.items()]
    checks = []
    for name, points in task.points.items():
        passed, message = verdicts[name]()
        checks.append(Check(name, points if passed else 0.0, points, message))
    return checks


def fit(expected: ExpectedDrawing, drawn: np.ndarray) -> Fit:
    """The reference placed as the task allows so that it lies closest to `drawn`: every
    degree on both at `_COARSE` points, then the best angle refined to a tenth of a degree at
    full resolution. With `position` the reference's centre goes on the drawing's (each the
    centroid of the ground its line covers, so a stroke drawn twice weighs once); without, the
    reference starts where the drawing starts. Without `orientation` it leaves along +x
    (turtlesim's spawn heading)."""
    base = np.asarray(reference(expected), dtype=float)
    allow = expected.allow
    coarse_drawn = shapely.LineString(_resampled(drawn, _COARSE))
    drawn_line = shapely.LineString(drawn)
    anchor = _centre(drawn) if 'position' in allow else None
    best = Fit(base, math.inf)
    for mirror in ((False, True) if 'direction' in allow else (False,)):
        shape = base * (1.0, -1.0) if mirror else base
        if 'scale' in allow:
            shape = shape * (_spread(drawn) / max(_spread(shape), 1e-9))
        centre = _centre(shape)
        if 'orientation' not in allow:
            candidates = [0.0]
        else:
            coarse = _resampled(shape, _COARSE)
            distances = [shapely.hausdorff_distance(coarse_drawn, shapely.LineString(
                _placed(coarse, centre, angle, anchor, drawn[0])))
                for angle in np.radians(np.arange(0.0, 360.0, 1.0))]
            top = math.radians(float(np.argmin(distances)))
            candidates = top + np.radians(np.arange(-1.0, 1.05, 0.1))
        for angle in candidates:
            placed = _placed(shape, centre, float(angle), anchor, drawn[0])
            distance = shapely.hausdorff_distance(drawn_line, shapely.LineString(placed))
            if distance < best.distance:
                best = Fit(placed, distance, {'mirror': mirror, 'angle': float(angle)})
    return best


def _placed(shape: np.ndarray, centre: np.ndarray, angle: float, anchor: np.ndarray | None,
            start: np.ndarray) -> np.ndarray:
    """`shape` turned by `angle` about the origin, then its `centre` put on `anchor`, or (no
    anchor) its first point on `start`."""
    cos, sin = math.cos(angle), math.sin(angle)
    rotation = np.array([[cos, sin], [-sin, cos]])
    turned = shape @ rotation
    if anchor is not None:
        return turned - centre @ rotation + anchor
    return turned - turned[0] + start


def _resampled(points: np.ndarray, count: int) -> np.ndarray:
    """`count` points evenly along the polyline through `points`."""
    line = shapely.LineString(points)
    return np.array([line.interpolate(distance).coords[0]
                     for distance in np.linspace(0.0, line.length, count)])


def _centre(points: np.ndarray) -> np.ndarray:
    """The centroid of the ground a polyline covers (a thin band along it): a stretch drawn
    twice weighs once, and its vertices' spacing does not weigh."""
    line = shapely.LineString(points)
    if line.length == 0:
        return np.asarray(points[0], dtype=float)
    centroid = line.buffer(_BAND_M, cap_style='flat').centroid
    return np.array([centroid.x, centroid.y])


def _spread(points: np.ndarray) -> float:
    """The root-mean-square distance of the polyline from its centroid, by length."""
    samples = _resampled(points, 400)
    return float(np.sqrt(np.mean(np.sum((samples - _centre(points)) ** 2, axis=1))))


def drawn_points(record: Record) -> np.ndarray:
    """What the pen drew, its strokes joined in order ((0, 2) when nothing was drawn)."""
    strokes = [np.asarray(stroke, dtype=float).reshape(-1, 2) for stroke in record.strokes]
    strokes = [stroke for stroke in strokes if len(stroke) >= 2]
    return np.concatenate(strokes) if strokes else np.zeros((0, 2))


def _shape(expected: ExpectedDrawing, drawn: np.ndarray, placed: Fit | None) -> tuple[bool, str]:
    if len(drawn) < 2:
        return False, 'nothing was drawn: the pen left no line'
    placed = placed or fit(expected, drawn)
    within = placed.distance <= expected.tolerance
    return within, (f'the drawing lies within {placed.distance:.3f} m of the {expected.shape}'
                    f" ({'within' if within else 'beyond'} the tolerance "
                    f'{expected.tolerance:g} m)')


def _sides(expected: ExpectedDrawing, drawn: np.ndarray) -> tuple[bool, str]:
    if len(drawn) < 2:
        return False, 'nothing was drawn: no sides to measure'
    corners = np.asarray(shapely.LineString(drawn).simplify(
        _SIMPLIFY_SHARE * expected.tolerance, preserve_topology=False).coords)
    lengths = np.hypot(*np.diff(corners, axis=0).T)
    lengths = lengths[lengths > expected.tolerance]  # a hook at a corner is not a side
    wanted = 4 if expected.shape == 'square' else expected.sides
    if len(lengths) != wanted:
        return False, (f'{len(lengths)} sides drawn, expected {wanted} of '
                       f'{expected.size:.2f} ± {expected.tolerance:.2f} m')
    for index, length in enumerate(lengths, 1):
        if abs(length - expected.size) > expected.tolerance:
            return False, (f'side {index} is {length:.2f} m, expected {expected.size:.2f} ± '
                           f'{expected.tolerance:.2f} m')
    return True, (f'{wanted} sides of {min(lengths):.2f} to {max(lengths):.2f} m, expected '
                  f'{expected.size:.2f} ± {expected.tolerance:.2f} m')


def _closure(expected: ExpectedDrawing, drawn: np.ndarray) -> tuple[bool, str]:
    if len(drawn) < 2:
        return False, 'nothing was drawn: nothing to close'
    gap = float(np.hypot(*(drawn[-1] - drawn[0])))
    if not expected.closed:
        return True, 'an open path needs no closing'
    within = gap <= expected.tolerance
    return within, (f'the drawing ends {gap:.3f} m from where it began '
                    f"({'within' if within else 'beyond'} {expected.tolerance:g} m)")


def _moved(record: Record) -> bool:
    speeds = np.abs(record.poses[:, 4:6]) if len(record.poses) else np.zeros((0, 2))
    return bool(np.any((speeds[:, 0] > STOPPED[0]) | (speeds[:, 1] > STOPPED[1])))


def _stops(record: Record) -> tuple[bool, str]:
    if len(record.poses) == 0:
        return False, 'the simulator saw no pose'
    time, *_, linear, angular = record.poses[-1]
    if abs(linear) <= STOPPED[0] and abs(angular) <= STOPPED[1]:
        return True, f'the turtle stood still at the end ({time:.1f} s)'
    moving = (f'turning at {abs(angular):.2f} rad/s' if abs(angular) > STOPPED[1]
              else f'driving at {abs(linear):.2f} m/s')
    return False, f'the turtle never stopped: still {moving} after {time:.1f} s'


def _in_bounds(record: Record) -> tuple[bool, str]:
    if len(record.poses) == 0:
        return False, 'the simulator saw no pose'
    xy = record.poses[:, 1:3]
    clearance = np.minimum(xy, WORLD_SIZE_M - xy).min(axis=1)
    worst = int(np.argmin(clearance))
    if clearance[worst] < WALL_MARGIN_M:
        x, y = xy[worst]
        return False, (f'the turtle came within {max(clearance[worst], 0.0):.2f} m of the '
                       f'wall at ({x:.2f}, {y:.2f}) after {record.poses[worst, 0]:.1f} s')
    return True, f'the turtle kept {clearance[worst]:.2f} m from the walls at least'


def _goal(expected: ExpectedDrawing, record: Record) -> tuple[bool, str]:
    time, x, y = record.poses[-1, :3]
    gx, gy = expected.goal
    distance = math.hypot(x - gx, y - gy)
    within = distance <= expected.tolerance
    return within, (f'the turtle ended {distance:.3f} m from the goal ({gx:.2f}, {gy:.2f}) '
                    f"after {time:.1f} s ({'within' if within else 'beyond'} "
                    f'{expected.tolerance:g} m)')


def _no_teleport(record: Record) -> tuple[bool, str]:
    cheats = [(time, name) for time, name in record.calls if name in CHEATS]
    if cheats:
        time, name = cheats[0]
        return False, (f'the run called {name} after {time:.1f} s: the drawing must be '
                       'driven')
    return True, 'no teleport, clear, reset or kill was called'
