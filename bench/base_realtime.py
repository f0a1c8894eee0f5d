"""Part 3 of `base_bench.py`: the step curves and the sine through ROS, in (scaled) real time.

`python -m turtle_traj --with-sim --time-scale S` runs our simulator with inertia and the node
at the DWPP paper's limits in one process (paced lock-step: the simulator steps once the node
has answered, S times real time); with `separate`, they are two programs, the simulator on its
own timer and the node on its /clock, as with a robot elsewhere. This process is the client.
Each path starts with the turtle teleported to its first point, facing its first leg, and runs
with DWPP (a node started with `controller:=dwpp`), then exact, then rounded at DWPP's maximum
error on that path in the pure loop: DWPP goes through the same ROS, the same clocks and the
same planning as ours. The node's own figures are read from its response. With
BENCH_PROGRAM_LOGS set, the programs' logs go to this one's output.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
import time
from collections.abc import Callable
from functools import partial

import numpy as np

from base_loop import Limits

# Paths and DWPP's figures on them: name -> (points, DWPP's maximum error in m, DWPP's time)
Courses = dict[str, tuple[np.ndarray, float, float]]


def _programs(limits: Limits, time_scale: float, separate: bool,
              controller: str) -> list[subprocess.Popen]:
    # the simulator's inertia, which the node is told too (unscoped: both nodes read it)
    inertia = [f'max_linear_accel:={limits.a}', f'max_angular_accel:={limits.alpha}']
    node = [f'turtle_traj:linear_speed:={limits.v}', f'turtle_traj:angular_speed:={limits.omega}',
            f'turtle_traj:controller:={controller}',
            *(f'turtle_traj:arena_{side}:={value}' for side, value in (
                ('min_x', -100.0), ('min_y', -100.0), ('max_x', 100.0), ('max_y', 100.0)))]
    scale = ['--time-scale', str(time_scale)]
    if separate:
        argvs = [['turtle_traj.sim', *scale, '--ros-args', *_parameters(inertia)],
                 ['turtle_traj', '--ros-args',
                  *_parameters(['use_sim_time:=true', *inertia, *node])]]
    else:
        argvs = [['turtle_traj', '--with-sim', *scale, '--ros-args',
                  *_parameters(inertia + node)]]
    logs = None if os.environ.get('BENCH_PROGRAM_LOGS') else subprocess.DEVNULL
    return [subprocess.Popen([sys.executable, '-m', *argv], stdout=logs, stderr=logs)
            for argv in argvs]


def _parameters(values: list[str]) -> list[str]:
    return [word for value in values for word in ('-p', value)]


# a run through ROS: (ended, max deviation m, elapsed s, final error m, message)
Run = tuple[bool, float, float, float, str]


def through_ros_in_real_time(courses: Courses, limits: Limits, time_scale: float,
                             separate: bool = False) -> bool:
    """Every course with DWPP (`controller:=dwpp`), then exact and rounded, each through ROS
    in the same setting; True when every run ends and rounded is no slower than DWPP there at
    no more than DWPP's maximum error in the pure loop."""
    how = ('the simulator and the node as two programs' if separate else
           f'`python -m turtle_traj --with-sim --time-scale {time_scale:g}`, paced lock-step')
    print(f'Part 3: through ROS in real time x{time_scale:g} ({how}), simulator with inertia, '
          "the paper's limits; DWPP as the node's controller, in the same setting\n")
    import rclpy

    rclpy.init()
    try:
        dwpp = _drive(courses, limits, time_scale, separate, 'dwpp', [('dwpp', False)])
        ours = _drive(courses, limits, time_scale, separate, 'exact',
                      [('exact', False), ('rounded', True)])
    finally:
        rclpy.shutdown()
    print(f"{'path':8} {'mode':10} {'max mm':>7} {'time s':>7} {'DWPP s':>7} {'end mm':>7}  "
          'verdict')
    passed = True
    for name, (_, dwpp_max_m, dwpp_pure_s) in courses.items():
        dwpp_s = dwpp[name, 'dwpp'][2]
        for mode, run in (('dwpp', dwpp[name, 'dwpp']), ('exact', ours[name, 'exact']),
                          ('rounded', ours[name, 'rounded'])):
            ended, max_m, elapsed, end_m, message = run
            misses = [] if ended else [f'did not end: {message}']
            if mode == 'rounded':
                misses += ['slower than DWPP'] * (elapsed > dwpp_s)
                misses += ["max > DWPP's"] * (max_m > dwpp_max_m)
            passed &= not misses
            shown = f'{dwpp_pure_s:7.2f}' if mode == 'dwpp' else f'{dwpp_s:7.2f}'
            print(f'{name:8} {mode:10} {max_m * 1e3:7.1f} {elapsed:7.2f} {shown} '
                  f"{end_m * 1e3:7.1f}  {'ok' if not misses else 'MISSED: ' + ', '.join(misses)}",
                  flush=True)
    print("(DWPP s: on DWPP's rows its time in the pure loop; on ours, DWPP's through ROS)\n")
    return passed


