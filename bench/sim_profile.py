"""Where the simulator program's CPU goes at real time, side by side with an older commit.

Run: .venv/bin/python bench/sim_profile.py [--against 9873574] [--rounds 3]

For each tree in turn (the old one in a temporary git worktree), `python -m turtle_traj.sim`
runs one turtle at real time, first idle, then under bench/traffic_floor.py's driver (pose
subscribed, cmd_vel every 16 ms: the issue's "driven" case). Per window of 10 s it prints the
share of one core, the same per thread, the thread wake-ups per 16 ms step (voluntary context
switches), and, where `perf` runs, the driven window's samples by library. Then the levers:
this checkout with one saving undone at a time, measured the same way.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

from isolation import isolate
from process_cpu import process_cpu_s

ROOT = Path(__file__).resolve().parents[1]
BENCH = Path(__file__).resolve().parent
WINDOW_S = 10.0
STEP_S = 0.016
QUIET = {'stdout': subprocess.DEVNULL, 'stderr': subprocess.DEVNULL}

# Levers: what each undoes of this checkout, as code run before the simulator starts.
LEVERS = {
    'pose and colour published with no subscriber (as before)': (
        'from turtle_traj.sim.endpoints import TurtleEndpoints\n'
        'TurtleEndpoints.listened = staticmethod(lambda publisher: True)\n'),
    "Fast DDS's default announcement period (3 s, not our 0.5 s)": None,  # an environment
}


def _threads(pid: int) -> dict[int, tuple[str, float, int]]:
    """Per thread: its name, CPU seconds and voluntary context switches so far."""
    threads = {}
    for task in Path(f'/proc/{pid}/task').iterdir():
        try:
            name = (task / 'comm').read_text().strip()
            fields = (task / 'stat').read_text().rsplit(')', 1)[1].split()
            cpu = (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')
            switches = next(int(line.split()[1]) for line in (task / 'status').read_text()
                            .splitlines() if line.startswith('voluntary_ctxt_switches'))
        except (FileNotFoundError, ProcessLookupError, StopIteration):
            continue
        threads[int(task.name)] = (name, cpu, switches)
    return threads


def _window(pid: int) -> dict:
    """One window's figures for the process: CPU share, per thread, wake-ups."""
    before, cpu0, wall0 = _threads(pid), process_cpu_s(pid), time.monotonic()
    time.sleep(WINDOW_S)
    after, cpu1, wall1 = _threads(pid), process_cpu_s(pid), time.monotonic()
    elapsed = wall1 - wall0
    per_thread: Counter[str] = Counter()
    wakeups: Counter[str] = Counter()
    for tid, (name, cpu, switches) in after.items():
        _, cpu_before, switches_before = before.get(tid, (name, 0.0, 0))
        kind = 'main' if tid == pid else 'other Python' if name == 'python' else name
        per_thread[kind] += (cpu - cpu_before) / elapsed
        wakeups[kind] += (switches - switches_before) / (elapsed / STEP_S)
    return {'cpu': (cpu1 - cpu0) / elapsed, 'threads': per_thread,
            'wakeups_per_step': sum(wakeups.values()), 'wakeups': wakeups}


def _perf_window(pid: int) -> Counter[str]:
    """A window sampled by perf (its own: sampling costs the process some CPU)."""
    data = Path(tempfile.mkdtemp()) / 'perf.data'
    subprocess.run(['perf', 'record', '-F', '999', '-p', str(pid), '-o', str(data), '--',
                    'sleep', str(WINDOW_S)], **QUIET, timeout=120)
    return _perf_by_library(data)


def _perf_by_library(data: Path) -> Counter[str]:
    """Shares of the samples by shared object, folded into a few families."""
    report = subprocess.run(['perf', 'report', '-i', str(data), '--sort', 'dso', '--stdio',
                             '-q', '--percent-limit', '0.5'],
                            capture_output=True, text=True).stdout
    families: Counter[str] = Counter()
    for line in report.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0].endswith('%'):
            families[_family(parts[1])] += float(parts[0].rstrip('%'))
    return families


def _family(library: str) -> str:
    for key, family in (('python', 'Python interpreter'), ('kernel', 'kernel'),
                        ('fastrtps', 'Fast DDS'), ('fastcdr', 'Fast DDS'),
                        ('rmw', 'rmw + rcl'), ('rcl', 'rmw + rcl'), ('_rclpy', 'rclpy (C++)'),
                        ('libc', 'libc'), ('stdc++', 'libstdc++'), ('numpy', 'numpy'),
                        ('_multiarray', 'numpy')):
        if key in library:
            return family
    return 'other'


