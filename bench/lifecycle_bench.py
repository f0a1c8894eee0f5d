"""Lifecycle soak: nodes made, used and destroyed many times over, with no hang, crash or leak.

Two parts, each watched from this process, which never joins ROS itself:
1. in one child process, CYCLES times: the in-process system (simulator, trajectory node,
   client) comes up on the process's one context, draws a short line in lock-step and is
   destroyed. The child prints cycles per second, its memory at cycles 100 and CYCLES, and the
   most Fast DDS participants (`dds.ev.*` threads, one per participant) it ever had at once;
2. CLIS command-line processes (`turtle-traj params linear_speed`), one after another, against
   one running node program: their failures, their participants (sampled while they run), the
   node program's memory before and after.
A child that stops reporting for HANG_S is a hang: its threads' stacks are printed and it is
killed. A child that dies of a signal is a crash.

Run: .venv/bin/python bench/lifecycle_bench.py [--cycles N] [--clis N]
"""

from __future__ import annotations

import argparse
import json
import os
import select
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from isolation import isolate
from turtle_traj.rosutils.runtime import live_participants

HANG_S = 60.0  # no progress for this long: a hang (a cycle takes about 0.2 s)


def rss_mb(pid: int | str = 'self') -> float:
    for line in Path(f'/proc/{pid}/status').read_text().splitlines():
        if line.startswith('VmRSS:'):
            return int(line.split()[1]) / 1024.0
    return float('nan')


# -- part 1, in the child ----------------------------------------------------------------------

def run_cycles(cycles: int) -> None:
    """Print one JSON line per cycle: its number, participants at the peak, memory. At cycles 1,
    100 and the last, after a garbage collection, the memory is taken twice: as it is, and after
    glibc's malloc_trim gave the heap's free pages back (the C++ threads' heaps grow in steps
    that free() keeps; what is left after the trim is memory still in use)."""
    import ctypes
    import gc

    import rclpy
    from turtle_traj_interfaces.srv import Move

    from turtle_traj.apps.in_process import InProcessSystem
    from turtle_traj.rosutils.runtime import process_context

    context, _ = process_context()
    output = Path(tempfile.mkdtemp(prefix='turtle_traj_lifecycle_'))
    start = time.monotonic()
    try:
        for cycle in range(1, cycles + 1):
            system = InProcessSystem(context=context, output_dir=output)
            try:
                response = system.call(Move, 'move', Move.Request(distance=0.2), timeout_s=30.0)
                peak = live_participants()
            finally:
                system.close()
            line = {'cycle': cycle, 'ok': bool(response.success), 'message': response.message,
                    'participants': peak, 'after_close': live_participants(),
                    'elapsed_s': time.monotonic() - start}
            if cycle in (1, 100, cycles):
                gc.collect()
                line['rss_mb'] = rss_mb()
                ctypes.CDLL('libc.so.6').malloc_trim(0)
                line['in_use_mb'] = rss_mb()
            print(json.dumps(line), flush=True)
    finally:
        rclpy.try_shutdown()


def _watch(command: list[str], what: str) -> tuple[list[dict], str]:
    """Run a child that prints JSON lines; return them and how it ended (what it wrote to
    stderr, its nodes' logs, is printed only if it did not end well)."""
    log = tempfile.TemporaryFile('w+')
    lines, ending = _follow(subprocess.Popen(command, stdout=subprocess.PIPE, stderr=log,
                                             text=True), what)
    if ending != 'ended':
        log.seek(0)
        print(''.join(log.readlines()[-40:]))
    return lines, ending


def _follow(child: subprocess.Popen, what: str) -> tuple[list[dict], str]:
    lines: list[dict] = []
    buffered = ''
    while True:
        ready, _, _ = select.select([child.stdout], [], [], HANG_S)
        if not ready:
            print(f'  HANG: {what} made no progress for {HANG_S:g} s; its stacks:', flush=True)
            subprocess.run(['gdb', '-batch', '-nx', '-p', str(child.pid), '-ex',
                            'thread apply all bt'], check=False, timeout=120)
            child.kill()
            child.wait()
            return lines, 'hung'
        chunk = os.read(child.stdout.fileno(), 65536).decode()
        if not chunk:
            break
        buffered += chunk
        *complete, buffered = buffered.split('\n')
        lines.extend(json.loads(line) for line in complete if line.startswith('{'))
    code = child.wait()
    if code < 0:
        return lines, f'crashed ({signal.Signals(-code).name})'
    return lines, 'ended' if code == 0 else f'exited with {code}'


