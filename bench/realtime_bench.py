"""Real time as people use it: `turtle-traj up` (simulator and node in one process, wall-clock
time, default speeds) and a CLI call per drawing; the figure is each run's elapsed time over the
node's own "at least" bound, and its deviation.

Several checkouts run side by side, alternating round by round, each from its own `src/` (so an
old commit is measured with the same script, venv and machine):
    .venv/bin/python bench/realtime_bench.py [--rounds 3] [--repo PATH ...]
        [--time-scale S] [--bursts] [--programs]
With `--programs`, the simulator and the node run as two programs instead (`python -m
turtle_traj.sim`, `python -m turtle_traj`), each on its own clock as with the real turtlesim:
where the node's control ticks fall in turtlesim's step depends on when each started.
With `--time-scale S`, `turtle-traj up --time-scale S` (simulated time, S times real time);
with `--bursts`, waves of twelve processes importing numpy and rclpy run meanwhile (the load
that holds a timer up now and then, where steady busy loops do not).
The kinds are the issue's: the 2 m square, the text "ROS" 1 m high, the star, the circle, a
go-to and the sine, each from the centre after a reset. The bound is the kinematic one (length
over the default top speed, turns over the default top turn rate), from the plan the node logs:
the same for every commit, whatever its own "at least" says.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

from isolation import isolate
from turtle_traj.core.parameters.table import DEFAULTS

KINDS = {
    'square': ['draw', 'square', '--size', '2'],
    'text': ['write', 'ROS', '--height', '1'],
    'star': ['draw', 'star'],
    'circle': ['draw', 'circle'],
    'go_to': ['go-to', '8', '3'],
    'sine': ['draw', 'sine'],
}
ELAPSED = re.compile(r'elapsed ([0-9.]+) s, path [0-9.]+ m(?: \([0-9.]+ m driven\))?, '
                     r'max deviation ([0-9.]+) m, final error ([0-9.]+) m')
BURST = [sys.executable, '-c', 'import numpy, rclpy; sum(range(2000000))']
# the node's plan line: path length and turns in place, from which the kinematic bound is
# computed here (length over top speed, turns over top turn rate), the same for every commit
PLAN = re.compile(r': ([0-9.]+) m of path, ([0-9]+) deg of turns in place, at least')


def _env(repo: Path) -> dict[str, str]:
    return {**os.environ, 'PYTHONPATH': str(repo / 'src')}


def _cli(repo: Path, *argv: str) -> str:
    done = subprocess.run([sys.executable, '-m', 'turtle_traj.cli', *argv], env=_env(repo),
                          capture_output=True, text=True, timeout=300)
    return done.stdout + done.stderr


def _bursts(stop: threading.Event) -> None:
    """Waves of twelve short processes, one wave after another, until `stop`."""
    while not stop.is_set():
        wave = [subprocess.Popen(BURST) for _ in range(12)]
        for process in wave:
            process.wait()


def _start(repo: Path, up_options: list[str] | None, log: Path) -> list[subprocess.Popen]:
    """`turtle-traj up` (None: the simulator and the node as two programs), its log in `log`."""
    if up_options is None:
        programs = [[sys.executable, '-m', 'turtle_traj.sim'],
                    [sys.executable, '-m', 'turtle_traj']]
    else:
        programs = [[sys.executable, '-m', 'turtle_traj.cli', 'up', *up_options]]
    with open(log, 'w') as out:
        return [subprocess.Popen(argv, env=_env(repo), stdout=out, stderr=subprocess.STDOUT)
                for argv in programs]


def one_round(repo: Path, up_options: list[str] | None) -> dict[str, tuple[float, float, float]]:
    """Each kind's (elapsed / bound, max deviation in mm, final error in mm) from one
    `turtle-traj up` (None: two programs)."""
    log = repo / '.realtime_bench_up.log'
    started = _start(repo, up_options, log)
    try:
        for _ in range(120):  # the node says what it serves once it is up
            if 'serving' in log.read_text():
                break
            time.sleep(0.25)
        figures = {}
        for kind, argv in KINDS.items():
            _cli(repo, 'reset')
            said = _cli(repo, *argv)
            plans = PLAN.findall(log.read_text())
            found = ELAPSED.search(said)
            if not found or not plans:
                raise SystemExit(f'{kind} at {repo}: no figures in\n{said}')
            length, turns = (float(value) for value in plans[-1])
            bound = (length / DEFAULTS['linear_speed']
                     + math.radians(turns) / DEFAULTS['angular_speed'])
            figures[kind] = (float(found[1]) / bound, 1000 * float(found[2]),
                             1000 * float(found[3]))
        return figures
    finally:
        for process in started:
            process.terminate()
            process.wait(timeout=20)
        log.unlink(missing_ok=True)


def _label(repo: Path) -> str:
    done = subprocess.run(['git', '-C', str(repo), 'rev-parse', '--short', 'HEAD'],
                          capture_output=True, text=True)
    dirty = subprocess.run(['git', '-C', str(repo), 'status', '--porcelain', 'src'],
                           capture_output=True, text=True).stdout.strip()
    return done.stdout.strip() + ('+' if dirty else '')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--rounds', type=int, default=3)
    parser.add_argument('--repo', type=Path, action='append',
                        help='a checkout to measure (repeatable; default: this one)')
    parser.add_argument('--time-scale', type=float, metavar='S',
                        help='run `turtle-traj up --time-scale S`')
    parser.add_argument('--bursts', action='store_true',
                        help='waves of twelve processes meanwhile')
    parser.add_argument('--programs', action='store_true',
                        help='the simulator and the node as two programs')
    args = parser.parse_args()
    if args.programs and args.time_scale is not None:
        parser.error('--time-scale needs the simulator in the node\'s process')
    repos = [path.resolve() for path in (args.repo or [Path(__file__).resolve().parents[1]])]
    up_options = [] if args.time_scale is None else ['--time-scale', str(args.time_scale)]
    if args.programs:
        up_options = None
    isolate('realtime')
    results: dict[Path, list[dict]] = {repo: [] for repo in repos}
    stop = threading.Event()
    load = threading.Thread(target=_bursts, args=(stop,))
    if args.bursts:
        load.start()
    try:
        for round_ in range(args.rounds):
            for repo in repos:
                results[repo].append(one_round(repo, up_options))
                print(f'round {round_ + 1} {_label(repo)} done', file=sys.stderr)
    finally:
        stop.set()
        if load.is_alive():
            load.join()
    labels = {repo: _label(repo) for repo in repos}
    started = ('the simulator and the node as two programs' if up_options is None
               else f'`turtle-traj up {" ".join(up_options)}`')
    print(started + (', under waves of processes' if args.bursts else ''))
    print('elapsed / bound per round (median, max); worst max deviation mm; worst final '
          'error mm')
    print(f'{"kind":8}' + ''.join(f'  {labels[repo]:>40}' for repo in repos))
    for kind in KINDS:
        row = f'{kind:8}'
        for repo in repos:
            ratios = [each[kind][0] for each in results[repo]]
            worst = max(each[kind][1] for each in results[repo])
            end = max(each[kind][2] for each in results[repo])
            cell = (', '.join(f'{ratio:.2f}' for ratio in ratios)
                    + f' ({statistics.median(ratios):.2f}, {max(ratios):.2f}) {worst:.1f}'
                    + f' {end:.2f}')
            row += f'  {cell:>40}'
        print(row)
    return 0


if __name__ == '__main__':
    sys.exit(main())
