"""Simulator benchmark: real-time factor, CPU at real time, cost per update for N turtles, and
the pen's lateral scans against the real turtlesim's (tests/data/turtlesim-pen-scan.json).

Run: .venv/bin/python bench/sim_bench.py   (or `make bench`)
"""

from __future__ import annotations

import json
import math
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import Parameter
from turtle_traj_interfaces.srv import DrawShape

from isolation import isolate
from process_cpu import cpu_share, wait_until_connected
from turtle_traj.api.ros_interface import make_goal
from turtle_traj.apps.in_process import InProcessSystem
from turtle_traj.client.traj_client import TrajClient
from turtle_traj.core.registry import BY_NAME
from turtle_traj.core.turtlesim_contract import STEP_S, WORLD_SIZE_M
from turtle_traj.sim.canvas import Canvas
from turtle_traj.sim.node import SimNode
from turtle_traj.sim.physics import World

SCAN_FILE = Path(__file__).resolve().parents[1] / 'tests' / 'data' / 'turtlesim-pen-scan.json'
REAL_TURTLESIM_CPU = {'idle': 0.027, 'driven': 0.057}  # issue 25, C++ turtlesim 1.8.2 here


def _spin_for(executor: SingleThreadedExecutor, seconds: float) -> None:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        executor.spin_once(timeout_sec=0.05)


def real_time_factor(time_scale: float, seconds: float = 4.0) -> float:
    node = SimNode(parameter_overrides=[Parameter('time_scale', value=time_scale),
                                        Parameter('publish_clock', value=True)])
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    try:
        start_wall, start_sim = time.monotonic(), node.world.time_s
        _spin_for(executor, seconds)
        return (node.world.time_s - start_sim) / (time.monotonic() - start_wall)
    finally:
        executor.shutdown()
        node.destroy_node()


def lockstep_real_time_factor() -> float:
    """Simulator, trajectory node and client in one lock-step process, drawing a square."""
    system = InProcessSystem(output_dir=Path(tempfile.mkdtemp()))
    try:
        start_wall, start_sim = time.monotonic(), system.sim_time_s
        response = system.call(DrawShape, 'draw_square', DrawShape.Request(size=2.0))
        if not response.success:
            raise RuntimeError(response.message)
        return (system.sim_time_s - start_sim) / (time.monotonic() - start_wall)
    finally:
        system.close()


def simulator_program_cpu(seconds: float = 10.0) -> tuple[float, float]:
    """Share of one core used by `python -m turtle_traj.sim` with one turtle at real time:
    idle (nothing connected), then while our trajectory node (its own process) drives a
    circle through it."""
    quiet = {'stdout': subprocess.DEVNULL, 'stderr': subprocess.DEVNULL}
    sim = subprocess.Popen([sys.executable, '-m', 'turtle_traj.sim'], **quiet)
    node = None
    try:
        time.sleep(3.0)  # started, discovered, settled
        idle = cpu_share(sim.pid, seconds)
        node = subprocess.Popen([sys.executable, '-m', 'turtle_traj'], **quiet)
        with TrajClient(connect_timeout_s=20.0) as client:
            wait_until_connected(client)
            driving, shares = threading.Event(), []

            def measure() -> None:
                driving.wait(timeout=30.0)
                time.sleep(1.0)
                shares.append(cpu_share(sim.pid, seconds))
            threading.Thread(target=measure, daemon=True).start()
            goal = make_goal(BY_NAME['circle'], {'size': 1.5, 'forever': True})
            client.draw(goal, on_feedback=lambda _feedback: driving.set(),
                        timeout_s=seconds + 3.0)  # then cancelled
        return idle, shares[0]
    finally:
        for process in (node, sim):
            if process is not None:
                process.terminate()
                process.wait(timeout=15)


def _program_cpu_driven(program: list[str], seconds: float = 10.0) -> tuple[float, float]:
    """Share of one core used by `program` idle, then while the traffic driver runs."""
    quiet = {'stdout': subprocess.DEVNULL, 'stderr': subprocess.DEVNULL}
    floor = str(Path(__file__).with_name('traffic_floor.py'))
    sim = subprocess.Popen([sys.executable, *program], **quiet)
    driver = None
    try:
        time.sleep(3.0)
        idle = cpu_share(sim.pid, seconds)
        driver = subprocess.Popen([sys.executable, floor, 'driver'], **quiet)
        time.sleep(3.0)  # discovered and matched
        return idle, cpu_share(sim.pid, seconds)
    finally:
        for process in (driver, sim):
            if process is not None:
                process.terminate()
                process.wait(timeout=15)


