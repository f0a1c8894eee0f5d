"""Soak: 500 back-to-back trajectories with random valid parameters, simulator in its own process.

Prints successes, failures with reasons, resident memory of both processes at runs 1, 50, 250
and 500, and the service-call overhead (request sent -> first velocity command seen), p50/p99.
Run: .venv/bin/python bench/soak_bench.py [--runs N] [--time-scale F]
"""

from __future__ import annotations

import argparse
import math
import os
import random
import statistics
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import rclpy
from geometry_msgs.msg import Twist
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from turtlesim.srv import TeleportAbsolute

from isolation import isolate
from turtle_traj.api.ros_interface import make_request, service_type
from turtle_traj.core.registry import TRAJECTORIES
from turtle_traj.core.turtlesim_contract import SPAWN_XY_M
from turtle_traj.node.trajectory_node import TrajectoryNode
from turtle_traj.rosutils import runtime
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS

CHECKPOINTS = (1, 50, 250, 500)


def rss_mb(pid: int) -> float:
    for line in Path(f'/proc/{pid}/status').read_text().splitlines():
        if line.startswith('VmRSS:'):
            return int(line.split()[1]) / 1024.0
    return math.nan


def _polygon(rng: random.Random) -> dict:
    return {'sides': rng.randint(3, 9), 'size': rng.uniform(0.3, 1.5),
            'clockwise': rng.random() < 0.5}


# Per trajectory of the registry: random values, as entered, that fit from the arena's centre.
RANDOM_GIVEN = {
    'square': _polygon, 'triangle': _polygon, 'hexagon': _polygon, 'polygon': _polygon,
    'circle': lambda rng: {'size': rng.uniform(0.3, 1.5), 'turns': rng.uniform(0.3, 1.5),
                           'clockwise': rng.random() < 0.5},
    'spiral': lambda rng: {'size': rng.uniform(0.2, 0.5), 'growth': rng.uniform(0.2, 0.6),
                           'turns': rng.uniform(0.5, 2.0)},
    'sine': lambda rng: {'size': rng.uniform(0.1, 1.0), 'frequency': rng.uniform(0.2, 1.0),
                         'length': rng.uniform(0.5, 4.0)},
    'star': lambda rng: {'size': rng.uniform(0.3, 1.5), 'tips': rng.randint(3, 8)},
    'heart': lambda rng: {'size': rng.uniform(0.5, 3.0)},
    'lemniscate': lambda rng: {'size': rng.uniform(0.5, 3.0)},
    'rose': lambda rng: {'size': rng.uniform(0.5, 3.0), 'petals': rng.choice([1, 3, 4, 5, 8])},
    'lissajous': lambda rng: {'size': rng.uniform(0.5, 2.5), 'a': rng.randint(1, 4),
                              'b': rng.randint(1, 4), 'phase': rng.uniform(-180.0, 180.0)},
    'text': lambda rng: {'text': rng.choice(['ROS', 'Hi!', 'turtle', '42']),
                         'height': rng.uniform(0.2, 0.6)},
    'svg': lambda rng: {'file': rng.choice(['turtle.svg', 'wave.svg']),
                        'size': rng.uniform(0.5, 3.0), 'pen_color': rng.choice(['', 'red'])},
    'go_to': lambda rng: {'x': rng.uniform(2.0, 9.0), 'y': rng.uniform(2.0, 9.0),
                          'theta': rng.choice([None, rng.uniform(-180.0, 180.0)])},
    'move': lambda rng: {'distance': rng.choice([-1, 1]) * rng.uniform(0.2, 3.0)},
    'rotate': lambda rng: {'angle': rng.uniform(-400.0, 400.0)},
    'follow_path': lambda rng: {
        'points': [(rng.uniform(3.0, 8.0), rng.uniform(3.0, 8.0))
                   for _ in range(rng.randint(1, 5))], 'closed': rng.random() < 0.5},
}


def random_request(rng: random.Random):
    """A random trajectory of the registry with a random, valid request."""
    trajectory = rng.choice(TRAJECTORIES)
    given = RANDOM_GIVEN[trajectory.name](rng)
    speed = rng.choice([0.0, rng.uniform(0.5, 3.0)])
    if any(item.name == 'linear_speed' for item in trajectory.fields):
        given['linear_speed'] = speed
    return trajectory, make_request(trajectory, given)


