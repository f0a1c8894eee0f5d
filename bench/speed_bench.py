"""Lock-step speed and the node program's CPU, this checkout side by side with an older commit.

Run: .venv/bin/python bench/speed_bench.py [--against REV] [--rounds N] [--skip-demo]
     .venv/bin/python bench/speed_bench.py --step-cost [--against REV] [--rounds N]

REV (default 9873574, the commit before lock-step moved to the EventsExecutor) is checked out
in a temporary git worktree; every figure is measured in a fresh process for each tree in turn
(old, new, old, new, ...), with that tree's `src` first on PYTHONPATH and this venv's ROS and
interface packages, and the medians are printed with their ratio.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from isolation import isolate

ROOT = Path(__file__).resolve().parents[1]
SIM_SECONDS = 8.0  # simulated time per real-time-factor figure


# -- measurements, each run in a process of its own (`--measure NAME`) -----------------------

def _lockstep_system(turtles: int):
    """Simulator, client and one trajectory node per turtle, each driving a circle forever."""
    import rclpy
    from rclpy.parameter import Parameter
    from turtle_traj_interfaces.srv import DrawShape
    from turtlesim.srv import Spawn

    from turtle_traj.apps.in_process import SIM_TIME, InProcessSystem
    from turtle_traj.node.trajectory_node import TrajectoryNode

    rclpy.init()
    system = InProcessSystem(output_dir=Path(tempfile.mkdtemp()))
    nodes = [system.node]
    for index in range(1, turtles):
        x, y = 1.5 + (index % 5) * 2.0, 1.5 + (index // 5) * 2.0  # up to 25, circles apart
        name = system.call(Spawn, '/spawn', Spawn.Request(x=x, y=y, name=f'turtle{index + 1}'))
        node = TrajectoryNode(f'turtle_traj{index + 1}', parameter_overrides=[
            SIM_TIME, Parameter('turtle_name', value=name.name)])
        system.add_node(node)
        nodes.append(node)
    if not system.spin_until(lambda: all(node.ready for node in nodes), timeout_s=10.0):
        raise RuntimeError('the trajectory nodes did not get ready')
    for node in nodes:
        system.start(DrawShape, f'/{node.get_name()}/draw_circle',
                     DrawShape.Request(size=0.5, forever=True))
    if not system.spin_until(lambda: all(node.busy for node in nodes), timeout_s=5.0):
        raise RuntimeError('the circles did not start')
    system.spin_sim_seconds(1.0)  # every node under way
    return system


def measure_real_time_factor(turtles: int) -> dict:
    system = _lockstep_system(turtles)
    start_wall, start_sim = time.perf_counter(), system.sim_time_s
    system.spin_sim_seconds(SIM_SECONDS)
    wall = time.perf_counter() - start_wall
    return {'factor': (system.sim_time_s - start_sim) / wall}


# our callbacks, as measure_breakdown labels them
OUR_CALLBACKS = ('sim_step', 'sim_command', 'node_pose', 'node_tick')


def measure_breakdown(turtles: int = 1) -> dict:
    """Per 16 ms step, `turtles` driving: executor passes, messages, where the time goes (in
    each of our callbacks: the simulator's step and command, the node's pose delivery and
    control tick; the step and the tick include the publishing they do)."""
    from rclpy.publisher import Publisher

    from turtle_traj.node.base_topics import BaseTopics
    from turtle_traj.node.control_timer import ControlTimer
    from turtle_traj.sim.node import SimNode

    spent = dict.fromkeys(OUR_CALLBACKS, 0.0)
    published = [0]

    def timed(function, name):
        def wrapper(*args, **kwargs):
            start = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                spent[name] += time.perf_counter() - start
        return wrapper

    for (cls, name), label in zip(((SimNode, 'step'), (SimNode, 'on_cmd_vel'),
                                   (BaseTopics, '_delivered'), (ControlTimer, '_tick')),
                                  OUR_CALLBACKS, strict=True):
        setattr(cls, name, timed(getattr(cls, name), label))
    publish = Publisher.publish

    def counting_publish(self, msg):
        published[0] += 1
        return publish(self, msg)
    Publisher.publish = counting_publish

    system = _lockstep_system(turtles)
    executor = system.executor
    passes = [0]
    spin_once = executor.spin_once

    def counting_spin_once(*args, **kwargs):
        passes[0] += 1
        return spin_once(*args, **kwargs)
    executor.spin_once = counting_spin_once
    spent.update(dict.fromkeys(spent, 0.0))
    published[0] = 0
    steps, start = executor.steps, time.perf_counter()
    system.spin_sim_seconds(SIM_SECONDS)
    wall, steps = time.perf_counter() - start, executor.steps - steps
    return {'passes': passes[0] / steps, 'messages': published[0] / steps,
            'step_ms': 1e3 * wall / steps, 'ours_ms': 1e3 * sum(spent.values()) / steps,
            **{f'{name}_ms': 1e3 * value / steps for name, value in spent.items()}}


STEP_COST_TURTLES = (1, 5, 10, 20)


def measure_floor(turtles: int) -> dict:
    """The same lock-step step with the traffic alone (traffic_floor.lockstep_floor_ms)."""
    import rclpy

    from traffic_floor import lockstep_floor_ms

    rclpy.init()
    try:
        return {'floor_ms': lockstep_floor_ms(turtles)}
    finally:
        rclpy.try_shutdown()


def print_step_cost(rounds: int) -> None:
    """What a lock-step step costs this checkout with 1 to 20 turtles, each drawing a circle
    with its own trajectory node, and where it goes (median of `rounds` fresh processes);
    beside it, the floor: the same step with the traffic alone (a stand-in simulator and a
    driver node per turtle that does nothing but take its pose and send a command)."""
    print('per 16 ms lock-step step, this checkout (ms; median of fresh processes):')
    print(f'{"turtles":>7} {"step":>7} {"per turtle":>10} {"rclpy+DDS":>9} {"ours":>7} '
          + ' '.join(f'{name:>11}' for name in OUR_CALLBACKS) + f' {"x real":>7}'
          + f' {"floor":>7} {"x real":>7}')
    for turtles in STEP_COST_TURTLES:
        runs = []
        for _ in range(rounds):  # alternating, so that a busy spell falls on both
            runs.append({**_run(ROOT, f'breakdown{turtles}'), **_run(ROOT, f'floor{turtles}')})
        figures = {key: statistics.median(run[key] for run in runs) for key in runs[0]}
        rest = figures['step_ms'] - figures['ours_ms']
        print(f'{turtles:7d} {figures["step_ms"]:7.3f} {figures["step_ms"] / turtles:10.3f} '
              f'{rest:9.3f} {figures["ours_ms"]:7.3f} '
              + ' '.join(f'{figures[f"{name}_ms"]:11.3f}' for name in OUR_CALLBACKS)
              + f' {16.0 / figures["step_ms"]:7.2f} {figures["floor_ms"]:7.3f}'
              f' {16.0 / figures["floor_ms"]:7.2f}', flush=True)


def print_step_cost_against(old: Path, rev: str, rounds: int, turtles: int = 20) -> None:
    """The step with `turtles` turtles, `rev` and this checkout in turn in fresh processes
    (old, new, old, ...): each pair's figures and ratio, then the medians. A pair runs within
    seconds, so a busy spell of the machine falls on both of it."""
    print(f'per 16 ms lock-step step with {turtles} turtles, {rev} (old) against this checkout '
          f'(new), {rounds} pairs:')
    keys = ('step_ms', 'node_tick_ms', 'node_pose_ms', 'sim_step_ms')
    pairs = []
    for _ in range(rounds):
        pairs.append((_run(old, f'breakdown{turtles}'), _run(ROOT, f'breakdown{turtles}')))
        before, after = pairs[-1]
        print('  ' + '  '.join(f'{key[:-3]} {before[key]:.3f} -> {after[key]:.3f}'
                               for key in keys)
              + f'  ratio {after["step_ms"] / before["step_ms"]:.3f}', flush=True)
    ratios = [after['step_ms'] / before['step_ms'] for before, after in pairs]
    medians = {side: statistics.median(pair[index]['step_ms'] for pair in pairs)
               for index, side in enumerate(('old', 'new'))}
    print(f'  median step: old {medians["old"]:.3f} ms ({16.0 / medians["old"]:.2f}x real '
          f'time), new {medians["new"]:.3f} ms ({16.0 / medians["new"]:.2f}x); median ratio '
          f'{statistics.median(ratios):.3f} (pairs {min(ratios):.3f} to {max(ratios):.3f})')


def measure_node_cpu(seconds: float) -> dict:
    """`python -m turtle_traj` at real time beside our simulator program: idle, then driving."""
    from process_cpu import cpu_share as _share
    from process_cpu import process_cpu_s as _cpu_s
    from process_cpu import wait_until_connected
    from turtle_traj.api.ros_interface import make_goal
    from turtle_traj.client.traj_client import TrajClient
    from turtle_traj.core.registry import BY_NAME

    quiet = {'stdout': subprocess.DEVNULL, 'stderr': subprocess.DEVNULL}
    sim = subprocess.Popen([sys.executable, '-m', 'turtle_traj.sim'], **quiet)
    node = subprocess.Popen([sys.executable, '-m', 'turtle_traj'], **quiet)
    try:
        with TrajClient(connect_timeout_s=30.0) as client:
            wait_until_connected(client)
        time.sleep(1.0)
        idle = _share(node.pid, seconds)
        client_cpu = {}
        with TrajClient(connect_timeout_s=30.0) as client:
            goal = make_goal(BY_NAME['circle'], {'size': 1.5, 'forever': True})
            started = time.monotonic()
            me = os.getpid()
            mine = _cpu_s(me)

            def on_feedback(_feedback) -> None:
                if 'driving' not in client_cpu and time.monotonic() - started > 1.0:
                    client_cpu['driving'] = _share(node.pid, seconds)
            client.draw(goal, on_feedback=on_feedback, timeout_s=seconds + 3.0)
            client_cpu['client'] = (_cpu_s(me) - mine) / (time.monotonic() - started)
        return {'idle': idle, 'driving': client_cpu['driving'], 'client': client_cpu['client'],
                **_traffic_floor(seconds)}
    finally:
        for process in (node, sim):
            process.terminate()
            process.wait(timeout=15)


def _traffic_floor(seconds: float) -> dict:
    """The same traffic with no work (bench/traffic_floor.py) beside our simulator, which is
    running: a node that only subscribes to the pose (idle) and one that also publishes cmd_vel
    every 16 ms (driving). Ours cannot cost less."""
    from process_cpu import cpu_share as _share

    floor = {}
    for role, key in (('listener', 'idle_floor'), ('driver', 'driving_floor')):
        stand_in = subprocess.Popen([sys.executable, str(Path(__file__).parent /
                                                         'traffic_floor.py'), role],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            time.sleep(3.0)  # discovered and matched
            floor[key] = _share(stand_in.pid, seconds)
        finally:
            stand_in.terminate()
            stand_in.wait(timeout=15)
    return floor


def measure_demo() -> dict:
    with tempfile.TemporaryDirectory() as folder:
        start = time.perf_counter()
        subprocess.run([sys.executable, '-m', 'turtle_traj.apps.demo', '--output-dir', folder],
                       check=True, capture_output=True)
        return {'wall_s': time.perf_counter() - start}


MEASURES = {
    'rtf1': lambda: measure_real_time_factor(1),
    'rtf2': lambda: measure_real_time_factor(2),
    'rtf10': lambda: measure_real_time_factor(10),
    'breakdown': measure_breakdown,
    **{f'breakdown{count}': (lambda count=count: measure_breakdown(count))
       for count in STEP_COST_TURTLES},
    **{f'floor{count}': (lambda count=count: measure_floor(count)) for count in STEP_COST_TURTLES},
    'cpu': lambda: measure_node_cpu(20.0),
    'demo': measure_demo,
}


# -- the side-by-side driver -------------------------------------------------------------------

def _run(tree: Path, measure: str) -> dict:
    env = {**os.environ, 'PYTHONPATH': os.pathsep.join([str(tree / 'src'), str(Path(__file__)
                                                                                .parent)])}
    done = subprocess.run([sys.executable, __file__, '--measure', measure], env=env,
                          capture_output=True, text=True, timeout=900, cwd=tree)
    if done.returncode != 0:
        raise RuntimeError(f'{measure} in {tree} failed:\n{done.stderr[-3000:]}')
    return json.loads(done.stdout.strip().splitlines()[-1])


def _worktree(rev: str) -> Path:
    folder = Path(tempfile.mkdtemp(prefix='turtle_traj_bench_')) / 'old'
    subprocess.run(['git', '-C', str(ROOT), 'worktree', 'add', '--detach', str(folder), rev],
                   check=True, capture_output=True)
    return folder


def _side_by_side(old: Path, measure: str, rounds: int) -> tuple[dict, dict]:
    results: dict[str, list[dict]] = {'old': [], 'new': []}
    for _ in range(rounds):
        results['old'].append(_run(old, measure))
        results['new'].append(_run(ROOT, measure))
    return tuple({key: statistics.median(r[key] for r in results[side])
                  for key in results[side][0]} for side in ('old', 'new'))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--against', help='the old commit (default 9873574; with '
                        '--step-cost, the step with 20 turtles against it, pair by pair)')
    parser.add_argument('--rounds', type=int, default=3, help='runs of each figure per tree')
    parser.add_argument('--skip-demo', action='store_true', help='leave out make demo')
    parser.add_argument('--step-cost', action='store_true',
                        help='only the step cost of this checkout with 1, 5, 10 and 20 turtles')
    parser.add_argument('--measure', choices=sorted(MEASURES), help=argparse.SUPPRESS)
    options = parser.parse_args()
    isolate('speed')
    if options.measure:
        print(json.dumps(MEASURES[options.measure]()))
        return
    if options.step_cost and options.against is None:
        print_step_cost(options.rounds)
        return
    options.against = options.against or '9873574'
    old = _worktree(options.against)
    try:
        if options.step_cost:
            print_step_cost_against(old, options.against, options.rounds)
            return
        print(f'turtle_traj speed benchmark: {options.against} (old) against this checkout '
              f'(new), median of {options.rounds} runs each, alternating')
        for turtles in (1, 2, 10):
            before, after = _side_by_side(old, f'rtf{turtles}', options.rounds)
            print(f'  lock-step real-time factor, {turtles:2d} turtle(s), each with its own '
                  f'trajectory node drawing a circle: old {before["factor"]:6.1f}x, '
                  f'new {after["factor"]:6.1f}x ({after["factor"] / before["factor"]:.2f}x)')
        before, after = _side_by_side(old, 'breakdown', options.rounds)
        print('  per 16 ms step, one turtle driving:')
        for key, label in (('step_ms', 'wall time, ms'), ('ours_ms', 'in our callbacks, ms'),
                           ('passes', 'executor passes'), ('messages', 'messages published')):
            print(f'    {label:24s} old {before[key]:7.3f}   new {after[key]:7.3f}')
        for side, figures in (('old', before), ('new', after)):
            rclpy_ms = figures['step_ms'] - figures['ours_ms']
            print(f'    {side}: {rclpy_ms:.3f} ms of each step in rclpy and the middleware, '
                  f'{figures["ours_ms"]:.3f} ms in our callbacks')
        before, after = _side_by_side(old, 'cpu', options.rounds)
        print('  CPU of the trajectory node program at real time, beside our simulator program '
              '(20 s windows; share of one core):')
        for key, label in (('idle', 'idle'), ('driving', 'driving a circle'),
                           ('client', "the client's own process while it waits on the goal"),
                           ('idle_floor', 'its traffic alone, idle (pose subscribed)'),
                           ('driving_floor', 'its traffic alone, driving (cmd_vel each 16 ms)')):
            print(f'    {label:54s} old {100 * before[key]:5.1f}%   new {100 * after[key]:5.1f}%')
        if not options.skip_demo:
            before, after = _side_by_side(old, 'demo', 1)
            print(f'  make demo (python -m turtle_traj.apps.demo) wall time: old '
                  f'{before["wall_s"]:.1f} s, new {after["wall_s"]:.1f} s '
                  f'({before["wall_s"] / after["wall_s"]:.1f}x faster)')
    finally:
        subprocess.run(['git', '-C', str(ROOT), 'worktree', 'remove', '--force', str(old)],
                       capture_output=True)


if __name__ == '__main__':
    sys.path.insert(0, str(Path(__file__).parent))
    main()
