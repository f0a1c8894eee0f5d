"""The trajectory node program's CPU at real time, idle and driving, side by side with older
commits (issue 66, item 5).

Each tree runs as a user runs it: our simulator and the node as two programs
(`python -m turtle_traj.sim`, `python -m turtle_traj`), a ROS domain of their own. The node's
share of one core is read from /proc over `--seconds` while it stands idle, then while it drives
`turtle-traj draw circle --size 1 --forever` (a client process of the same tree). The trees
take turns, round after round, so that the machine's drift falls on all alike. Prints the
median and the spread of each.

    python bench/node_cpu_bench.py [--against 5cb29f8 c1af86f] [--rounds 3] [--seconds 10]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from process_cpu import cpu_share
from worktree import ROOT, old_tree

DOMAIN = '93'


def _measure(tree: Path, seconds: float) -> tuple[float, float]:
    """One round in `tree`: the node's share of a core idle, then driving a circle."""
    env = {**os.environ, 'PYTHONPATH': str(tree / 'src'), 'ROS_DOMAIN_ID': DOMAIN}
    quiet = {'stdout': subprocess.DEVNULL, 'stderr': subprocess.DEVNULL, 'env': env,
             'cwd': tree}
    sim = subprocess.Popen([sys.executable, '-m', 'turtle_traj.sim'], **quiet)
    node = subprocess.Popen([sys.executable, '-m', 'turtle_traj'], **quiet)
    client = None
    try:
        _until_ready(env, tree)
        idle = cpu_share(node.pid, seconds)
        client = subprocess.Popen([sys.executable, '-c', 'from turtle_traj.cli.main import main; '
                                   'main(["draw", "circle", "--size", "1", "--forever"])'],
                                  **quiet)
        time.sleep(2.0)  # connected and driving
        driving = cpu_share(node.pid, seconds)
        return idle, driving
    finally:
        for program in (client, node, sim):
            if program is not None:
                program.terminate()
                with contextlib.suppress(subprocess.TimeoutExpired):
                    program.wait(timeout=10)
                if program.poll() is None:
                    program.kill()


def _until_ready(env: dict, tree: Path, timeout_s: float = 60.0) -> None:
    """Until the node answers a reset (it then has the simulator's poses)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        done = subprocess.run([sys.executable, '-c', 'from turtle_traj.cli.main import main; '
                               'raise SystemExit(main(["reset"]))'],
                              env=env, cwd=tree, capture_output=True, timeout=60)
        if done.returncode == 0:
            return
        time.sleep(0.5)
    raise RuntimeError(f'the node in {tree} never became ready')


def _line(label: str, values: list[float]) -> str:
    shares = [100.0 * value for value in values]
    return (f'{label:>10} {statistics.median(shares):6.1f} % '
            f'({min(shares):.1f} to {max(shares):.1f})')


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--against', nargs='*', default=['5cb29f8', 'c1af86f'])
    parser.add_argument('--rounds', type=int, default=3)
    parser.add_argument('--seconds', type=float, default=10.0)
    options = parser.parse_args()
    with contextlib.ExitStack() as stack:
        trees = {'HEAD': ROOT, **{rev: stack.enter_context(old_tree(rev))
                                  for rev in options.against}}
        results: dict[str, list[tuple[float, float]]] = {label: [] for label in trees}
        for _ in range(options.rounds):
            for label, tree in trees.items():
                results[label].append(_measure(tree, options.seconds))
    print(f'node program, share of one core over {options.seconds:g} s, median (range) of '
          f'{options.rounds} rounds')
    print(f"{'tree':>10} {'idle':>16}   {'driving':>16}")
    for label, runs in results.items():
        print(f"{_line(label, [idle for idle, _ in runs])}   "
              f"{_line('', [driving for _, driving in runs]).strip()}")


if __name__ == '__main__':
    main()
