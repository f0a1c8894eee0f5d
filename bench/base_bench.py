"""turtle_traj on a base with acceleration limits, side by side with Dynamic Window Pure Pursuit.

    .venv/bin/python bench/base_bench.py [--skip-ros] [--real-time SCALE ...]

Part 1, the pure loop (no ROS, simulated time): the DWPP paper's base (0.5 m/s, 1 rad/s,
0.5 m/s², 1 rad/s², 16 ms steps) on step curves of three 3 m legs whose middle leg turns by
30 to 150 degrees, and one period of a sine of amplitude 1 m over 6 m. Contestants: DWPP (the
shipped controller, `controller:=dwpp`), turtle_traj exact (corner_tolerance 0) and rounded at a
tolerance equal to DWPP's maximum error on that path. Errors are distances from the path as
drawn, measured here at every pose; "outside" counts commands the base cannot take within one
step of the one before; "bound" is the time-optimal stop-and-turn time (for the sine, the
time-optimal profile along the exact curve), computed here at the full limits.

Part 2, through ROS on our simulator with inertia (lock-step): every trajectory kind of the
registry at the node's default speeds, with the node's turtlesim Pose and Twist, then again on
Odometry and TwistStamped through `BaseAdapter`.

Part 3 (`--real-time 1 --real-time 5`), through ROS in (scaled) real time: the 45, 90 and 135
degree steps and the sine, exact and rounded at DWPP's maximum error (`base_realtime.py`); the
simulator in the node's program (paced lock-step), or with `--separate` as a program of its own.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence

import numpy as np

from base_loop import DWPP_LIMITS, Limits, base_settings, drive_turtle_traj
from base_realtime import Courses, through_ros_in_real_time
from isolation import isolate
from turtle_traj.core.control.profile import FULL_LIMITS, SpeedProfile
from turtle_traj.core.geometry.path import Polyline, Pose2D

STEP_ANGLES_DEG = (30, 45, 60, 90, 120, 135, 150)
LEG_M = 3.0


def step_curve(degrees: float) -> np.ndarray:
    turn = math.radians(degrees)
    points = [(1.0, 1.5), (1.0 + LEG_M, 1.5)]
    points.append((points[-1][0] + LEG_M * math.cos(turn), points[-1][1] + LEG_M * math.sin(turn)))
    points.append((points[-1][0] + LEG_M, points[-1][1]))
    return np.array(points)


def sine() -> np.ndarray:
    x = np.linspace(0.0, 6.0, 601)
    return np.stack([2.0 + x, 5.0 + np.sin(2.0 * math.pi * x / 6.0)], axis=1)


def _trapezoid_s(distance: float, top: float, accel: float) -> float:
    if distance * accel < top * top:
        return 2.0 * math.sqrt(distance / accel)
    return distance / top + top / accel


def stop_and_turn_bound(points: np.ndarray, limits: Limits) -> float:
    """Rest-to-rest legs and turns in place, each at its time-optimal trapezoid."""
    legs = np.diff(points, axis=0)
    headings = np.arctan2(legs[:, 1], legs[:, 0])
    turns = np.abs(np.angle(np.exp(1j * np.diff(headings))))
    return (sum(_trapezoid_s(float(length), limits.v, limits.a)
                for length in np.hypot(legs[:, 0], legs[:, 1]))
            + sum(_trapezoid_s(float(turn), limits.omega, limits.alpha) for turn in turns))


def curve_bound(points: np.ndarray, limits: Limits) -> float:
    """The time-optimal profile along the exact curve at the full limits (TOPP-RA)."""
    return SpeedProfile.plan(Polyline(points), base_settings(limits).control.limits,
                             shares=FULL_LIMITS).duration_s


def run_dwpp(points: np.ndarray, start: Pose2D, limits: Limits) -> dict:
    return drive_turtle_traj(points, start, limits, controller='dwpp').figures(
        points, limits, tuple(points[-1]))


REAL_TIME_COURSES = ('step45', 'step90', 'step135', 'sine')


def pure_loop(limits: Limits, courses: Courses) -> bool:
    """Part 1; True when every target holds. DWPP's figures on the real-time courses go into
    `courses`."""
    print('Part 1: the pure loop, the DWPP paper\'s base '
          f'(v {limits.v} m/s, omega {limits.omega} rad/s, a {limits.a} m/s², '
          f'alpha {limits.alpha} rad/s², 16 ms steps)\n')
    header = (f"{'path':8} {'contestant':22} {'rmse mm':>8} {'max mm':>8} {'time s':>7} "
              f"{'bound s':>7} {'ratio':>6} {'outside':>8} {'end mm':>7}  verdict")
    print(header)
    print('-' * len(header))
    passed = True
    paths = [(f'step{angle}', step_curve(angle)) for angle in STEP_ANGLES_DEG]
    paths.append(('sine', sine()))
    for name, points in paths:
        heading = math.atan2(points[1, 1] - points[0, 1], points[1, 0] - points[0, 0])
        start = Pose2D(float(points[0, 0]), float(points[0, 1]), heading)
        bound = (curve_bound(points, limits) if name == 'sine'
                 else stop_and_turn_bound(points, limits))
        dwpp = run_dwpp(points, start, limits)
        exact = drive_turtle_traj(points, start, limits).figures(points, limits,
                                                                  tuple(points[-1]))
        tolerance = dwpp['max_mm'] / 1000.0
        if name in REAL_TIME_COURSES:
            courses[name] = (points, tolerance, dwpp['time_s'])
        rounded = drive_turtle_traj(points, start, limits, corner_tolerance=tolerance).figures(
            points, limits, tuple(points[-1]))
        checks = {
            'dwpp': [],
            'exact': [('ends at the goal', exact['success'] and exact['end_mm'] <= 10.0),
                      ('max <= 5 mm', exact['max_mm'] <= 5.0),
                      ('time <= 1.10 bound', exact['time_s'] <= 1.10 * bound),
                      ('0% outside', exact['outside_pct'] == 0.0)],
            'rounded': [('ends at the goal', rounded['success'] and rounded['end_mm'] <= 10.0),
                        ("max <= DWPP's", rounded['max_mm'] <= dwpp['max_mm']),
                        ("time <= DWPP's", rounded['time_s'] <= dwpp['time_s']),
                        ('0% outside', rounded['outside_pct'] == 0.0)],
        }
        for label, key, figures in (('DWPP (shipped)', 'dwpp', dwpp),
                                    ('turtle_traj exact', 'exact', exact),
                                    (f'turtle_traj {tolerance * 1000:.0f} mm', 'rounded',
                                     rounded)):
            failed = [what for what, ok in checks[key] if not ok]
            passed &= not failed
            verdict = '' if key == 'dwpp' else ('ok' if not failed else
                                                'MISSED: ' + ', '.join(failed))
            print(f"{name:8} {label:22} {figures['rmse_mm']:8.2f} {figures['max_mm']:8.2f} "
                  f"{figures['time_s']:7.2f} {bound:7.2f} {figures['time_s'] / bound:6.3f} "
                  f"{figures['outside_pct']:7.2f}% {figures['end_mm']:7.2f}  {verdict}")
        print()
    return passed


def through_ros(*, odometry: bool) -> bool:
    """Part 2: every registry kind on our simulator with inertia; True when all succeed."""
    import rclpy

    from turtle_traj.apps.demo import run_example
    from turtle_traj.apps.in_process import InProcessSystem
    from turtle_traj.core.registry import TRAJECTORIES

    inertia = {'max_linear_accel': 0.5, 'max_angular_accel': 1.0}
    topics = (dict(base_adapter=True, pose_source='odometry', odom_topic='odom',
                   cmd_vel_type='TwistStamped', cmd_vel_topic='cmd_vel') if odometry else {})
    wires = 'Odometry and TwistStamped via BaseAdapter' if odometry else 'Pose and Twist'
    print("Part 2: through ROS on our simulator with inertia (0.5 m/s², 1.0 rad/s²), the "
          f"node's default speeds, {wires}\n")
    print(f"{'trajectory':12} {'ok':>3} {'max dev mm':>11} {'final mm':>9} {'elapsed s':>10}"
          "  message")
    rclpy.init()
    system = InProcessSystem(sim_parameters=inertia, **topics, **inertia)
    passed = True
    try:
        for kind in TRAJECTORIES:
            response = run_example(system, kind)
            # the end-to-end tests' limits: 5 mm, the spiral's radius 10 mm
            limit = 0.010 if kind.name == 'spiral' else 0.005
            passed &= response.success and response.max_deviation <= limit
            print(f'{kind.name:12} {"yes" if response.success else "NO":>3} '
                  f'{response.max_deviation * 1e3:11.2f} {response.final_error * 1e3:9.2f} '
                  f'{response.elapsed:10.2f}  {response.message}')
    finally:
        system.close()
        rclpy.shutdown()
    print()
    return passed


def main(args: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog='python -m bench.base_bench', description=__doc__)
    parser.add_argument('--skip-ros', action='store_true', help='the pure loop only')
    parser.add_argument('--real-time', type=float, action='append', default=[],
                        metavar='SCALE', help='part 3 at this time scale (repeatable)')
    parser.add_argument('--separate', action='store_true',
                        help='part 3 with the simulator and the node as two programs')
    options = parser.parse_args(args)
    isolate('base')
    courses: Courses = {}
    passed = pure_loop(DWPP_LIMITS, courses)
    if not options.skip_ros:
        passed &= through_ros(odometry=False)
        passed &= through_ros(odometry=True)
    for scale in options.real_time:
        passed &= through_ros_in_real_time(courses, DWPP_LIMITS, scale, options.separate)
    print('every target met' if passed else 'some targets missed (see above)')
    return 0 if passed else 1


if __name__ == '__main__':
    sys.exit(main())