def _drive(courses: Courses, limits: Limits, time_scale: float, separate: bool,
           controller: str, modes: list[tuple[str, bool]]) -> dict:
    """Each course in each mode (named, and whether its corners are rounded at DWPP's maximum
    error) through a node of `controller`, from facing its first leg: {(course, mode): Run}."""
    wanted = [((name, mode), points, None, dwpp_max_m if rounded else 0.0)
              for name, (points, dwpp_max_m, _) in courses.items() for mode, rounded in modes]
    return drive_through_ros(wanted, limits, time_scale, separate, controller)


# a run asked for: (its key, the points, the heading it starts facing (None: along the first
# leg), the corner tolerance in m)
Wanted = tuple[object, np.ndarray, float | None, float]


def drive_through_ros(wanted: list[Wanted], limits: Limits, time_scale: float,
                      separate: bool, controller: str = 'exact') -> dict:
    """Each run `wanted`, follow_path from the turtle teleported to its first point, through
    a node of `controller` and our simulator with inertia: {key: Run}, the node's figures."""
    from geometry_msgs.msg import Point
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from turtle_traj_interfaces.srv import FollowPath
    from turtlesim.srv import TeleportAbsolute

    from turtle_traj.client.answers import first_answer

    programs = _programs(limits, time_scale, separate, controller)
    client = Node('base_bench_client')
    executor = SingleThreadedExecutor()
    executor.add_node(client)
    runs: dict = {}
    try:
        teleport = client.create_client(TeleportAbsolute, '/turtle1/teleport_absolute')
        follow = client.create_client(FollowPath, '/turtle_traj/follow_path')
        if not (follow.wait_for_service(timeout_sec=60.0)
                and teleport.wait_for_service(timeout_sec=60.0)):
            raise SystemExit('the node or the simulator did not come up within 60 s')
        call = _caller(executor)
        for key, points, heading, tolerance in wanted:
            if heading is None:
                heading = math.atan2(points[1, 1] - points[0, 1], points[1, 0] - points[0, 0])
            place = TeleportAbsolute.Request(x=float(points[0, 0]), y=float(points[0, 1]),
                                             theta=float(heading))
            # sent again while unanswered: a first request can race the service's discovery
            first_answer(executor, partial(teleport.call_async, place), 'teleport')
            time.sleep(0.1 + 0.5 / time_scale)  # a pose from where it now stands
            request = FollowPath.Request(
                points=[Point(x=float(x), y=float(y)) for x, y in points],
                corner_tolerance=float(tolerance))
            response = call(follow, request)
            runs[key] = (response.success, response.max_deviation, response.elapsed,
                         response.final_error, response.message)
    finally:
        executor.shutdown()
        client.destroy_node()
        for program in programs:
            program.terminate()
            program.wait(timeout=30)
    return runs


def _caller(executor) -> Callable:
    def call(service, request, timeout_s: float = 600.0):
        future = service.call_async(request)
        executor.spin_until_future_complete(future, timeout_sec=timeout_s)
        if future.result() is None:
            raise SystemExit(f'{service.srv_name}: no answer within {timeout_s:g} s')
        return future.result()
    return call


if __name__ == '__main__':  # pragma: no cover - run through base_bench.py
    sys.exit('run bench/base_bench.py --real-time 1 --real-time 5')