class SoakClient(Node):
    """Calls the node and notes when the first velocity command of each run appears."""

    def __init__(self) -> None:
        super().__init__('soak_client')
        self.first_command_s: float | None = None
        self.create_subscription(Twist, 'turtle1/cmd_vel', self._on_cmd_vel, TURTLE_TOPIC_QOS)
        self._service_clients = {}

    def _on_cmd_vel(self, msg: Twist) -> None:
        if self.first_command_s is None and (msg.linear.x or msg.angular.z):
            self.first_command_s = time.monotonic()

    def client(self, service_type, name: str):
        if name not in self._service_clients:
            self._service_clients[name] = self.create_client(service_type, name)
        return self._service_clients[name]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--runs', type=int, default=500)
    parser.add_argument('--time-scale', type=float, default=20.0)
    parser.add_argument('--seed', type=int, default=7)
    options = parser.parse_args()
    rng = random.Random(options.seed)
    isolate('soak')

    sim = subprocess.Popen([sys.executable, '-m', 'turtle_traj.sim', '--time-scale',
                            str(options.time_scale), '--output-dir', tempfile.mkdtemp()],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        return soak(options, rng, sim)
    finally:
        sim.terminate()
        sim.wait(timeout=10)


def soak(options: argparse.Namespace, rng: random.Random, sim: subprocess.Popen) -> int:
    rclpy.init()
    node = TrajectoryNode(parameter_overrides=[Parameter('use_sim_time', value=True)])
    client = SoakClient()
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    executor.add_node(client)

    def spin_until(condition, timeout_s: float) -> bool:
        return runtime.spin_until(executor, condition, timeout_s=timeout_s)

    def call(service_type, name, request, timeout_s=120.0):
        service = client.client(service_type, name)
        if not spin_until(service.service_is_ready, 10.0):
            raise RuntimeError(f'no service {name}')
        future = service.call_async(request)
        if not spin_until(future.done, timeout_s):
            raise RuntimeError(f'{name} did not answer in {timeout_s:g} s')
        return future.result()

    outcomes: Counter[str] = Counter()
    failures: list[str] = []
    overheads_ms: list[float] = []
    memory: list[tuple[int, float, float]] = []
    start = time.monotonic()
    try:
        if not spin_until(lambda: node.ready, 20.0):
            print('the simulator did not come up', file=sys.stderr)
            return 1
        for run in range(1, options.runs + 1):
            call(TeleportAbsolute, '/turtle1/teleport_absolute', TeleportAbsolute.Request(
                x=SPAWN_XY_M, y=SPAWN_XY_M, theta=rng.uniform(-math.pi, math.pi)))
            spin_until(lambda: node.ready and math.dist(
                (node.pose.x, node.pose.y), (SPAWN_XY_M, SPAWN_XY_M)) < 1e-3, 5.0)
            trajectory, request = random_request(rng)
            client.first_command_s = None
            sent = time.monotonic()
            response = call(service_type(trajectory), f'/turtle_traj/{trajectory.service}',
                            request)
            if response.success:
                outcomes['succeeded'] += 1
                if client.first_command_s is not None:
                    overheads_ms.append((client.first_command_s - sent) * 1e3)
            elif 'refused' in response.message and 'arena' in response.message:
                outcomes['refused: would leave the arena (intended)'] += 1
            else:
                outcomes['failed'] += 1
                failures.append(f'run {run} {trajectory.name}: {response.message}')
            if run in CHECKPOINTS or run == options.runs:
                memory.append((run, rss_mb(os.getpid()), rss_mb(sim.pid)))
    finally:
        executor.shutdown()
        node.destroy_node()
        client.destroy_node()
        rclpy.try_shutdown()

    print(f'soak: {options.runs} trajectories in {time.monotonic() - start:.0f} s wall '
          f'(simulator at {options.time_scale:g}x in its own process)')
    for outcome, count in sorted(outcomes.items()):
        print(f'  {outcome}: {count}')
    for failure in failures[:20]:
        print(f'  {failure}')
    print('  resident memory (MB):  run   node+client   simulator')
    for run, node_mb, sim_mb in memory:
        print(f'                        {run:4d}   {node_mb:11.1f}   {sim_mb:9.1f}')
    by_run = {run: (node_mb, sim_mb) for run, node_mb, sim_mb in memory}
    if 50 in by_run and options.runs in by_run:
        print(f'  growth run 50 -> {options.runs}: node+client '
              f'{by_run[options.runs][0] - by_run[50][0]:+.1f} MB, simulator '
              f'{by_run[options.runs][1] - by_run[50][1]:+.1f} MB')
    if overheads_ms:
        quantiles = statistics.quantiles(overheads_ms, n=100, method='inclusive')
        print(f'  call overhead (request -> first velocity command): p50 '
              f'{statistics.median(overheads_ms):.1f} ms, p99 {quantiles[98]:.1f} ms, '
              f'max {max(overheads_ms):.1f} ms')
    return 0 if not failures else 1


if __name__ == '__main__':
    sys.exit(main())
