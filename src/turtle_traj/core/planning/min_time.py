"""The minimum-time limit: the fastest a unicycle can go from rest at a path's start to rest at
its end while it stays within a tolerance of the path. Plain Python; CasADi with IPOPT solves it.

A direct optimal-control problem by multiple shooting:

* **States** at `nodes + 1` instants: the pose (x, y, heading) and, for a base with inertia,
  the speed and turn rate. **Controls**, constant over each of the `nodes` intervals: the
  accelerations (a base with inertia) or the speed and turn rate themselves (turtlesim, whose
  velocities take each command at once). The final time is free; the intervals share it equally.
  Each interval is integrated by two steps of Runge-Kutta 4.
* **Limits**: 0 <= v <= top speed, |w| <= top turn rate, and the accelerations' bounds.
* **The tube**: each node carries its progress `s` along the path (from 0 at the start to the
  length at the end), and lies within the tolerance of the path's point at `s`. Progress that
  never goes back, and advances in an interval no more than the robot can drive, keeps a
  closed or crossing path from being cut short.
* **Ends**: at rest, on the path's first point with the given heading, and on its last point.

What it omits: between nodes the motion is only integrated, not held to the tube (the error
between nodes is measured afterwards, `max_error_m`); the robot's control period and the
transport's delay; a tolerance of zero, which at a corner means a stop (`EXACT_M` stands for it).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import shapely

EXACT_M = 0.0005  # the tube's half-width asked for "exact": within the followers' own error
SAMPLED_CURVE_DEG = 10.0  # a polyline turning less than this at every vertex samples a curve
_RK4_STEPS = 2  # per interval
_DENSE = 20  # samples per interval where the error is measured


@dataclass(frozen=True)
class RobotLimits:
    """A unicycle's bounds; no acceleration bounds: velocities take each command at once."""

    speed: float  # m/s
    turn_rate: float  # rad/s
    acceleration: float | None = None  # m/s^2
    angular_acceleration: float | None = None  # rad/s^2

    @property
    def has_inertia(self) -> bool:
        return self.acceleration is not None


@dataclass(frozen=True)
class MinimumTime:
    """The solved limit."""

    time_s: float
    poses: np.ndarray  # (nodes + 1, 3): x, y, heading at each node
    velocities: np.ndarray  # (nodes + 1, 2): speed, turn rate (the controls', held, without inertia)
    max_error_m: float  # the largest distance to the path, along the integrated motion
    solve_s: float
    solved: bool  # IPOPT converged


def path_length(points: np.ndarray) -> np.ndarray:
    """The arc length at each point of a polyline."""
    return np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(points, axis=0).T))))


