"""A fleet across two hosts, in real time: turtles driven from both (needs root).

    sudo .venv/bin/python bench/fleet_two_hosts.py [--runs 2] [--loss 0]

Two network namespaces on a veth pair (`turtle_traj.testing.two_hosts`). Host a runs our
simulator with three turtles, turtle1's trajectory node and a pose log; host b runs the nodes of
turtle2 and turtle3 and the fleet coordinator, and the command line asks it to write "ROS 2"
(1 m) with the three. Printed per run: the coordinator's makespan, closest two turtles and
largest deviation, the wall time of the call, and the closest two turtles measured on host a
from every pose the simulator published.
"""

from __future__ import annotations

import argparse
import itertools
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / 'src'))

from turtle_traj.testing.domain import claim_domain_id  # noqa: E402
from turtle_traj.testing.two_hosts import TwoHosts  # noqa: E402

NODE = ('turtle_traj', '--ros-args', '-p', "turtle_name:=''", '-r')


def log_poses(out: Path, turtles: int) -> None:
    """Write `turtleK x y` for every pose of turtle1 to turtleK until SIGTERM (on host a)."""
    import signal

    import rclpy
    from turtlesim.msg import Pose

    from turtle_traj.rosutils.qos import TURTLE_TOPIC_QOS
    rclpy.init()
    node = rclpy.create_node('fleet_pose_log')
    with out.open('w') as file:
        for number in range(1, turtles + 1):
            node.create_subscription(
                Pose, f'/turtle{number}/pose', lambda pose, name=f'turtle{number}': file.write(
                    f'{name} {pose.x} {pose.y}\n'), TURTLE_TOPIC_QOS)
        signal.signal(signal.SIGTERM, lambda *_: rclpy.shutdown())
        try:
            rclpy.spin(node)
        except Exception:  # the context shut down by SIGTERM
            pass


def _closest(log: Path) -> float:
    """The least distance between two turtles' centres, from the poses the simulator sent,
    step by step (each turtle's n-th pose of the run together)."""
    tracks: dict[str, list[tuple[float, float]]] = {}
    for line in log.read_text().splitlines():
        name, x, y = line.split()
        tracks.setdefault(name, []).append((float(x), float(y)))
    count = min(len(track) for track in tracks.values())
    arrays = [np.array(track[:count]) for track in tracks.values()]
    return min(float(np.hypot(*(a - b).T).min()) for a, b in itertools.combinations(arrays, 2))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--runs', type=int, default=2)
    parser.add_argument('--loss', type=int, default=0, help='percent of packets dropped each way')
    parser.add_argument('--log', type=Path, help=argparse.SUPPRESS)  # the pose log, on host a
    options = parser.parse_args()
    if options.log:
        log_poses(options.log, 3)
        return 0
    with TwoHosts(claim_domain_id()) as hosts, tempfile.TemporaryDirectory() as folder:
        log = Path(folder) / 'poses.txt'
        hosts.run('a', 'turtle_traj.sim', '--turtles', '3')
        hosts.run('a', *NODE, '__ns:=/turtle1')
        hosts.run('b', *NODE, '__ns:=/turtle2')
        hosts.run('b', *NODE, '__ns:=/turtle3')
        hosts.run('b', 'turtle_traj.fleet')
        hosts.loss(options.loss)
        print(f'{"run":>3} {"makespan":>9} {"closest":>8} {"on host a":>9} {"dev mm":>7} '
              f'{"wall s":>7}')
        for run in range(1, options.runs + 1):
            logger = hosts._spawn('a', sys.executable, __file__, '--log', str(log))
            time.sleep(2.0)  # the log subscribes
            began = time.monotonic()
            done = hosts.call('b', 'write', 'ROS 2', '--height', '1', '--turtles', '3',
                              '--wait', '30', timeout_s=300.0)
            wall = time.monotonic() - began
            logger.terminate()
            logger.wait(timeout=15)
            said = done.stdout + done.stderr
            figures = re.search(r'makespan ([0-9.]+) s .* closest two turtles ([0-9.]+) m', said)
            deviations = [float(d) for d in re.findall(r'max deviation ([0-9.]+) m', said)]
            if done.returncode != 0 or figures is None:
                print(f'{run:3d} failed:\n{said}')
                continue
            print(f'{run:3d} {float(figures[1]):9.2f} {float(figures[2]):8.3f} '
                  f'{_closest(log):9.3f} {max(deviations) * 1000:7.2f} {wall:7.1f}', flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
