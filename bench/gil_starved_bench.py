"""The MultiThreadedExecutor flake through ROS, on demand: tests/test_multithreaded.py's
concurrent goals, run whole, with a thread in the test's process that holds the GIL in slices
(bench/gil_hog.py), one pytest process a run.

    .venv/bin/python bench/gil_starved_bench.py [RUNS] [--switch SECONDS ...] [--repo PATH ...]
        [--alternate-load]

With `--alternate-load`, every second run has two busy loops (one a core) beside it, each
stopped once the run ends: the flake's loop, half quiet and half loaded.

The full suite fails that test now and then ('polygon aborted: no progress along the path for
3 s, 0.000 m from it'); bench/starved_bench.py reproduces it in pure Python with stalls drawn
at random. Here the node runs in ROS as the test runs it, and the starvation is steady: at a
switch interval of 10 ms the test fails at caf3c5f in every run, at 5 ms (the interpreter's
default) it passes. The thread starts as the test's body does (bench/gil_hog.py): caf3c5f
still fails every run, and a run takes about 25 s instead of 70. Each checkout runs its own
tests and `src/` (an A/B of two commits).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import time
from pathlib import Path

from load import busy_loops

ROOT = Path(__file__).resolve().parents[1]
TEST = ('tests/test_multithreaded.py', '-k', 'concurrent_draw')


def run_once(repo: Path, switch_s: float) -> tuple[bool, str, float]:
    """One run of the test: whether it passed, the run's message if it failed, wall seconds."""
    env = {**os.environ, 'PYTHONPATH': f'{repo / "src"}:{ROOT / "bench"}',
           'GIL_HOG_SWITCH_S': str(switch_s)}
    began = time.monotonic()
    done = subprocess.run([sys.executable, '-m', 'pytest', '-q', '-p', 'no:cacheprovider',
                           '-p', 'gil_hog', *TEST], cwd=repo, env=env, capture_output=True,
                          text=True, timeout=300)
    said = re.search(r"'(\w+ aborted: [^']*?)'", done.stdout)
    message = said[1] if said else (done.stdout.strip().splitlines() or ['?'])[-1]
    return done.returncode == 0, '' if done.returncode == 0 else message, time.monotonic() - began


def run_loaded_or_not(repo: Path, switch_s: float, index: int,
                      alternate: bool) -> tuple[bool, str, float]:
    """Run `index`, with two busy loops beside it when `alternate` and `index` is odd."""
    with busy_loops(2 if alternate and index % 2 else 0):
        return run_once(repo, switch_s)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('runs', type=int, nargs='?', default=3)
    parser.add_argument('--switch', type=float, action='append', metavar='SECONDS',
                        help='the GIL slice (repeatable; default 0.01 and 0.005)')
    parser.add_argument('--repo', type=Path, action='append')
    parser.add_argument('--alternate-load', action='store_true',
                        help='two busy loops beside every second run')
    args = parser.parse_args()
    print(f'{"checkout":28} {"slice ms":>8} {"failed":>8} {"s a run":>8}')
    for switch in args.switch or [0.01, 0.005]:
        for repo in args.repo or [ROOT]:
            results = [run_loaded_or_not(repo.resolve(), switch, index, args.alternate_load)
                       for index in range(args.runs)]
            failed = [message for ok, message, _ in results if not ok]
            seconds = sorted(elapsed for _, _, elapsed in results)[len(results) // 2]
            print(f'{str(repo)[-28:]:28} {switch * 1e3:8.0f} {len(failed):4}/{len(results):<3} '
                  f'{seconds:8.1f}')
            for message in sorted(set(failed))[:3]:
                print(f'    {message[:100]}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
