"""Part 3 of `base_bench.py`: the step curves and the sine through ROS, in (scaled) real time.

`python -m turtle_traj --with-sim --time-scale S` runs our simulator with inertia and the node
at the DWPP paper's limits in one process (paced lock-step: the simulator steps once the node
has answered, S times real time); with `separate`, they are two programs, the simulator on its
own timer and the node on its /clock, as with a robot elsewhere. This process is the client.
Each path starts with the turtle teleported to its first point, facing its first leg, and runs
exact, then rounded at DWPP's maximum error on that path (DWPP from the pure loop: the same
robot, the same 16 ms steps). The node's own figures are read from its response.
"""

from __future__ import annotations

import math
import subprocess
import sys
import time
from collections.abc import Callable

import numpy as np

from base_loop import Limits

# Paths and DWPP's figures on them: name -> (points, DWPP's maximum error in m, DWPP's time)
Courses = dict[str, tuple[np.ndarray, float, float]]


def _programs(limits: Limits, time_scale: float, separate: bool) -> list[subprocess.Popen]:
    # the simulator's inertia, which the node is told too (unscoped: both nodes read it)
    inertia = [f'max_linear_accel:={limits.a}', f'max_angular_accel:={limits.alpha}']
    node = [f'turtle_traj:linear_speed:={limits.v}', f'turtle_traj:angular_speed:={limits.omega}',
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
    return [subprocess.Popen([sys.executable, '-m', *argv], stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL) for argv in argvs]


def _parameters(values: list[str]) -> list[str]:
    return [word for value in values for word in ('-p', value)]


def through_ros_in_real_time(courses: Courses, limits: Limits, time_scale: float,
                             separate: bool = False) -> bool:
    """Every course exact and rounded; True when every run ends and rounded is no slower than
    DWPP at no more than its maximum error."""
    import rclpy
    from geometry_msgs.msg import Point
    from rclpy.node import Node
    from turtle_traj_interfaces.srv import FollowPath
    from turtlesim.srv import TeleportAbsolute

    how = ('the simulator and the node as two programs' if separate else
           f'`python -m turtle_traj --with-sim --time-scale {time_scale:g}`, paced lock-step')
    print(f'Part 3: through ROS in real time x{time_scale:g} ({how}), simulator with inertia, '
          'the paper\'s limits\n')
    print(f"{'path':8} {'mode':10} {'max mm':>7} {'time s':>7} {'DWPP s':>7} {'end mm':>7}  "
          'verdict')
    programs = _programs(limits, time_scale, separate)
    rclpy.init()
    client = Node('base_bench_client')
    passed = True
    try:
        teleport = client.create_client(TeleportAbsolute, '/turtle1/teleport_absolute')
        follow = client.create_client(FollowPath, '/turtle_traj/follow_path')
        if not follow.wait_for_service(timeout_sec=60.0):
            raise SystemExit('the node did not come up within 60 s')
        call = _caller(client)
        for name, (points, dwpp_max_m, dwpp_s) in courses.items():
            heading = math.atan2(points[1, 1] - points[0, 1], points[1, 0] - points[0, 0])
            for mode, tolerance in (('exact', 0.0), ('rounded', dwpp_max_m)):
                call(teleport, TeleportAbsolute.Request(
                    x=float(points[0, 0]), y=float(points[0, 1]), theta=heading))
                time.sleep(0.1 + 0.5 / time_scale)  # a pose from where it now stands
                response = call(follow, FollowPath.Request(
                    points=[Point(x=float(x), y=float(y)) for x, y in points],
                    corner_tolerance=tolerance))
                misses = [] if response.success else [f'did not end: {response.message}']
                if mode == 'rounded':
                    misses += ["slower than DWPP"] * (response.elapsed > dwpp_s)
                    misses += ["max > DWPP's"] * (response.max_deviation > dwpp_max_m)
                passed &= not misses
                print(f'{name:8} {mode:10} {response.max_deviation * 1e3:7.1f} '
                      f'{response.elapsed:7.2f} {dwpp_s:7.2f} {response.final_error * 1e3:7.1f}'
                      f"  {'ok' if not misses else 'MISSED: ' + ', '.join(misses)}", flush=True)
    finally:
        client.destroy_node()
        rclpy.shutdown()
        for program in programs:
            program.terminate()
            program.wait(timeout=30)
    print()
    return passed


def _caller(client) -> Callable:
    import rclpy

    def call(service, request, timeout_s: float = 600.0):
        future = service.call_async(request)
        rclpy.spin_until_future_complete(client, future, timeout_sec=timeout_s)
        if future.result() is None:
            raise SystemExit(f'{service.srv_name}: no answer within {timeout_s:g} s')
        return future.result()
    return call


if __name__ == '__main__':  # pragma: no cover - run through base_bench.py
    sys.exit('run bench/base_bench.py --real-time 1 --real-time 5')