def part_cycles(cycles: int) -> bool:
    lines, ending = _watch([sys.executable, __file__, '--child-cycles', str(cycles)],
                           'the create-use-destroy cycles')
    failed = [line for line in lines if not line['ok']]
    print(f'1. {len(lines)} of {cycles} create-use-destroy cycles of the in-process system '
          f'(simulator, trajectory node, client, a 0.2 m move each), one process: {ending}')
    if lines:
        print(f'   {len(lines) / lines[-1]["elapsed_s"]:.1f} cycles per second; '
              f'{len(failed)} moves failed' + (f' (first: {failed[0]["message"]})'
                                               if failed else ''))
        by_cycle = {line['cycle']: line for line in lines if 'rss_mb' in line}
        for key, label in (('rss_mb', 'resident'), ('in_use_mb', 'after malloc_trim')):
            marks = ', '.join(f'cycle {cycle} {line[key]:.1f} MB'
                              for cycle, line in by_cycle.items())
            growth = ''
            if 100 in by_cycle and cycles in by_cycle and cycles > 100:
                growth = (f'; growth from cycle 100 to {cycles}: '
                          f'{by_cycle[cycles][key] - by_cycle[100][key]:+.1f} MB')
            print(f'   memory {label}: {marks}{growth}')
        print(f'   live participants: at most {max(line["participants"] for line in lines)} '
              f'while a system ran, at most {max(line["after_close"] for line in lines)} after '
              'it was closed')
    return ending == 'ended' and not failed and len(lines) == cycles


# -- part 2 ------------------------------------------------------------------------------------

def part_clis(count: int) -> bool:
    quiet = {'stdout': subprocess.DEVNULL, 'stderr': subprocess.DEVNULL}
    node = subprocess.Popen([sys.executable, '-m', 'turtle_traj', '--with-sim'], **quiet)
    try:
        subprocess.run([sys.executable, '-m', 'turtle_traj.cli', '--wait', '30', 'reset'],
                       check=True, timeout=60, **quiet)
        before = rss_mb(node.pid)
        failures, most, times = [], 0, []
        for number in range(1, count + 1):
            start = time.monotonic()
            cli = subprocess.Popen([sys.executable, '-m', 'turtle_traj.cli', 'params',
                                    'linear_speed'], stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True)
            while cli.poll() is None:
                try:
                    most = max(most, live_participants(cli.pid))
                except OSError:
                    pass
                if time.monotonic() - start > HANG_S:
                    print(f'  HANG: command-line process {number} ran {HANG_S:g} s; killed')
                    cli.kill()
                time.sleep(0.02)
            out, err = cli.communicate()
            times.append(time.monotonic() - start)
            if cli.returncode != 0 or 'linear_speed:' not in out:
                failures.append(f'#{number}: exit {cli.returncode}: {err.strip()[-200:]}')
        after = rss_mb(node.pid)
        alive = node.poll() is None
    finally:
        node.terminate()
        node.wait(timeout=15)
    print(f'2. {count} command-line processes (params linear_speed) against one node program: '
          f'{len(failures)} failed; median {statistics.median(times):.2f} s, longest '
          f'{max(times):.2f} s each')
    for failure in failures[:5]:
        print(f'   {failure}')
    print(f'   at most {most} live participant(s) seen in one of them; the node program '
          f'{"still running" if alive else "DIED"}, its memory {before:.1f} -> {after:.1f} MB')
    return not failures and alive and most <= 1


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--cycles', type=int, default=1000)
    parser.add_argument('--clis', type=int, default=200)
    parser.add_argument('--child-cycles', type=int, help=argparse.SUPPRESS)
    options = parser.parse_args()
    isolate('lifecycle')
    if options.child_cycles:
        run_cycles(options.child_cycles)
        return 0
    print(f'turtle_traj lifecycle soak (pid {os.getpid()}, ROS_DOMAIN_ID '
          f'{os.environ["ROS_DOMAIN_ID"]})')
    good = part_cycles(options.cycles)
    good = part_clis(options.clis) and good
    print('verdict: ' + ('no hang, no crash, no failure' if good else 'FAILED'))
    return 0 if good else 1


if __name__ == '__main__':
    sys.path.insert(0, str(Path(__file__).parent))
    sys.exit(main())
