"""Grading a class, timed as a teacher waits for it: `turtle-traj grade` on 30 copies of the
square lab's open-loop sample (about 13 s of driving each), from the command to the class
page, with the machine's CPU seconds spent (all processes, from /proc/stat), and every
copy's grade, closure and the simulator's lost steps. Target (issue 75): at most 90 s on 2
cores, every copy 11 of 11.

    python bench/grading_bench.py [--copies 30] [--jobs N]
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

LAB = Path(__file__).resolve().parents[1] / 'src' / 'turtle_traj' / 'labs' / 'square'


def cpu_seconds() -> float:
    fields = Path('/proc/stat').read_text().split('\n', 1)[0].split()[1:]
    user, nice, system = (int(value) for value in fields[:3])
    return (user + nice + system) / 100.0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--copies', type=int, default=30)
    parser.add_argument('--jobs', type=int)
    options = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        work = Path(folder)
        for index in range(options.copies):
            shutil.copytree(LAB / 'samples' / 'right', work / 'class' / f'student{index:02d}')
        command = [sys.executable, '-m', 'turtle_traj.cli', 'grade', str(LAB / 'task.yaml'),
                   str(work / 'class'), '--output', str(work / 'grades')]
        if options.jobs:
            command += ['--jobs', str(options.jobs)]
        cpu, started = cpu_seconds(), time.monotonic()
        done = subprocess.run(command, capture_output=True, text=True)
        seconds, cpu = time.monotonic() - started, cpu_seconds() - cpu
        summary = json.loads((work / 'grades' / 'summary.json').read_text())
        scores = [student['score'] for student in summary['students']]
        closures = [float(check['message'].split(' m from')[0].rsplit(' ', 1)[1])
                    for student in summary['students'] for check in student['checks']
                    if check['name'] == 'closure' and 'from where' in check['message']]
        lost = [json.loads(path.read_text())['lost_steps']
                for path in (work / 'grades' / 'runs').glob('*/outcome.json')]
    print(f'{options.copies} copies graded in {seconds:.1f} s (target 90 s), '
          f'{cpu:.0f} CPU-s of the machine; exit status {done.returncode}')
    print(f'scores: {sorted(set(scores))} ({scores.count(11.0)} of {len(scores)} full); '
          f'closure {min(closures):.3f} to {max(closures):.3f} m (tolerance 0.2); '
          f'simulator steps lost: {sum(lost)} (most in a run {max(lost, default=0)})')
    return 0 if done.returncode in (0, 1) else done.returncode


if __name__ == '__main__':
    sys.exit(main())
