"""The minimum-time limit: the fastest a unicycle can go from rest at a path's start to rest at
its end while it stays within a tolerance of the path. Plain Python; CasADi with IPOPT solves it.

A direct optimal-control problem by multiple shooting:

* **States** at `nodes + 1` instants: the pose (x, y, heading) and, for a base with inertia,
  the speed and turn rate. **Controls**, constant over each interval: the accelerations (a base
  with inertia) or the speed and turn rate themselves (turtlesim, whose velocities take each
  command at once). Each interval is integrated by four steps of Runge-Kutta 4.
* **Limits**: 0 <= v <= top speed, |w| <= top turn rate, the accelerations' bounds.
* **The tube**: each node, and each step within an interval, carries its progress `s` along
  the path (0 at the start, the length at the end) and lies within the tolerance of the path's
  point at `s`. Progress that never goes back, and advances in an interval no more than the
  robot can drive, keeps a closed or crossing path from being cut short.
* **Ends**: at rest, on the path's first point with the given heading, and on its last point.

Each interval has a duration of its own, so time goes where it is needed. The problem is not
convex. It is solved twice: first with few long intervals from two starts (`exact_drive`: the
path with its corners rounded tight, or swinging out across the tube), which finds how to take
the corners; then with `nodes` shorter intervals from the better of the two, which holds the
motion to the tube more densely; and, where asked, again with twice the nodes while its motion
still leaves the tube between them.

What it omits: between nodes the motion is only integrated, not held to the tube (the error
between nodes is measured afterwards, `max_error_m`; a motion that cuts across the tube's edge
between nodes is faster than any that keeps within it, hence the finer solves); the robot's
control period and the transport's delay. Without inertia and at tolerance zero it solves
nothing: the limit is the path at the speed its curvature allows (`exact_drive`). With inertia,
a tolerance of zero is `EXACT_M`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np
import shapely

from turtle_traj.core.control.config import Limits
from turtle_traj.core.geometry.path import Polyline
from turtle_traj.core.planning.exact_drive import Timeline, exact_drive, rounded_corners

EXACT_M = 0.0005  # the tube's half-width asked for "exact": within the followers' own error
SEEDS = (False, True)  # the first solve's starts: corners rounded tight, or swinging out
SCOUTING_NODES = 60  # the first solve's intervals
SCOUTING_STEP_S = 0.5  # the first solve's longest interval; the second's: twice its mean
_RK4_STEPS = 4  # per interval; the tube is checked at each
_SHORTEST_STEP_S = 1e-3
_UNBOUNDED = 1e3  # an acceleration not limited (0), finite for the solver
_DENSE = 20  # samples per interval where the error is measured
STRAY_SHARE = 0.005  # of the tube's width, how far a limit's motion may leave it between nodes


@dataclass(frozen=True)
class MinimumTime:
    """The solved limit."""

    times: np.ndarray  # (nodes + 1,): each node's instant, s
    poses: np.ndarray  # (nodes + 1, 3): x, y, heading at each node
    velocities: np.ndarray  # (nodes + 1, 2): speed, turn rate (without inertia: as commanded)
    motion: np.ndarray  # (n, 2): the positions, integrated finely between nodes
    speeds: np.ndarray  # (n,): the speed at each position of `motion`
    max_error_m: float  # the largest distance of `motion` from the path
    solve_s: float  # CPU time of the solves
    solved: bool  # IPOPT converged

    @property
    def time_s(self) -> float:
        return float(self.times[-1])


def minimum_time(points: np.ndarray, tolerance_m: float, limits: Limits, *,
                 start_heading: float | None = None, nodes: int = 200,
                 most_nodes: int | None = None) -> MinimumTime:
    """The fastest motion along the polyline `points` (m) within `tolerance_m` of it (see the
    module) under `limits` (an acceleration of 0: none; the control period is not used).
    `start_heading` defaults to the first segment's direction. Up to `most_nodes`, a motion
    that leaves the tube between its nodes by more than `STRAY_SHARE` of it is solved again
    from itself with twice the nodes: one that cuts across the tube's edge is no limit, and
    its time is too short."""
    points = np.asarray(points, dtype=float)
    points = points[np.concatenate(([True], np.diff(Polyline(points).cumulative_length) > 1e-9))]
    heading0 = (math.atan2(*(points[1] - points[0])[::-1]) if start_heading is None
                else start_heading)
    if tolerance_m <= 0.0 and not limits.limited:
        return _on_the_path(points, limits, heading0)
    width = max(tolerance_m, EXACT_M)
    scouting = _Problem(points, width, limits, heading0, min(SCOUTING_NODES, nodes),
                        SCOUTING_STEP_S)
    scouts = [scouting.solve(exact_drive(rounded_corners(points, width, swing=swing), heading0,
                                         limits))
              for swing in SEEDS]
    best, spent = min(scouts, key=lambda scout: (not scout[0].solved, scout[0].time_s))
    final, timeline = _Problem(points, width, limits, heading0, nodes,
                               2.0 * best.time_s / nodes).solve(spent)
    if not final.solved and best.solved:
        final, timeline = best, spent
    solve_s = sum(scout.solve_s for scout, _ in scouts) + final.solve_s
    while (final.solved and final.max_error_m > (1.0 + STRAY_SHARE) * width
           and 2 * nodes <= (most_nodes or nodes)):
        nodes *= 2
        problem = _Problem(points, width, limits, heading0, nodes, 2.0 * final.time_s / nodes)
        for seed in (timeline, spent):  # from the last answer; else as the first was found
            finer, finer_timeline = problem.solve(seed)
            solve_s += finer.solve_s
            if finer.solved:
                break
        if not finer.solved:
            break
        final, timeline = finer, finer_timeline
    return replace(final, solve_s=solve_s)


def _on_the_path(points: np.ndarray, limits: Limits, heading0: float) -> MinimumTime:
    """Without inertia and tolerance, the limit is the path itself at the speed its curvature
    allows, turning in place at its corners: `exact_drive`, with nothing to solve."""
    began = time.process_time()
    drive = exact_drive(points, heading0, limits)
    return MinimumTime(drive.time, drive.poses, drive.velocities, drive.poses[:, :2],
                       drive.velocities[:, 0], 0.0, time.process_time() - began, True)


class _Problem:
    """The optimal-control problem (see the module) over `nodes` intervals, each at most
    `longest_step_s` long."""

    def __init__(self, points: np.ndarray, width: float, limits: Limits, heading0: float,
                 nodes: int, longest_step_s: float) -> None:
        import casadi  # noqa: PLC0415 (a bench's and a test's yardstick: loaded when asked for)

        self.points, self.limits, self.nodes = points, limits, nodes
        along = Polyline(points).cumulative_length
        # the path between its points as drawn: straight (IPOPT wanders metres off a
        # B-spline's smooth curve through a sampled sine)
        path_x = casadi.interpolant('path_x', 'linear', [along], points[:, 0])
        path_y = casadi.interpolant('path_y', 'linear', [along], points[:, 1])
        self.opti = opti = casadi.Opti()
        inertia = limits.limited
        self.states = states = opti.variable(5 if inertia else 3, nodes + 1)
        self.controls = controls = opti.variable(2, nodes)
        self.progress = progress = opti.variable(nodes + 1)
        # each interval its own duration: the time goes where it is needed
        self.steps = steps = opti.variable(1, nodes)
        opti.subject_to(opti.bounded(_SHORTEST_STEP_S, steps, longest_step_s))

        def derivative(state, control):
            speed, turn = (state[3], state[4]) if inertia else (control[0], control[1])
            rates = [speed * casadi.cos(state[2]), speed * casadi.sin(state[2]), turn]
            return casadi.vertcat(*rates, *(control[0], control[1]) if inertia else ())

        inside = [[] for _ in range(_RK4_STEPS - 1)]  # each interval's inner instants
        for k in range(nodes):
            state, h = states[:, k], steps[k] / _RK4_STEPS
            for substep in range(_RK4_STEPS):
                k1 = derivative(state, controls[:, k])
                k2 = derivative(state + h / 2 * k1, controls[:, k])
                k3 = derivative(state + h / 2 * k2, controls[:, k])
                k4 = derivative(state + h * k3, controls[:, k])
                state = state + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
                if substep < _RK4_STEPS - 1:
                    inside[substep].append(state[:2])
            opti.subject_to(states[:, k + 1] == state)
        speeds, turns = ((states[3, :], states[4, :]) if inertia
                         else (controls[0, :], controls[1, :]))
        opti.subject_to(opti.bounded(0, speeds, limits.linear_speed))
        opti.subject_to(opti.bounded(-limits.angular_speed, turns, limits.angular_speed))
        if inertia:
            angular = limits.angular_accel or _UNBOUNDED
            opti.subject_to(opti.bounded(-(limits.linear_braking or _UNBOUNDED), controls[0, :],
                                         limits.linear_accel or _UNBOUNDED))
            opti.subject_to(opti.bounded(-angular, controls[1, :], angular))
            opti.subject_to(states[3:, 0] == 0)
            opti.subject_to(states[3:, -1] == 0)
        opti.subject_to(states[:3, 0] == casadi.vertcat(*points[0], heading0))
        opti.subject_to(states[:2, -1] == casadi.vertcat(*points[-1]))
        opti.subject_to(progress[0] == 0)
        opti.subject_to(progress[-1] == float(along[-1]))
        # never back, and no further in an interval than the robot can go (plus the tube's
        # width: cutting a corner passes more of the path than it drives), so a closed path's
        # start and end, a step apart, are not one
        advance = progress[1:] - progress[:-1]
        opti.subject_to(opti.bounded(0, advance, limits.linear_speed * steps.T + 2 * width))
        checks = [(states[:2, :], progress)] + [
            (casadi.horzcat(*inner), progress[:-1] + (index + 1) / _RK4_STEPS * advance)
            for index, inner in enumerate(inside)]
        for where, at in checks:
            gap = (where[0, :].T - path_x(at)) ** 2 + (where[1, :].T - path_y(at)) ** 2
            opti.subject_to(gap / width ** 2 <= 1.0)
        opti.minimize(casadi.sum2(steps))
        opti.solver('ipopt', {'print_time': False, 'expand': True},
                    {'print_level': 0, 'sb': 'yes',  # 'sb': no banner on stdout
                     'max_iter': 3000, 'tol': 1e-8, 'acceptable_tol': 1e-6})

    def solve(self, start: Timeline) -> tuple[MinimumTime, Timeline]:
        """The solver's answer from the motion `start`, and that answer as a timeline."""
        opti, nodes, inertia = self.opti, self.nodes, self.limits.limited
        duration = float(start.time[-1])
        at = start.at(np.linspace(0.0, duration, nodes + 1))
        opti.set_initial(self.states[:3, :], at.poses.T)
        if inertia:
            opti.set_initial(self.states[3:, :], at.velocities.T)
            opti.set_initial(self.controls,
                             (np.diff(at.velocities, axis=0) / (duration / nodes)).T)
        else:
            opti.set_initial(self.controls, (0.5 * (at.velocities[:-1] + at.velocities[1:])).T)
        opti.set_initial(self.progress, at.progress)
        opti.set_initial(self.steps, np.full(nodes, duration / nodes))
        began = time.process_time()
        try:
            solution, solved = opti.solve(), True
        except RuntimeError:  # not converged: the last iterate, said so
            solution, solved = opti.debug, False
        solve_s = time.process_time() - began
        poses = np.asarray(solution.value(self.states[:3, :])).T
        taken = np.atleast_2d(np.asarray(solution.value(self.controls)))
        velocities = (np.asarray(solution.value(self.states[3:, :])).T if inertia
                      else np.vstack([taken.T, [0.0, 0.0]]))
        durations = np.atleast_1d(np.asarray(solution.value(self.steps), dtype=float)).ravel()
        times = np.concatenate(([0.0], np.cumsum(durations)))
        motion, speeds = _dense_motion(poses, velocities, taken, durations, inertia)
        error = float(np.max(shapely.distance(shapely.LineString(self.points),
                                              shapely.points(motion))))
        return (MinimumTime(times, poses, velocities, motion, speeds, error, solve_s, solved),
                Timeline(times, poses, velocities,
                         np.asarray(solution.value(self.progress), dtype=float).ravel()))


def _dense_motion(poses, velocities, controls, durations,
                  inertia) -> tuple[np.ndarray, np.ndarray]:
    """The motion's positions, integrated finely (_DENSE samples an interval) from each node,
    and its speed at each."""
    samples, speeds = [poses[0, :2]], [velocities[0, 0]]
    for k in range(len(poses) - 1):
        x, y, heading = poses[k]
        speed, turn = velocities[k]
        dt = durations[k] / _DENSE
        for _ in range(_DENSE):
            if inertia:
                speed, turn = (speed + controls[0, k] * dt / 2, turn + controls[1, k] * dt / 2)
            x += speed * math.cos(heading + turn * dt / 2) * dt
            y += speed * math.sin(heading + turn * dt / 2) * dt
            heading += turn * dt
            if inertia:
                speed, turn = (speed + controls[0, k] * dt / 2, turn + controls[1, k] * dt / 2)
            samples.append((x, y))
            speeds.append(speed)
    return np.asarray(samples), np.maximum(np.asarray(speeds, dtype=float), 0.0)
