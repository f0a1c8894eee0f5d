"""The physics base with a command delay, driven by odometry: does the model of the robot
compensate on a base that reports nav_msgs/Odometry (no turtlesim echo)?

The MuJoCo base (a TurtleBot3 Burger) applies each TwistStamped `command_delay` later; the
trajectory node drives it by `odom`. A 1 m square and a 0.5 m circle, with no delay and with
48 ms, in lock-step (simulated time, figures that repeat) and in real time (the base on its own
wall-clock timer, the node and this client in one executor, as `turtle-traj up --base` runs
them). Deviation is measured here, against independent geometry (the square's corners and the
circle's centre from where the run started), on the odometry the node saw and on the base's
ground truth; the time is the node's `elapsed`, and its ratio to the same run with no delay.

Run: .venv/bin/python bench/odometry_bench.py [--delay 0.048] [--rounds 3] [--skip-real-time]
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

from turtle_traj.testing.geometry import distance_to_polyline, regular_polygon

SQUARE_M, RADIUS_M = 1.0, 0.5
RUNS = (('square 1 m', 'draw_square', SQUARE_M), ('circle r 0.5 m', 'draw_circle', RADIUS_M))


def deviation_m(kind: str, samples: np.ndarray, size: float) -> float:
    """Largest distance of (x, y, yaw) samples from the shape the run started at samples[0]."""
    x, y, yaw = samples[0]
    points = samples[:, :2]
    if kind == 'draw_square':
        return float(distance_to_polyline(points, regular_polygon(
            x, y, yaw, 4, size, False)).max())
    centre = np.array([x - size * math.sin(yaw), y + size * math.cos(yaw)])  # to the left
    return float(np.abs(np.linalg.norm(points - centre, axis=1) - size).max())


def lock_step(delay_s: float) -> list[tuple[str, float, float, float, bool]]:
    """(run, elapsed, odometry max, truth max, success) for each run, in simulated time."""
    import rclpy
    from turtle_traj_interfaces.srv import DrawShape

    from turtle_traj.apps.base_system import BaseSystem
    context = rclpy.Context()
    rclpy.init(context=context)
    system = BaseSystem(context=context, output_dir=Path(tempfile.mkdtemp()),
                        base_parameters={'command_delay': delay_s})
    rows = []
    try:
        for name, service, size in RUNS:
            response = system.call(DrawShape, service, DrawShape.Request(size=size))
            odometry = np.array([sample[1:] for sample in system.odometry])
            truth = np.array([sample[1:] for sample in system.truth])
            rows.append((name, response.elapsed, deviation_m(service, odometry, size),
                         deviation_m(service, truth, size), response.success))
    finally:
        system.close()
        rclpy.shutdown(context=context)
    return rows


def real_time(delay_s: float) -> list[tuple[str, float, float, float, bool]]:
    """The same runs on the wall clock: base, node and a recording client in one executor."""
    import rclpy
    from nav_msgs.msg import Odometry
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.parameter import Parameter
    from turtle_traj_interfaces.srv import DrawShape

    from turtle_traj.apps.base_system import base_node_parameters
    from turtle_traj.base.node import BaseNode
    from turtle_traj.node.trajectory_node import TrajectoryNode

    context = rclpy.Context()
    rclpy.init(context=context)
    base = BaseNode(context=context, parameter_overrides=[
        Parameter('command_delay', value=delay_s)])
    node = TrajectoryNode(context=context, parameter_overrides=[
        Parameter(name, value=value) for name, value in base_node_parameters(base).items()])
    client = Node('odometry_bench', context=context)
    seen: dict[str, list[tuple[float, float, float]]] = {'odom': [], 'ground_truth': []}

    def recorder(topic: str):
        def record(msg: Odometry) -> None:
            q = msg.pose.pose.orientation
            seen[topic].append((msg.pose.pose.position.x, msg.pose.pose.position.y,
                                2.0 * math.atan2(q.z, q.w)))
        return record
    for topic in seen:
        client.create_subscription(Odometry, topic, recorder(topic), 50)
    executor = SingleThreadedExecutor(context=context)
    for each in (base, node, client):
        executor.add_node(each)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    rows = []
    try:
        time.sleep(1.0)  # odometry flowing, the node has its first pose
        for name, service, size in RUNS:
            caller = client.create_client(DrawShape, f'/turtle_traj/{service}')
            if not caller.wait_for_service(timeout_sec=30.0):
                raise SystemExit(f'{service}: no service within 30 s')
            for samples in seen.values():
                samples.clear()
            future = caller.call_async(DrawShape.Request(size=size))
            while not future.done():
                time.sleep(0.01)
            response = future.result()
            odometry, truth = np.array(seen['odom']), np.array(seen['ground_truth'])
            rows.append((name, response.elapsed, deviation_m(service, odometry, size),
                         deviation_m(service, truth, size), response.success))
            time.sleep(0.5)  # standing before the next run
    finally:
        executor.shutdown()
        for each in (client, node, base):
            each.destroy_node()
        rclpy.shutdown(context=context)
        spinner.join(timeout=5.0)
    return rows


def table(title: str, delay_s: float, runs: list[list[tuple]], ratio_to: dict[str, float],
          ) -> bool:
    """Print one table (a row per run and round); True when every round meets the targets:
    odometry within 5 mm, truth within 15 mm, time at most 1.10x the run without delay."""
    print(f'{title}, command delay {delay_s * 1e3:.0f} ms')
    print(f"  {'run':16} {'round':>5} {'time s':>7} {'x no delay':>10} {'odom mm':>8} "
          f"{'truth mm':>8}  verdict")
    passed = True
    for round_number, rows in enumerate(runs, 1):
        for name, elapsed, odom_m, truth_m, success in rows:
            ratio = elapsed / ratio_to[name] if name in ratio_to else float('nan')
            misses = ([] if success else ['did not end']) + ['odom > 5 mm'] * (odom_m > 0.005) \
                + ['truth > 15 mm'] * (truth_m > 0.015) + ['> 1.10x'] * (ratio > 1.10)
            passed &= not misses
            print(f'  {name:16} {round_number:5d} {elapsed:7.3f} {ratio:10.3f} '
                  f"{odom_m * 1e3:8.2f} {truth_m * 1e3:8.2f}  "
                  f"{'ok' if not misses else 'MISSED: ' + ', '.join(misses)}", flush=True)
    print()
    return passed


def median_times(runs: list[list[tuple]]) -> dict[str, float]:
    return {name: float(np.median([rows[i][1] for rows in runs]))
            for i, (name, *_rest) in enumerate(runs[0])}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--delay', type=float, default=0.048, help='seconds (default 0.048)')
    parser.add_argument('--rounds', type=int, default=3, help='real-time rounds (default 3)')
    parser.add_argument('--skip-real-time', action='store_true')
    options = parser.parse_args()
    passed = True
    undelayed = lock_step(0.0)
    base_times = median_times([undelayed])
    passed &= table('Lock-step', 0.0, [undelayed], base_times)
    passed &= table('Lock-step', options.delay, [lock_step(options.delay)], base_times)
    if not options.skip_real_time:
        rounds_0 = [real_time(0.0) for _ in range(options.rounds)]
        real_base = median_times(rounds_0)
        passed &= table('Real time', 0.0, rounds_0, real_base)
        passed &= table('Real time', options.delay,
                        [real_time(options.delay) for _ in range(options.rounds)], real_base)
    print('all targets met' if passed else 'TARGETS MISSED')
    return 0 if passed else 1


if __name__ == '__main__':
    sys.exit(main())