def minimum_time(points: np.ndarray, tolerance_m: float, limits: RobotLimits, *,
                 start_heading: float | None = None, nodes: int = 200) -> MinimumTime:
    """The fastest motion along the polyline `points` (m) within `tolerance_m` of it (see the
    module). `start_heading` defaults to the first segment's direction."""
    import casadi  # noqa: PLC0415 (a bench's and a test's yardstick: loaded when asked for)

    points = np.asarray(points, dtype=float)
    along = path_length(points)
    keep = np.concatenate(([True], np.diff(along) > 1e-9))
    points, along = points[keep], along[keep]
    length = float(along[-1])
    heading0 = (math.atan2(*(points[1] - points[0])[::-1]) if start_heading is None
                else start_heading)
    width = max(tolerance_m, EXACT_M)
    # a sampled curve as the smooth curve through its points (a polyline's kinks at every
    # sample stall the solver); corners as they are
    method = ('bspline' if len(points) >= 4 and _largest_turn_deg(points) < SAMPLED_CURVE_DEG
              else 'linear')
    path_x = casadi.interpolant('path_x', method, [along], points[:, 0])
    path_y = casadi.interpolant('path_y', method, [along], points[:, 1])

    opti = casadi.Opti()
    inertia = limits.has_inertia
    states = opti.variable(5 if inertia else 3, nodes + 1)
    controls = opti.variable(2, nodes)
    progress = opti.variable(nodes + 1)
    total = opti.variable()
    step = total / nodes

    def derivative(state, control):
        speed, turn = (state[3], state[4]) if inertia else (control[0], control[1])
        rates = [speed * casadi.cos(state[2]), speed * casadi.sin(state[2]), turn]
        return casadi.vertcat(*rates, control[0], control[1]) if inertia else casadi.vertcat(*rates)

    midpoints = []  # each interval's middle, held to the tube too
    for k in range(nodes):
        state, h = states[:, k], step / _RK4_STEPS
        for substep in range(_RK4_STEPS):
            k1 = derivative(state, controls[:, k])
            k2 = derivative(state + h / 2 * k1, controls[:, k])
            k3 = derivative(state + h / 2 * k2, controls[:, k])
            k4 = derivative(state + h * k3, controls[:, k])
            state = state + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            if substep == _RK4_STEPS // 2 - 1:
                midpoints.append(state[:2])
        opti.subject_to(states[:, k + 1] == state)
    speeds, turns = ((states[3, :], states[4, :]) if inertia else (controls[0, :], controls[1, :]))
    opti.subject_to(opti.bounded(0, speeds, limits.speed))
    opti.subject_to(opti.bounded(-limits.turn_rate, turns, limits.turn_rate))
    if inertia:
        opti.subject_to(opti.bounded(-limits.acceleration, controls[0, :], limits.acceleration))
        opti.subject_to(opti.bounded(-limits.angular_acceleration, controls[1, :],
                                     limits.angular_acceleration))
        opti.subject_to(states[3:, 0] == 0)
        opti.subject_to(states[3:, -1] == 0)
    opti.subject_to(states[:3, 0] == casadi.vertcat(*points[0], heading0))
    opti.subject_to(states[:2, -1] == casadi.vertcat(*points[-1]))
    opti.subject_to(progress[0] == 0)
    opti.subject_to(progress[-1] == length)
    # never back, and no further in an interval than the robot can go (plus the tube's width:
    # cutting a corner passes more of the path than it drives), so a closed path's start and
    # end, a step apart, are not one
    advance = progress[1:] - progress[:-1]
    opti.subject_to(opti.bounded(0, advance, limits.speed * step + 2 * width))
    gap = (states[0, :].T - path_x(progress)) ** 2 + (states[1, :].T - path_y(progress)) ** 2
    opti.subject_to(gap / width ** 2 <= 1.0)
    middle = casadi.horzcat(*midpoints)
    halfway = (progress[1:] + progress[:-1]) / 2
    gap = (middle[0, :].T - path_x(halfway)) ** 2 + (middle[1, :].T - path_y(halfway)) ** 2
    opti.subject_to(gap / width ** 2 <= 1.0)
    opti.subject_to(opti.bounded(1e-3, total, 1e4))
    opti.minimize(total)
    _initial_guess(opti, points, along, limits, states, progress, total, nodes, heading0)
    opti.solver('ipopt', {'print_time': False},
                {'print_level': 0, 'max_iter': 3000, 'tol': 1e-8, 'acceptable_tol': 1e-6})
    began = time.process_time()
    try:
        solution, solved = opti.solve(), True
    except RuntimeError:  # not converged: the last iterate, said so
        solution, solved = opti.debug, False
    solve_s = time.process_time() - began
    poses = np.asarray(solution.value(states[:3, :])).T
    taken = np.asarray(solution.value(controls))
    velocities = (np.asarray(solution.value(states[3:, :])).T if inertia
                  else np.vstack([taken.T, [0.0, 0.0]]))
    time_s = float(solution.value(total))
    return MinimumTime(time_s, poses, velocities,
                       _max_error(points, poses, velocities, taken, time_s / nodes, inertia),
                       solve_s, solved)


def _largest_turn_deg(points: np.ndarray) -> float:
    legs = np.diff(points, axis=0)
    headings = np.unwrap(np.arctan2(legs[:, 1], legs[:, 0]))
    return float(np.degrees(np.max(np.abs(np.diff(headings)), initial=0.0)))


def _initial_guess(opti, points, along, limits, states, progress, total, nodes, heading0):
    """A start the solver can improve: the path at an even pace, at half the top speed."""
    guess_s = np.linspace(0.0, along[-1], nodes + 1)
    xy = np.column_stack([np.interp(guess_s, along, points[:, i]) for i in (0, 1)])
    heading = np.unwrap(np.concatenate(([heading0], np.arctan2(*np.diff(xy, axis=0).T[::-1]))))
    opti.set_initial(states[0, :], xy[:, 0])
    opti.set_initial(states[1, :], xy[:, 1])
    opti.set_initial(states[2, :], heading)
    opti.set_initial(progress, guess_s)
    opti.set_initial(total, 2.0 * along[-1] / limits.speed + 1.0)


def _max_error(points, poses, velocities, controls, step_s, inertia) -> float:
    """The largest distance from the path along the motion, integrated finely between nodes."""
    path = shapely.LineString(points)
    samples = []
    for k in range(len(poses) - 1):
        x, y, heading = poses[k]
        speed, turn = velocities[k]
        dt = step_s / _DENSE
        for _ in range(_DENSE):
            if inertia:
                speed, turn = (speed + controls[0, k] * dt / 2, turn + controls[1, k] * dt / 2)
            x += speed * math.cos(heading + turn * dt / 2) * dt
            y += speed * math.sin(heading + turn * dt / 2) * dt
            heading += turn * dt
            if inertia:
                speed, turn = (speed + controls[0, k] * dt / 2, turn + controls[1, k] * dt / 2)
            samples.append((x, y))
    distances = shapely.distance(path, shapely.points(np.asarray(samples)))
    return float(np.max(distances)) if len(distances) else 0.0