def measure(tree: Path, prelude: str | None = None, environ: dict | None = None,
            perf: bool = False) -> dict:
    """The simulator of `tree`, idle then driven."""
    env = {**os.environ, 'PYTHONPATH': str(tree / 'src'), **(environ or {})}
    command = [sys.executable, '-c', (prelude or '') +
               'import sys\nfrom turtle_traj.apps.sim import main\nsys.exit(main([]))']
    with tempfile.TemporaryDirectory() as folder:
        sim = subprocess.Popen(command, env=env, cwd=folder, **QUIET)
        driver = None
        try:
            time.sleep(3.0)  # started, discovered, settled
            idle = _window(sim.pid)
            driver = subprocess.Popen([sys.executable, str(BENCH / 'traffic_floor.py'),
                                       'driver'], **QUIET)
            time.sleep(3.0)  # matched
            driven = _window(sim.pid)
            if perf:
                driven['perf'] = _perf_window(sim.pid)
            if sim.poll() is not None:
                raise RuntimeError(f'the simulator of {tree} ended early')
            return {'idle': idle, 'driven': driven}
        finally:
            for process in (driver, sim):
                if process is not None:
                    process.terminate()
                    process.wait(timeout=15)


def _median(runs: list[dict], case: str, key: str) -> float:
    return statistics.median(run[case][key] for run in runs)


def _perf_available() -> bool:
    try:
        return subprocess.run(['perf', 'record', '-o', os.devnull, '--', 'true'],
                              **QUIET, timeout=30).returncode == 0
    except (FileNotFoundError, subprocess.TimeoutExpired):
        return False


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--against', default='9873574', help='the old commit (default 9873574)')
    parser.add_argument('--rounds', type=int, default=3)
    options = parser.parse_args()
    isolate('sim')
    perf = _perf_available()
    old = Path(tempfile.mkdtemp(prefix='turtle_traj_bench_')) / 'old'
    subprocess.run(['git', '-C', str(ROOT), 'worktree', 'add', '--detach', str(old),
                    options.against], check=True, capture_output=True)
    try:
        runs: dict[str, list[dict]] = {'old': [], 'new': []}
        for round_index in range(options.rounds):
            last = round_index == options.rounds - 1
            runs['old'].append(measure(old, perf=perf and last))
            runs['new'].append(measure(ROOT, perf=perf and last))
        print(f'turtle_traj simulator profile: `python -m turtle_traj.sim`, one turtle, real '
              f'time; {options.against} (old) and this checkout (new), median of '
              f'{options.rounds} alternating runs, {WINDOW_S:.0f} s windows')
        print('  (the real C++ turtlesim 1.8.2, measured on this machine for issue 25: idle '
              '2.7%, driven 5.7%)')
        for case in ('idle', 'driven'):
            old_cpu, new_cpu = (100 * _median(runs[side], case, 'cpu') for side in runs)
            old_wakes, new_wakes = (_median(runs[side], case, 'wakeups_per_step')
                                    for side in runs)
            print(f'  {case}: share of one core  old {old_cpu:4.1f}%  new {new_cpu:4.1f}%;  '
                  f'thread wake-ups per step  old {old_wakes:4.1f}  new {new_wakes:4.1f}')
            for side in ('old', 'new'):
                last = runs[side][-1][case]
                busiest = ', '.join(f'{name} {100 * share:.1f}% ({last["wakeups"][name]:.1f})'
                                    for name, share in last['threads'].most_common(5)
                                    if share >= 0.001 or last['wakeups'][name] >= 0.1)
                print(f'    {side} by thread, CPU (wake-ups per step), last run: {busiest}')
        if perf:
            print('  driven, perf samples by library (last run):')
            for side in ('old', 'new'):
                shares = runs[side][-1]['driven']['perf']
                print(f'    {side}: ' + ', '.join(f'{name} {share:.0f}%'
                                                   for name, share in shares.most_common()))
        print('  levers: this checkout with one saving undone (median of the rounds):')
        for lever, prelude in LEVERS.items():
            environ = None
            if prelude is None:
                empty = Path(tempfile.mkdtemp()) / 'default.xml'
                empty.write_text('<?xml version="1.0"?>\n<profiles xmlns="http://www.eprosima'
                                 '.com/XMLSchemas/fastRTPS_Profiles"/>\n')
                environ = {'FASTRTPS_DEFAULT_PROFILES_FILE': str(empty)}
            undone = [measure(ROOT, prelude, environ) for _ in range(options.rounds)]
            print(f'    {lever:58s} idle {100 * _median(undone, "idle", "cpu"):4.1f}%  '
                  f'driven {100 * _median(undone, "driven", "cpu"):4.1f}%')
    finally:
        subprocess.run(['git', '-C', str(ROOT), 'worktree', 'remove', '--force', str(old)],
                       capture_output=True)


if __name__ == '__main__':
    main()
