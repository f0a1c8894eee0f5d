"""The MultiThreadedExecutor flake as a loop: the 12-sided polygon of tests/test_multithreaded.py
on an executor that starves the node (tests/starved_executor.py: timer and pose stalls fitted to
what that test measured), one seeded run per seed, pure Python.

    .venv/bin/python bench/starved_bench.py [SEEDS] [--repo PATH ...]

Each checkout runs from its own `src/` in a process of its own (an old commit with this script's
harness), and the table gives failures, and the elapsed time over the bound and the deviation at
the median and the worst.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
_ONE = """
import json, sys
sys.path.insert(0, {root!r})
from tests.starved_executor import drive
from tests.test_supervisor import shape
out = []
for seed in range({seeds}):
    run = drive('polygon', shape(sides=12, size=0.15), seed)
    out.append((run.success, run.message, run.elapsed_s / run.bound_s, run.max_deviation_m))
print(json.dumps(out))
"""


def runs(repo: Path, seeds: int) -> list[tuple[bool, str, float, float]]:
    env = {**os.environ, 'PYTHONPATH': str(repo / 'src')}
    done = subprocess.run([sys.executable, '-c', _ONE.format(root=str(ROOT), seeds=seeds)],
                          env=env, capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('seeds', type=int, nargs='?', default=300)
    parser.add_argument('--repo', type=Path, action='append')
    args = parser.parse_args()
    print(f'{"checkout":28} {"failed":>8} {"time/bound med":>15} {"worst":>6} '
          f'{"deviation mm med":>17} {"worst":>6}')
    for repo in args.repo or [ROOT]:
        results = runs(repo.resolve(), args.seeds)
        failed = [message for ok, message, _, _ in results if not ok]
        ratios = [ratio for ok, _, ratio, _ in results if ok] or [float('nan')]
        deviations = [1000 * deviation for _, _, _, deviation in results]
        print(f'{str(repo)[-28:]:28} {len(failed):4}/{len(results):<3} '
              f'{statistics.median(ratios):15.2f} {max(ratios):6.2f} '
              f'{statistics.median(deviations):17.1f} {max(deviations):6.1f}')
        for message in sorted(set(failed))[:3]:
            print(f'    {message[:90]}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