def traffic_floor() -> dict[str, tuple[float, float]]:
    """Our simulator and a stand-in with turtlesim's traffic only, under the same driver."""
    floor = str(Path(__file__).with_name('traffic_floor.py'))
    return {'our simulator': _program_cpu_driven(['-m', 'turtle_traj.sim']),
            'traffic-only stand-in': _program_cpu_driven([floor, 'stand-in'])}


def update_cost_ms(turtles: int, updates: int = 300) -> tuple[float, float]:
    """Median and worst wall time of one update (physics, drawing, publishing)."""
    node = SimNode(lockstep=True)  # no timer: we call the update ourselves
    try:
        for index in range(turtles - 1):
            node.spawn_turtle('', 1.0 + (index % 10) * 0.9, 1.0 + (index // 10) * 0.9, 0.0)
        for turtle in node.world:
            node.world.command(turtle.name, 0.5, 0.0, 0.3)
        costs = []
        for step in range(updates):
            if step % 50 == 0:
                for turtle in node.world:
                    node.world.command(turtle.name, 0.5, 0.0, 0.3)
            start = time.perf_counter()
            node.step()
            costs.append((time.perf_counter() - start) * 1e3)
        return statistics.median(costs), max(costs)
    finally:
        node.destroy_node()


def lateral_scan(width: int, heading: float) -> str:
    """Our colour sensor read across a red line, as the scan file says the real turtlesim was
    read, on the pure core (tests/test_pen_scan.py does it over ROS)."""
    world, canvas = World(), Canvas()
    turtle = world.spawn(3.0, 3.0, heading)
    world.set_pen(turtle.name, 255, 0, 0, width, off=0)
    world.command(turtle.name, 1.0, 0.0, 0.0)
    for _ in range(70):  # it moves for 63 steps
        for segment in world.step().segments:
            canvas.draw(segment)
    world.set_pen(turtle.name, 0, 0, 0, 0, off=1)
    pixel_m, read = WORLD_SIZE_M / 500, ''
    middle_x, middle_y = 3.0 + 0.504 * math.cos(heading), 3.0 + 0.504 * math.sin(heading)
    for offset in range(-4, 5):  # positive: to the left of the heading
        world.teleport_absolute(turtle.name, middle_x - offset * pixel_m * math.sin(heading),
                                middle_y + offset * pixel_m * math.cos(heading), heading)
        world.step()
        read += 'P' if canvas.color_under(turtle) == (255, 0, 0) else '.'
    return read


def print_scan_table() -> None:
    recorded = json.loads(SCAN_FILE.read_text())['scan']
    agree = 0
    print('  pen lateral scans, -4..+4 px across the line (P: the pen colour):')
    print('    scan                       real turtlesim   ours')
    for name, real in recorded.items():
        width, heading = (float(part.split()[1]) for part in name.split(', '))
        ours = lateral_scan(int(width), heading)
        agree += ours == real
        print(f'    {name:26s} {real}        {ours}   {"same" if ours == real else "DIFFERS"}')
    print(f'    {agree} of {len(recorded)} agree')


def main() -> None:
    isolate('sim')
    rclpy.init()
    try:
        print('turtle_traj simulator benchmark (SingleThreadedExecutor, one process)')
        for scale in (100.0, 1000.0):
            print(f'  real-time factor, time_scale={scale:g}: {real_time_factor(scale):7.1f}x')
        print(f'  real-time factor, lock-step simulator + trajectory node + client drawing a '
              f'square: {lockstep_real_time_factor():7.1f}x')
        real = REAL_TURTLESIM_CPU
        for run in range(1, 4):
            idle, driven = simulator_program_cpu()
            print(f'  CPU of `python -m turtle_traj.sim`, one turtle, real time, run {run}: '
                  f'idle {100 * idle:4.1f}% of one core, while our node drives a circle '
                  f'{100 * driven:4.1f}% (the real turtlesim: {100 * real["idle"]:.1f}% idle)')
        for run in range(1, 3):
            for program, (idle, driven) in traffic_floor().items():
                print(f'  CPU under the traffic driver (pose subscribed, cmd_vel every 16 ms), '
                      f'run {run}: {program:21s} idle {100 * idle:4.1f}%, '
                      f'driven {100 * driven:4.1f}% (target: at most the real turtlesim\'s '
                      f'{100 * real["idle"]:.1f}% and {100 * real["driven"]:.1f}%)')
        budget_ms = STEP_S * 1e3
        for turtles in (1, 10, 100):
            median, worst = update_cost_ms(turtles)
            verdict = 'holds 62.5 Hz' if median < budget_ms else 'cannot hold 62.5 Hz'
            print(f'  update with {turtles:3d} turtles: median {median:6.3f} ms, '
                  f'worst {worst:6.3f} ms (budget {budget_ms:.0f} ms): {verdict}')
        print_scan_table()
    finally:
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()
