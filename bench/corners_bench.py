"""Exact corners in scaled real time on a base with inertia, side by side with an older commit.

    .venv/bin/python bench/corners_bench.py [--against c1af86f] [--runs 5] [--time-scale 5]
        [--load none|quarter|busy] [--tolerance M]

The setting of a new user's: our simulator with inertia (0.5 m/s², 1 rad/s²) at `--time-scale`
and the trajectory node (0.5 m/s, 1 rad/s, told the same limits) as two programs, the node on
the simulator's /clock. This process is the client: per run it starts both programs, and sends
`follow_path` along the DWPP paper's step paths (three 3 m legs turning 45, 90 and 135 degrees)
and one period of a sine (1 m over 6 m), each from its first point facing its first leg.
`--tolerance` rounds corners by up to that much (0: exact). Each path's maximum distance from
the path is measured here, from every /turtle1/pose of the run, and set beside the node's own.

The trees run alternately, run by run, each from its own `src/` (the old one in a temporary git
worktree) with this venv and this script. `--load quarter` keeps a quarter of a core busy
beside each run (2.5 ms of work every 10 ms), `busy` a whole one.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from isolation import isolate
from worktree import ROOT, old_tree

LIMITS = {'max_linear_accel': 0.5, 'max_angular_accel': 1.0}
NODE = {'linear_speed': 0.5, 'angular_speed': 1.0, 'use_sim_time': True, 'arena_min_x': -100.0,
        'arena_min_y': -100.0, 'arena_max_x': 100.0, 'arena_max_y': 100.0}
LOADS = {'none': None,
         'quarter': ('import time\nwhile True:\n    end = time.perf_counter() + 0.0025\n'
                     '    while time.perf_counter() < end: pass\n    time.sleep(0.0075)\n'),
         'busy': 'while True: pass\n'}
WORSE_MM = 5.0  # an exact corner further off than this is a miss


def paths() -> dict[str, np.ndarray]:
    def step(degrees: float) -> np.ndarray:
        turn = math.radians(degrees)
        points = [(1.0, 1.5), (4.0, 1.5)]
        points.append((points[-1][0] + 3.0 * math.cos(turn), points[-1][1] + 3.0 * math.sin(turn)))
        points.append((points[-1][0] + 3.0, points[-1][1]))
        return np.array(points)

    x = np.linspace(0.0, 6.0, 601)
    return {'step45': step(45), 'step90': step(90), 'step135': step(135),
            'sine': np.stack([2.0 + x, 5.0 + np.sin(2.0 * math.pi * x / 6.0)], axis=1)}


def distance_to_path(points: np.ndarray, path: np.ndarray) -> np.ndarray:
    starts, along = path[:-1], np.diff(path, axis=0)
    offset = points[:, None, :] - starts[None]
    t = np.clip((offset * along[None]).sum(axis=2) / (along ** 2).sum(axis=1), 0.0, 1.0)
    return np.sqrt(((offset - t[..., None] * along[None]) ** 2).sum(axis=2)).min(axis=1)


def _arguments(values: dict) -> list[str]:
    return [word for name, value in values.items() for word in ('-p', f'{name}:={value}')]


def measure(time_scale: float, tolerance: float) -> dict[str, dict]:
    """One run of every path, through this interpreter's turtle_traj: per path, whether it
    ended well, the maximum distance measured here and the node's, in mm, and the time."""
    import rclpy
    from geometry_msgs.msg import Point
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from turtle_traj_interfaces.srv import FollowPath
    from turtlesim.msg import Pose
    from turtlesim.srv import TeleportAbsolute

    programs = [
        subprocess.Popen([sys.executable, '-m', 'turtle_traj.sim', '--time-scale',
                          str(time_scale), '--ros-args', *_arguments(LIMITS)],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL),
        subprocess.Popen([sys.executable, '-m', 'turtle_traj', '--ros-args',
                          *_arguments({**NODE, **LIMITS})],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    rclpy.init()
    client = Node('corners_bench')
    executor = SingleThreadedExecutor()
    executor.add_node(client)
    poses: list[tuple[float, float]] | None = None

    def on_pose(message: Pose) -> None:
        if poses is not None:
            poses.append((message.x, message.y))

    def call(service, request, timeout_s: float):
        future = service.call_async(request)
        executor.spin_until_future_complete(future, timeout_sec=timeout_s)
        return future.result()

    results = {}
    try:
        client.create_subscription(Pose, '/turtle1/pose', on_pose, 1000)
        teleport = client.create_client(TeleportAbsolute, '/turtle1/teleport_absolute')
        follow = client.create_client(FollowPath, '/turtle_traj/follow_path')
        if not (follow.wait_for_service(timeout_sec=60.0)
                and teleport.wait_for_service(timeout_sec=60.0)):
            raise SystemExit('the node or the simulator did not come up within 60 s')
        for name, path in paths().items():
            heading = math.atan2(path[1, 1] - path[0, 1], path[1, 0] - path[0, 0])
            place = TeleportAbsolute.Request(x=float(path[0, 0]), y=float(path[0, 1]),
                                             theta=heading)
            while call(teleport, place, 5.0) is None:  # sent again until answered
                pass
            settle = time.monotonic() + 0.1 + 0.5 / time_scale  # a pose from where it stands
            while time.monotonic() < settle:
                executor.spin_once(timeout_sec=0.01)
            poses = []
            response = call(follow, FollowPath.Request(
                points=[Point(x=float(x), y=float(y)) for x, y in path],
                corner_tolerance=tolerance), 300.0)
            measured, poses = np.array(poses), None
            if response is None:
                raise SystemExit(f'{name}: no answer within 300 s')
            results[name] = {
                'ended': bool(response.success), 'message': response.message,
                'measured_mm': 1e3 * float(distance_to_path(measured, path).max()),
                'node_mm': 1e3 * response.max_deviation, 'time_s': response.elapsed}
    finally:
        executor.shutdown()
        client.destroy_node()
        rclpy.shutdown()
        for program in programs:
            program.terminate()
        for program in programs:
            program.wait(timeout=30)
    return results


def _run(tree: Path, options: argparse.Namespace) -> dict[str, dict]:
    env = {**os.environ, 'PYTHONPATH': os.pathsep.join([str(tree / 'src'),
                                                        str(Path(__file__).parent)])}
    load = LOADS[options.load]
    loader = (subprocess.Popen([sys.executable, '-c', load]) if load else None)
    try:
        done = subprocess.run([sys.executable, __file__, '--measure', '--time-scale',
                               str(options.time_scale), '--tolerance', str(options.tolerance)],
                              env=env, capture_output=True, text=True, timeout=900, cwd=tree)
    finally:
        if loader is not None:
            loader.kill()
            loader.wait()
    if done.returncode != 0:
        raise RuntimeError(f'a run in {tree} failed:\n{done.stderr[-3000:]}')
    return json.loads(done.stdout.strip().splitlines()[-1])


def _report(label: str, runs: list[dict[str, dict]], tolerance: float) -> None:
    print(f'  {label}')
    for name in paths():
        figures = [run[name] for run in runs]
        measured = [figure['measured_mm'] for figure in figures]
        failed = [figure['message'] for figure in figures if not figure['ended']]
        misses = sum(value > WORSE_MM for value in measured) if not tolerance else 0
        print(f'    {name:8} max mm: median {statistics.median(measured):6.2f}, worst '
              f'{max(measured):6.2f}; node/measured agree within 0.1 mm in '
              f'{sum(abs(f["node_mm"] - f["measured_mm"]) <= 0.1 for f in figures)} of '
              f'{len(figures)}; time s median '
              f'{statistics.median(f["time_s"] for f in figures):6.2f}'
              + (f'; past {WORSE_MM:g} mm in {misses}' if not tolerance else ''))
        print(f'             every run: {" ".join(f"{value:.1f}" for value in measured)}')
        for message in failed:
            print(f'             did not end: {message}')


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--against', default='c1af86f', help='the old commit (default c1af86f)')
    parser.add_argument('--runs', type=int, default=5, help='runs of every path per tree')
    parser.add_argument('--time-scale', type=float, default=5.0)
    parser.add_argument('--load', choices=sorted(LOADS), default='none')
    parser.add_argument('--tolerance', type=float, default=0.0,
                        help='corner_tolerance, m (0: exact)')
    parser.add_argument('--measure', action='store_true', help=argparse.SUPPRESS)
    options = parser.parse_args()
    isolate('corners')
    if options.measure:
        print(json.dumps(measure(options.time_scale, options.tolerance)))
        return
    results: dict[str, list] = {'old': [], 'new': []}
    with old_tree(options.against) as old:
        for _ in range(options.runs):
            results['old'].append(_run(old, options))
            results['new'].append(_run(ROOT, options))
    mode = (f'rounded by up to {options.tolerance * 1e3:g} mm' if options.tolerance
            else 'exact')
    print(f'follow_path {mode}, x{options.time_scale:g}, simulator with inertia and node as '
          f'two programs, load: {options.load}; {options.runs} runs per tree, alternating; '
          'distances measured from every pose')
    _report(f'{options.against} (old)', results['old'], options.tolerance)
    _report('this checkout (new)', results['new'], options.tolerance)


if __name__ == '__main__':
    main()
