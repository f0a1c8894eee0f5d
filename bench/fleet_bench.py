"""Several turtles drawing one request, against one turtle drawing it alone, in lock-step.

    .venv/bin/python bench/fleet_bench.py [--turtles 1,3,10,20] [--planning] [--faults]
        [--step-cost] [--picture docs/fleet.png]

For the text "ROS 2" (1 m, from turtlesim's spawn point), the demo's SVG and the demo's star
(the registry's examples, from their start poses), one turtle draws the request with its own
Draw action, then the other sizes of `--turtles` draw it through the fleet coordinator:
turtle1 where the one turtle started, the others where `up --turtles N` puts them (rings of 3
and 4.5 m round the spawn point).
Every figure but the planned ones is measured here from what the simulator did:
  answer      simulated time from sending the goal to its answer, what a user waits for, and
              its ratio to the one turtle's;
  makespan    the result's own figure (one turtle: its elapsed time);
  bound       the lower bound of the sharing (the longest piece, or all of it shared evenly);
  closest     the least distance between two turtles' centres, from their poses, step by step;
  deviation   the largest of the turtles' own figures (distance from the pieces they drew);
  ink         the pixels inked by one but not the other, against the one turtle's inked pixels.
"""

from __future__ import annotations

import argparse
import itertools
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / 'src'))

from turtle_traj.api.ros_interface import make_fleet_goal, make_goal  # noqa: E402
from turtle_traj.apps.in_process import InProcessFleet, LockstepSim  # noqa: E402
from turtle_traj.apps.sim import starting_places  # noqa: E402
from turtle_traj.core.registry import BY_NAME  # noqa: E402
from turtle_traj.testing.domain import claim_domain_id  # noqa: E402

DRAWINGS = {  # name: (trajectory, values as entered, start pose)
    'ROS 2': ('text', {'text': 'ROS 2', 'height': 1.0}, starting_places(1)[0]),
    'svg': ('svg', BY_NAME['svg'].example.given, BY_NAME['svg'].example.start),
    'star': ('star', BY_NAME['star'].example.given, BY_NAME['star'].example.start),
}


def _finish(system: LockstepSim, client, goal) -> tuple:
    """The goal's result, and the simulated time from sending it to its answer."""
    asked_s = system.sim_time_s
    sent = client.send_goal_async(goal)
    if not system.spin_until(sent.done, timeout_s=30.0):
        raise RuntimeError('the goal was not answered')
    answer = sent.result().get_result_async()
    if not system.spin_until(answer.done, timeout_s=900.0):
        raise RuntimeError('the goal did not end')
    return answer.result().result, system.sim_time_s - asked_s


def _closest(poses: dict) -> float:
    count = min(len(log) for log in poses.values())
    tracks = [np.array([(p.x, p.y) for p in log[:count]]) for log in poses.values()]
    return min((float(np.hypot(*(a - b).T).min())
                for a, b in itertools.combinations(tracks, 2)), default=float('inf'))


def lose_one(fault: str, at_s: float, output: Path, single: np.ndarray) -> str:
    """'ROS 2' by three turtles, turtle2 lost `at_s` into it (its turtle killed with /kill, or
    its node destroyed): a line of figures."""
    from turtle_traj_interfaces.action import FleetDraw
    trajectory, given, start = DRAWINGS['ROS 2']
    system = InProcessFleet([start, *starting_places(3)[1:]], output_dir=output)
    try:
        for log in system.poses.values():
            log.clear()
        client = system.action_client(FleetDraw, '/fleet/draw')
        sent = client.send_goal_async(make_fleet_goal(BY_NAME[trajectory], given, system.names))
        system.spin_until(sent.done, timeout_s=30.0)
        answer = sent.result().get_result_async()
        started = system.sim_time_s
        system.spin_until(lambda: system.sim_time_s > started + at_s)
        system.lose('turtle2', fault)
        system.spin_until(answer.done, timeout_s=900.0)
        result = answer.result().result
        ink = system.sim.canvas.trails[..., 3] > 0
        differ = 100.0 * np.count_nonzero(ink ^ single) / np.count_nonzero(single)
        return (f'{fault:5} at {at_s:4.1f} s: {"drawn" if result.success else "FAILED"}, '
                f'makespan {result.makespan:.2f} s, pieces {list(result.pieces)}, ink '
                f'{differ:.2f}%, closest {_closest(system.poses):.3f} m, deviation '
                f'{max(result.max_deviation) * 1000:.2f} mm; {result.lost[1]}')
    finally:
        system.close()


