"""The minimum-time limit (`core.planning.min_time`) on the DWPP paper's paths, at the
tolerances of issue 76's table, beside the reference's times there and ours.

    .venv/bin/python bench/limit_bench.py [--nodes 120] [--most-nodes 480] [--twice]
                                          [--plot PNG] [--through-ros SCALE]

The base with inertia of the paper (0.5 m/s, 1 rad/s, 0.5 m/s^2, 1 rad/s^2): three 3 m legs
turning 45, 90 and 135 degrees (the 135 degree one also within pure pursuit's maximum error on
it in `turtle-traj score --matched`, 106 mm), and one period of a sine (1 m over 6 m), from
facing its first leg and from facing along x. For each:
- the limit: its time, its largest distance from the path (integrated between the nodes), its
  nodes (doubled from `--nodes` while its motion left the tube between them) and the CPU time
  of its solves; with `--twice`, the limit again with twice those nodes (how much the
  discretisation still moves it);
- the reference DWPP's time at its maximum error (written from the paper; issue 76's figures,
  measured in a plain simulation of the same model);
- the CPU time of our plan (`plan s`, tube planning, as the node plans the request);
- ours: `follow_path` with `corner_tolerance` set to that error, on the pure loop the node
  runs (`base_loop.drive_turtle_traj`, the simulator's physics, 16 ms steps), with
  `corner_planning` 'tube' (the default) and 'minimum_time': its time, its largest distance
  from the path measured here from the poses, and its time over the limit's;
- with `--through-ros SCALE`, ours again through ROS as issue 76 measured it: the simulator
  with inertia and the node as two programs, at SCALE times real time (`base_realtime`), the
  node's own figures from its response.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from base_bench import sine, step_curve
from base_loop import DWPP_LIMITS, base_settings, drive_turtle_traj
from base_realtime import drive_through_ros
from turtle_traj.apps.score.courses import follow_request
from turtle_traj.core.geometry.path import Pose2D
from turtle_traj.core.planning import planner
from turtle_traj.core.planning.min_time import minimum_time

PAPER = base_settings(DWPP_LIMITS).control.limits


def staircase(steps: int = 24, cell: float = 0.05) -> np.ndarray:
    """A grid planner's diagonal: `steps` times one cell along x, then one along y."""
    moves = np.tile([[cell, 0.0], [0.0, cell]], (steps, 1))
    return np.array([1.0, 1.0]) + np.concatenate(([[0.0, 0.0]], np.cumsum(moves, axis=0)))


# issue 76: the reference DWPP's maximum error and its time (none for the staircase, nor for
# the 135 degree step at pure pursuit's maximum error on it in `turtle-traj score --matched`)
CASES = [('step 45', step_curve(45), None, 0.062, 18.7),
         ('step 90', step_curve(90), None, 0.086, 19.5),
         ('step 135', step_curve(135), None, 0.165, 21.4),
         ("step 135 at pure pursuit's", step_curve(135), None, 0.10607, None),
         ('sine, facing its leg', sine(), None, 0.104, 16.3),
         ('sine, facing x', sine(), 0.0, 0.104, 16.3),
         ('staircase, facing diagonal', staircase(), math.pi / 4, 0.05, None),
         ('staircase, facing x', staircase(), 0.0, 0.05, None)]
PLOTTED = ('step 90', 'sine, facing x')


def _shown(reference: float | None) -> str:
    return f'{reference:6.1f}' if reference is not None else f'{"-":>6}'


def _start(points, heading: float | None) -> Pose2D:
    first = points[1] - points[0]
    return Pose2D(float(points[0, 0]), float(points[0, 1]),
                  math.atan2(first[1], first[0]) if heading is None else heading)


def planning_s(points, heading: float | None, tolerance: float) -> float:
    """The CPU time of our plan (tube planning), as the node plans a request."""
    settings = base_settings(DWPP_LIMITS)
    request = follow_request(points, corner_tolerance=tolerance)
    began = time.process_time()
    planner.plan('follow_path', request, _start(points, heading), settings)
    return time.process_time() - began


def ours(points, heading: float | None, tolerance: float,
         corner_planning: str) -> tuple[float, float, np.ndarray]:
    """Our time, largest distance from the path and positions, rounded within `tolerance` by
    `corner_planning` ('tube' or 'minimum_time')."""
    start = _start(points, heading)
    run = drive_turtle_traj(points, start, DWPP_LIMITS, corner_tolerance=tolerance,
                            corner_planning=corner_planning)
    figures = run.figures(points, DWPP_LIMITS, tuple(points[-1]))
    return figures['time_s'], figures['max_mm'], np.array([(p.x, p.y) for p in run.poses])


