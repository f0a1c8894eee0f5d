"""The same submission gets the same grade: every lab's sample submissions graded N times
(the labs at once, as a teacher's machine would), quiet or beside two busy loops, and each
sample's grades counted against its expected grade. Also the simulators' lost steps, the
slowest repetition, and the spread of the right samples' shape distance and closure. Target
(issue 75): every sample its expected grade in 20 runs of 20, quiet and loaded.

    python bench/grading_repeat_bench.py [--runs 20] [--busy 2]
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import yaml

from load import busy_loops
from turtle_traj.apps.grade import load_task
from turtle_traj.grading.grader import grade_class

LABS = Path(__file__).resolve().parents[1] / 'src' / 'turtle_traj' / 'labs'


def grade_all(folder: Path) -> dict[tuple[str, str], object]:
    def one(lab: Path) -> list:
        return [((lab.name, result.name), result) for result in grade_class(
            load_task(lab / 'task.yaml'), lab / 'samples', folder / lab.name)]

    labs = sorted(path for path in LABS.iterdir() if (path / 'task.yaml').exists())
    with ThreadPoolExecutor(len(labs)) as pool:
        return dict(pair for results in pool.map(one, labs) for pair in results)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--runs', type=int, default=20)
    parser.add_argument('--busy', type=int, default=0, help='busy loops beside (default 0)')
    options = parser.parse_args()
    expected = {(lab.name, name): grade for lab in LABS.iterdir()
                if (lab / 'samples' / 'expected_grades.yaml').exists()
                for name, grade in yaml.safe_load(
                    (lab / 'samples' / 'expected_grades.yaml').read_text()).items()}
    grades, lost, durations = collections.defaultdict(list), [], []
    wrong: list[str] = []
    with busy_loops(options.busy):
        for run in range(options.runs):
            with tempfile.TemporaryDirectory() as folder:
                started = time.monotonic()
                results = grade_all(Path(folder))
                durations.append(time.monotonic() - started)
                for key, result in results.items():
                    grades[key].append(result.score)
                    outcome = result.run_dir / 'outcome.json'
                    if outcome.exists():
                        lost.append((key, json.loads(outcome.read_text())['lost_steps']))
                    if result.score != expected[key]:
                        wrong.append(f'run {run + 1}: {key[0]}/{key[1]} got {result.score:g} '
                                     f'({[c.message for c in result.checks if not c.passed]})')
            print(f'run {run + 1}: {durations[-1]:.0f} s', flush=True)
    print(f'\n{options.runs} runs, {options.busy} busy loops beside; slowest '
          f'{max(durations):.0f} s a run')
    for key in sorted(expected):
        got = grades[key]
        print(f'{key[0]:>10}/{key[1]:<15} expected {expected[key]:>3g}: '
              f'{got.count(expected[key])} of {len(got)}'
              f'{"" if set(got) == {expected[key]} else f"  (got {sorted(set(got))})"}')
    moved_lost = [steps for key, steps in lost if key != ('square', 'hostile_fork')]
    print(f'simulator steps lost, the fork bomb\'s own room aside: {sum(moved_lost)} in all, '
          f'{max(moved_lost, default=0)} at most in a run')
    for line in wrong:
        print(line)
    return 1 if wrong else 0


if __name__ == '__main__':
    sys.exit(main())