def _planned(name: str, count: int):
    """The coordinator's FleetRun for `name` among `count` turtles where the bench puts them:
    the drawing planned, cut into pieces, shared out and timed apart."""
    from turtle_traj.api.ros_interface import make_request
    from turtle_traj.core.fleet.pieces import pieces_in
    from turtle_traj.core.fleet.run import FleetRun
    from turtle_traj.core.geometry.path import Pose2D
    from turtle_traj.core.parameters.settings import DEFAULT_SETTINGS
    from turtle_traj.core.planning.planner import plan
    trajectory, given, start = DRAWINGS[name]
    starts = [Pose2D(*start), *(Pose2D(*place) for place in starting_places(count)[1:])]
    planned = plan(trajectory, make_request(BY_NAME[trajectory], dict(given)), starts[0],
                   DEFAULT_SETTINGS)
    config = planned.control(DEFAULT_SETTINGS.control)
    pieces = pieces_in(planned.path, config, corner_angle=DEFAULT_SETTINGS.defaults.corner_angle)
    return FleetRun(pieces, [f'turtle{k + 1}' for k in range(count)],
                    starts, config, 0.6, arena=DEFAULT_SETTINGS.arena)


def planning_s(name: str, count: int) -> float:
    """CPU seconds the coordinator's planning takes for `name` among `count` turtles."""
    began = time.process_time()
    _planned(name, count)
    return time.process_time() - began


def faults_at_scale(output: Path, single: np.ndarray, count: int = 20) -> str:
    """The demo's SVG by `count` turtles: the one with the third longest part has a worn motor
    (half its speed, throughout); the one with the longest is removed with /kill 3 s in, the
    next one's node destroyed 6 s in. A line of figures."""
    from rclpy.parameter import Parameter
    from turtle_traj_interfaces.action import FleetDraw
    shares = _planned('svg', count).first_sharing.shares
    longest = sorted(range(count), key=lambda turtle: -shares[turtle].time_s)
    killed, dead_node, worn = (f'turtle{turtle + 1}' for turtle in longest[:3])
    trajectory, given, start = DRAWINGS['svg']
    system = InProcessFleet([start, *starting_places(count)[1:]], output_dir=output)
    try:
        system.sim.set_parameters([Parameter('motor_gains', value=f'{worn}=0.5')])
        for log in system.poses.values():
            log.clear()
        client = system.action_client(FleetDraw, '/fleet/draw')
        asked_s = system.sim_time_s
        sent = client.send_goal_async(make_fleet_goal(BY_NAME[trajectory], given, system.names))
        system.spin_until(sent.done, timeout_s=30.0)
        answer = sent.result().get_result_async()
        for at_s, name, how in ((3.0, killed, 'kill'), (6.0, dead_node, 'node')):
            system.spin_until(lambda at_s=at_s: system.sim_time_s > asked_s + at_s)
            system.lose(name, how)
        system.spin_until(answer.done, timeout_s=900.0)
        result = answer.result().result
        ink = system.sim.canvas.trails[..., 3] > 0
        differ = 100.0 * np.count_nonzero(ink ^ single) / np.count_nonzero(single)
        lost = '; '.join(f'{name}: {why}' for name, why in zip(result.turtles, result.lost,
                                                               strict=True) if why)
        return (f'svg, {count} turtles, {worn} at half speed, {killed} killed at 3 s, '
                f'{dead_node}\'s node gone at 6 s: '
                f'{"drawn" if result.success else "FAILED: " + result.message}, answer '
                f'{system.sim_time_s - asked_s:.2f} s (planned {result.planned_makespan:.2f}), '
                f'pieces {sum(result.pieces)}, ink {differ:.2f}%, closest '
                f'{_closest(system.poses):.3f} m, deviation '
                f'{max(result.max_deviation) * 1000:.2f} mm; lost: {lost}')
    finally:
        system.close()


PICTURE_COLORS = ('orange,#40e0d0,#ff69b4,#adff2f,#ffd700,#1e90ff,#ff4500,#9370db,#00fa9a,'
                  '#f5f5f5')  # turtle1, turtle2, ... in the picture (in turn)