def plot(drawn: list[tuple], where: str) -> None:
    """The tube, the limit's path and ours (tube planning) at the 90 degree step's first corner
    and on the sine facing x."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    import shapely

    figure, axes = plt.subplots(1, len(drawn), figsize=(6 * len(drawn), 5))
    for axis, (name, points, tolerance, limit, our) in zip(axes, drawn, strict=True):
        tube = shapely.LineString(points).buffer(tolerance)
        axis.fill(*tube.exterior.xy, color='0.9', label=f'tube, {tolerance * 1e3:.0f} mm')
        for hole in tube.interiors:
            axis.fill(*hole.xy, color='white')
        axis.plot(points[:, 0], points[:, 1], 'k--', lw=0.8, label='path')
        axis.plot(limit.motion[:, 0], limit.motion[:, 1], 'C0', lw=1.5,
                  label=f'limit {limit.time_s:.2f} s')
        axis.plot(our[1][:, 0], our[1][:, 1], 'C3', lw=1.0, label=f'ours {our[0]:.2f} s')
        if name.startswith('step'):
            corner = points[1]
            axis.set_xlim(corner[0] - 1.0, corner[0] + 0.6)
            axis.set_ylim(corner[1] - 0.4, corner[1] + 1.2)
        axis.set_title(f'{name}, within {tolerance * 1e3:.0f} mm')
        axis.set_aspect('equal')
        axis.legend(loc='best', fontsize=8)
    figure.tight_layout()
    figure.savefig(where, dpi=90)
    print(f'plotted: {where}')


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--nodes', type=int, default=120)
    parser.add_argument('--most-nodes', type=int, default=480,
                        help="solved again with twice the nodes, up to these, while the limit's "
                             'motion leaves the tube between its nodes')
    parser.add_argument('--twice', action='store_true',
                        help='also solve with twice the nodes')
    parser.add_argument('--plot', metavar='PNG',
                        help="draw the limit's path and ours at a corner and on the sine")
    parser.add_argument('--through-ros', metavar='SCALE', type=float,
                        help='also drive ours through ROS, two programs, at SCALE x real time')
    options = parser.parse_args()
    print(f'{"":60} {"ours, tube":^31}  {"ours, minimum_time":^23}')
    print(f'{"path":26} {"tol mm":>6} {"limit s":>8} {"err mm":>7} {"nodes":>5} {"solve s":>8} '
          f'{"2x nodes":>9} {"ref s":>6} {"plan s":>7}'
          + f' {"time s":>7} {"err mm":>7} {"/limit":>7}' * 2)
    drawn, limits = [], {}
    for name, points, heading, tolerance, reference in CASES:
        limit = minimum_time(points, tolerance, PAPER, start_heading=heading,
                             nodes=options.nodes, most_nodes=options.most_nodes)
        finer = f'{"-":>9}'
        if options.twice:
            finer_s = minimum_time(points, tolerance, PAPER, start_heading=heading,
                                   nodes=2 * len(limit.times) - 2).time_s
            finer = f'{finer_s:9.2f}'
        planning_s(points, heading, tolerance)  # TOPP-RA and SciPy loaded
        columns = f' {planning_s(points, heading, tolerance):7.2f}'
        for way in ('tube', 'minimum_time'):
            our_s, our_mm, our_xy = ours(points, heading, tolerance, way)
            columns += f' {our_s:7.2f} {our_mm:7.1f} {our_s / limit.time_s:7.3f}'
            if way == 'tube' and name in PLOTTED:
                drawn.append((name, points, tolerance, limit, (our_s, our_xy)))
        limits[name] = limit.time_s
        flag = '' if limit.solved else '  (not converged)'
        print(f'{name:26} {tolerance * 1e3:6.0f} {limit.time_s:8.2f} '
              f'{limit.max_error_m * 1e3:7.1f} {len(limit.times) - 1:5d} {limit.solve_s:8.1f} '
              f'{finer} {_shown(reference)}'
              f'{columns}{flag}')
    straight = 9.0 / PAPER.linear_speed + PAPER.linear_speed / PAPER.linear_accel
    print(f'a straight 9 m from rest to rest at these limits: {straight:.2f} s')
    if options.plot:
        plot(drawn, options.plot)
    if options.through_ros:
        through_ros(limits, options.through_ros)


def through_ros(limits: dict[str, float], time_scale: float) -> None:
    """Ours (tube planning) on every case through ROS, the simulator with inertia and the node
    as two programs at `time_scale`, beside the limit and the reference."""
    print(f'\nThrough ROS, two programs at x{time_scale:g} (the node\'s figures):')
    print(f'{"path":26} {"tol mm":>6} {"time s":>7} {"err mm":>7} {"/limit":>7} {"ref s":>6}')
    import rclpy

    rclpy.init()
    try:
        runs = drive_through_ros([(name, points, heading, tolerance)
                                  for name, points, heading, tolerance, _ in CASES],
                                 DWPP_LIMITS, time_scale, separate=True)
    finally:
        rclpy.shutdown()
    for name, _, _, tolerance, reference in CASES:
        ended, max_m, elapsed, _, message = runs[name]
        shown = '' if ended else f'  (did not end: {message})'
        print(f'{name:26} {tolerance * 1e3:6.0f} {elapsed:7.2f} {max_m * 1e3:7.1f} '
              f'{elapsed / limits[name]:7.3f} {_shown(reference)}{shown}')


if __name__ == '__main__':
    main()
