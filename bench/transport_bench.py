"""How late `turtle-traj play` sends a bag's commands: our Fast DDS profile as it is (UDP only)
against the same profile with Fast DDS's default transports (shared memory and UDP), as it was
until this bench, side by side, on a busy machine.

Each round is what tests/test_bags.py's real-time replay does: a fresh simulator program, an
observer of its poses in another process, and `turtle-traj play` of a recorded circle (158
commands at 62.5 Hz). Several rounds run at once on separate domains, beside busy loops, as in
`make test`. The player says how late its latest message was sent: with shared memory, a
publish() now and then waits 333 ms on a port's health check (eProsima/Fast-DDS#6535), and
open loop, the command before acts that much longer.

Run: .venv/bin/python bench/transport_bench.py [--rounds N] [--copies C] [--busy B]
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from load import busy_loops

ROOT = Path(__file__).resolve().parents[1]
OURS = ROOT / 'src' / 'turtle_traj' / 'rosutils' / 'fastdds.xml'
_OBSERVER = '''
import rclpy
from turtlesim.msg import Pose
from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
rclpy.init()
node = rclpy.create_node('transport_bench_observer')
node.create_subscription(Pose, 'turtle1/pose', lambda pose: None, TURTLE_TOPIC_QOS)
try:
    rclpy.spin(node)
except BaseException:
    pass
'''


def with_shared_memory(profile: Path) -> str:
    """`profile` without its transport settings: Fast DDS's shared memory and UDP."""
    text = re.sub(r'\s*<transport_descriptors>.*?</transport_descriptors>', '',
                  profile.read_text(), flags=re.S)
    text = re.sub(r'\s*<userTransports>.*?</userTransports>', '', text, flags=re.S)
    return re.sub(r'\s*<useBuiltinTransports>false</useBuiltinTransports>', '', text)


def _environ(profile: Path, domain: int) -> dict[str, str]:
    return {**os.environ, 'FASTRTPS_DEFAULT_PROFILES_FILE': str(profile),
            'ROS_DOMAIN_ID': str(domain), 'RMW_IMPLEMENTATION': 'rmw_fastrtps_cpp'}


def _stop(process: subprocess.Popen) -> None:
    process.send_signal(signal.SIGINT)
    try:
        process.wait(timeout=15)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()


def record(bag: Path, domain: int) -> None:
    """A circle drawn by the real programs, recorded for 2.5 s, as the test records it."""
    environ = _environ(OURS, domain)
    node = subprocess.Popen([sys.executable, '-m', 'turtle_traj', '--with-sim'], env=environ,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        subprocess.run([sys.executable, '-m', 'turtle_traj.cli', 'reset'], env=environ,
                       check=True, capture_output=True, timeout=60)
        recorder = subprocess.Popen([sys.executable, '-m', 'turtle_traj.cli', 'record',
                                     '--output', str(bag)], env=environ,
                                    stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        recorder.stdout.readline()
        subprocess.run([sys.executable, '-m', 'turtle_traj.cli', '--timeout', '2.5', 'draw',
                        'circle', '--size', '1.0'], env=environ, capture_output=True, timeout=60)
        _stop(recorder)
    finally:
        _stop(node)


def replay(bag: Path, profile: Path, domain: int) -> float:
    """One real-time replay into a fresh simulator; how late (ms) the player's latest send."""
    environ = _environ(profile, domain)
    sim = subprocess.Popen([sys.executable, '-m', 'turtle_traj.sim'], env=environ,
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    observer = None
    try:
        for line in sim.stderr:
            if 'Spawning turtle [turtle1]' in line:
                break
        observer = subprocess.Popen([sys.executable, '-c', _OBSERVER], env=environ)
        played = subprocess.run([sys.executable, '-m', 'turtle_traj.cli', 'play', str(bag)],
                                env=environ, capture_output=True, text=True, timeout=120)
        found = re.search(r'at most (\d+) ms after its time', played.stdout)
        if found is None:
            raise RuntimeError(played.stdout + played.stderr)
        return float(found.group(1))
    finally:
        for process in (observer, sim):
            if process is not None:
                _stop(process)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--rounds', type=int, default=24, help='replays per profile')
    parser.add_argument('--copies', type=int, default=4, help='replays at once')
    parser.add_argument('--busy', type=int, default=3, help='busy loops beside them')
    options = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix='turtle_traj_transport_'))
    shared = folder / 'shared_memory.xml'
    shared.write_text(with_shared_memory(OURS))
    base = 150 + os.getpid() % 40
    record(folder / 'circle', base)
    with busy_loops(options.busy):
        print(f'{options.rounds} real-time replays per profile, {options.copies} at once, '
              f'{options.busy} busy loops; how late the player sent its latest command:')
        for name, profile in (('with shared memory (before)', shared),
                              ('UDP only (now)', OURS)):
            domains = [base + 1 + i % options.copies for i in range(options.rounds)]
            with ThreadPoolExecutor(options.copies) as pool:
                late = sorted(pool.map(replay, [folder / 'circle'] * options.rounds,
                                       [profile] * options.rounds, domains))
            print(f'  {name:30s} median {late[len(late) // 2]:4.0f} ms, max {late[-1]:4.0f} ms,'
                  f' over 100 ms in {sum(x > 100 for x in late)} of {len(late)}', flush=True)


if __name__ == '__main__':
    main()