def draw(name: str, count: int, output: Path, colors: str = '') -> dict:
    """`name` drawn by `count` turtles (1: alone, with its own Draw action); `colors`: the
    coordinator's turtle_colors."""
    from turtle_traj_interfaces.action import Draw, FleetDraw
    trajectory, given, start = DRAWINGS[name]
    kind = BY_NAME[trajectory]
    system = InProcessFleet([start, *starting_places(count)[1:]], output_dir=output)
    try:
        if colors:
            from rclpy.parameter import Parameter
            system.coordinator.set_parameters([Parameter('turtle_colors', value=colors)])
        for log in system.poses.values():
            log.clear()
        wall = time.perf_counter()
        if count == 1:
            client = system.action_client(Draw, '/turtle1/turtle_traj/draw')
            result, answered_s = _finish(system, client, make_goal(kind, given))
            figures = {'makespan': result.elapsed, 'deviation': result.max_deviation,
                       'planned': float('nan'), 'bound': float('nan'), 'ok': result.success}
        else:
            client = system.action_client(FleetDraw, '/fleet/draw')
            result, answered_s = _finish(system, client,
                                         make_fleet_goal(kind, given, system.names))
            figures = {'makespan': result.makespan, 'deviation': max(result.max_deviation),
                       'planned': result.planned_makespan, 'bound': result.lower_bound,
                       'ok': result.success, 'reported_closest': result.min_distance,
                       'message': result.message}
        figures['answered'] = answered_s
        figures['wall'] = time.perf_counter() - wall
        figures['closest'] = _closest(system.poses)
        figures['trails'] = system.sim.canvas.trails.copy()
        figures['picture'] = system.sim.render()
        return figures
    finally:
        system.close()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--turtles', type=lambda text: [int(n) for n in text.split(',')],
                        default=[1, 2, 3, 4], help='the fleet sizes, comma-separated '
                        '(default 1,2,3,4; the ratio is to the first)')
    parser.add_argument('--drawings', nargs='*', default=list(DRAWINGS), choices=list(DRAWINGS))
    parser.add_argument('--no-table', dest='table', action='store_false',
                        help='skip the makespan table')
    parser.add_argument('--faults', action='store_true', help='then lose turtle2 of three at '
                        'quarter, half and three quarters of "ROS 2": /kill, and its node gone; '
                        'and the SVG by 20, one at half speed, two lost')
    parser.add_argument('--planning', action='store_true', help='then the CPU time the '
                        'coordinator takes to plan each drawing for each fleet size')
    parser.add_argument('--step-cost', action='store_true', help='then what a lock-step step '
                        'costs with 1, 5, 10 and 20 turtles, and where it goes '
                        '(speed_bench.py --step-cost)')
    parser.add_argument('--picture', type=Path, help='draw the demo\'s SVG with the most '
                        'turtles, each in its own colour, and save the canvas here')
    options = parser.parse_args()
    claim_domain_id()
    import rclpy
    rclpy.init()
    output = Path('output/fleet_bench')
    print(f'{"drawing":8} {"turtles":>7} {"answer s":>9} {"ratio":>6} {"makespan":>9} '
          f'{"planned":>8} {"bound":>6} {"closest":>8} {"reported":>8} {"dev mm":>7} '
          f'{"ink %":>6} {"wall s":>6}')
    try:
        for name in options.drawings if options.table else []:
            alone = None
            for count in options.turtles:
                row = draw(name, count, output)
                alone = alone or row
                ink = row['trails'][..., 3] > 0
                single = alone['trails'][..., 3] > 0
                differ = 100.0 * np.count_nonzero(ink ^ single) / np.count_nonzero(single)
                print(f'{name:8} {count:7d} {row["answered"]:9.2f} '
                      f'{row["answered"] / alone["answered"]:6.3f} {row["makespan"]:9.2f} '
                      f'{row["planned"]:8.2f} {row["bound"]:6.2f} {row["closest"]:8.3f} '
                      f'{row.get("reported_closest", float("nan")):8.3f} '
                      f'{row["deviation"] * 1000:7.2f} {differ:6.2f} {row["wall"]:6.1f}'
                      + ('' if row['ok'] else f'  FAILED: {row.get("message", "")}'), flush=True)
        if options.faults:
            single = draw('ROS 2', 1, output)['trails'][..., 3] > 0
            for fault in ('kill', 'node'):
                for at_s in (4.0, 8.0, 12.0):
                    print(lose_one(fault, at_s, output, single), flush=True)
            single = draw('svg', 1, output)['trails'][..., 3] > 0
            print(faults_at_scale(output, single), flush=True)
        if options.planning:
            for name in options.drawings:
                print(f'planning {name:8} CPU s: ' + ', '.join(
                    f'{count} turtles {planning_s(name, count):.2f}'
                    for count in options.turtles if count > 1), flush=True)
        if options.step_cost:
            sys.path.insert(0, str(Path(__file__).parent))
            from speed_bench import print_step_cost
            print_step_cost(rounds=3)
        if options.picture:
            row = draw('svg', options.turtles[-1], output, PICTURE_COLORS)
            options.picture.parent.mkdir(parents=True, exist_ok=True)
            row['picture'].save(options.picture)
            print(f'saved {options.picture}')
    finally:
        rclpy.shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
