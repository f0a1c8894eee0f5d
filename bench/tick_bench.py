"""The control tick alone, phase by phase, side by side with an older commit.

    .venv/bin/python bench/tick_bench.py [--against 5cb29f8] [--rounds 3]

The node's control loop (`ControlLoop`: a pose in, a command out) drives the score's courses in
pure Python on the simulator's physics, as `turtle-traj score` does: turtlesim's (the registry's
examples), the base with inertia (the DWPP paper's step paths and sine), and that base seen
through odometry (its measured velocity instead of turtlesim's echo of the command). Each tick
is timed in four phases:
  observe    the model of the robot and the run take the pose (`observe`),
  predict    where the commands in flight take the robot (`RobotModel.predict`),
  command    the controller's command (the plan walker's `update`),
  supervise  the rest of the tick: the run's rules, the model's bookkeeping, the echo's nudge.
The simulator's own step is not timed. Each tree runs in a process of its own, from its own
`src/` (the old one in a temporary git worktree), round by round in turn; the figures are the
median and the 99th percentile per tick over every tick of every course, in microseconds, each
the median over the rounds.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from worktree import ROOT, old_tree

CONTROLLERS = ('exact', 'dwpp', 'pure_pursuit')
ROBOTS = ('turtlesim', 'inertia', 'odometry')
PHASES = ('observe', 'predict', 'command', 'supervise')


def measure() -> dict:
    """Every robot and controller: per-tick microseconds, per phase and in all."""
    import numpy as np

    from turtle_traj.apps.score.courses import PAPER_INERTIA, standard_courses
    from turtle_traj.core.control import loop, robot_model, supervisor
    try:
        from turtle_traj.core.control.walker import PlanWalker
        drivers = [PlanWalker]
    except ImportError:  # an older tree: the exact follower and the stroke driver apart
        from turtle_traj.core.control import follower, strokes
        drivers = [follower.PathFollower, strokes.StrokeDriver]
    try:
        from turtle_traj.api.controllers import choose
    except ImportError:  # an older tree: the core's catalogue found controllers by name
        from turtle_traj.core.control.controllers.catalogue import choose
    from turtle_traj.core.geometry.path import Pose2D
    from turtle_traj.core.planning import planner
    from turtle_traj.core.turtlesim_contract import STEP_S
    from turtle_traj.sim.physics import World

    def _loop(loop, odometry: bool, step_s: float):
        """A control loop for turtlesim or an odometry base (an older tree took a flag)."""
        try:
            from turtle_traj.core.control.observers import ODOMETRY_BASE, TURTLESIM
        except ImportError:
            return loop.ControlLoop(step_s, echoes=not odometry)
        return loop.ControlLoop(step_s, robot=ODOMETRY_BASE if odometry else TURTLESIM)

    def _untimed(name: str):
        """The controller, its answers untimed (an older tree's choose timed them unless told
        not to)."""
        try:
            return choose(name, timed=False)
        except TypeError:
            return choose(name)

    spent = dict.fromkeys(PHASES, 0)

    def timed(owner, name: str, phase: str) -> None:
        method = getattr(owner, name)

        def wrapper(*args, **kwargs):
            began = time.perf_counter_ns()
            try:
                return method(*args, **kwargs)
            finally:
                spent[phase] += time.perf_counter_ns() - began
        setattr(owner, name, wrapper)

    timed(robot_model.RobotModel, 'observe', 'observe')
    timed(supervisor.RunSupervisor, 'observe', 'observe')
    timed(robot_model.RobotModel, 'predict', 'predict')
    for driver in drivers:
        timed(driver, 'update', 'command')

    results = {}
    courses = {'turtlesim': standard_courses(('turtlesim',)),
               'inertia': standard_courses(('inertia',))}
    courses['odometry'] = courses['inertia']
    for robot in ROBOTS:
        for controller in CONTROLLERS:
            ticks: dict[str, list[int]] = {phase: [] for phase in (*PHASES, 'tick')}
            for course in courses[robot]:
                plan = planner.plan(course.trajectory, course.request, course.start,
                                    course.settings)
                world = World(inertia=None if robot == 'turtlesim' else PAPER_INERTIA)
                turtle = world.spawn(course.start.x, course.start.y, course.start.theta, 't')
                control = _loop(loop, robot == 'odometry', STEP_S)
                control.observe(course.start, 0.0, 0.0)
                run = control.start(plan, arena=course.settings.arena, now_s=0.0,
                                    controller=_untimed(controller))
                for step in range(int(600.0 / STEP_S)):
                    for phase in PHASES:
                        spent[phase] = 0
                    began = time.perf_counter_ns()
                    control.observe(Pose2D(turtle.x, turtle.y, turtle.theta),
                                    float(np.float32(turtle.linear_speed)),
                                    float(np.float32(turtle.omega)))
                    command = control.command(course.settings.control, course.settings.arena,
                                              step * STEP_S)
                    tick = time.perf_counter_ns() - began
                    spent['supervise'] = tick - spent['observe'] - spent['predict'] - spent[
                        'command']
                    for phase in PHASES:
                        ticks[phase].append(spent[phase])
                    ticks['tick'].append(tick)
                    if run.ending is not None:
                        break
                    if run.pen_wanted is not None:
                        run.pen_is(run.pen_wanted)
                    if command is not None:
                        control.sent(command, step * STEP_S)
                        world.command('t', command.linear, 0.0, command.angular)
                    world.step()
            results[f'{robot}/{controller}'] = {
                phase: (float(np.median(values)) / 1e3, float(np.percentile(values, 99)) / 1e3)
                for phase, values in ticks.items()} | {
                'ticks': len(ticks['tick']), 'mean': (float(np.mean(ticks['tick'])) / 1e3, 0.0)}
    return results


def _run(tree: Path) -> dict:
    env = {**os.environ, 'PYTHONPATH': str(tree / 'src')}
    done = subprocess.run([sys.executable, __file__, '--measure'], env=env, cwd=tree,
                          capture_output=True, text=True, timeout=1800)
    if done.returncode != 0:
        raise RuntimeError(f'{tree}: {done.stderr[-3000:]}')
    return json.loads(done.stdout.strip().splitlines()[-1])


def _median(rounds: list[dict], key: str, phase: str, which: int) -> float:
    return statistics.median(result[key][phase][which] for result in rounds)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--against', default='5cb29f8', help='the old commit (default 5cb29f8)')
    parser.add_argument('--rounds', type=int, default=3)
    parser.add_argument('--measure', action='store_true', help=argparse.SUPPRESS)
    options = parser.parse_args()
    if options.measure:
        print(json.dumps(measure()))
        return
    rounds: dict[str, list[dict]] = {'old': [], 'new': []}
    with old_tree(options.against) as old:
        for _ in range(options.rounds):
            rounds['old'].append(_run(old))
            rounds['new'].append(_run(ROOT))
    print(f'The control tick, us: median and 99th percentile per tick over the score\'s '
          f'courses; {options.against} (old) against this checkout (new), median of '
          f'{options.rounds} rounds each')
    header = f"{'robot/controller':26} {'ticks':>6} " + ' '.join(
        f'{phase:>19}' for phase in (*PHASES, 'tick')) + f"{'mean':>8}   new/old: median, mean"
    print(header)
    for key in rounds['new'][0]:
        for side in ('old', 'new'):
            cells = ' '.join(f"{_median(rounds[side], key, phase, 0):8.1f} "
                             f"{_median(rounds[side], key, phase, 1):9.1f} "
                             for phase in (*PHASES, 'tick'))
            ratio = ''
            if side == 'new':
                ratio = (f"   {_median(rounds['new'], key, 'tick', 0) / _median(rounds['old'], key, 'tick', 0):.2f}"  # noqa: E501
                         f"   mean {_median(rounds['new'], key, 'mean', 0) / _median(rounds['old'], key, 'mean', 0):.2f}")  # noqa: E501
            mean = _median(rounds[side], key, 'mean', 0)
            print(f"{key + ' ' + side:26} {rounds[side][0][key]['ticks']:6d} {cells}{mean:8.1f}"
                  f'{ratio}')


if __name__ == '__main__':
    main()
